"""The compiled loops over points and samples: one pass over a piece of the motion adds its share to every point's sums.

Per point w (tangent basis t1, t2) and sample k, with Ω_k the cup's body
angular velocity and u = (Ω·t1, Ω·t2) its tangential part: the head slides
over w at |v| = r·|u| (v = −r·Ω × w), and v·e = −r·Ω·(w × e) for a tangent e,
so the work along e is r·Σ c·|u·m| with m = w × e and c = p·dt. Both passes
sum over samples in the inner loop, so a piece of any length costs one read of
its (N, 3) arrays per point, and the sums are all a point keeps: constant
memory however long the motion.
"""

from __future__ import annotations

import math

from ..physics.laws import jit

__all__ = ["COARSE_ANGLES", "direction_pass", "first_pass"]

#: The fixed directions of :func:`first_pass` in [rad] from t1.
COARSE_ANGLES = (0.0, math.pi / 4, math.pi / 2, 3 * math.pi / 4)


@jit(depends_on=())
def first_pass(t1, t2, w, omega, n, load_dt, dt, coef, s, s_loaded, work, tensor, coarse):  # pragma: no cover
    """Add a piece's sliding, work, work tensor and work along fixed directions to each point's sums.

    Args:
        t1, t2, w: tangent basis and point, (P, 3) each.
        omega: Ω in [rad/s], (N, 3); n: contact centre, (N, 3).
        load_dt: F·dt in [N·s], (N,); dt: quadrature weights in [s], (N,).
        coef: 3/(2π·r²) in [1/mm²], the pressure per newton at the contact centre.
        s, s_loaded, work: Σ|u|·dt, the same while loaded, Σ c·|u| (in [rad], [rad], [N·rad/mm²]), (P,), added to.
        tensor: Σ c·u·uᵀ/|u| as (xx, xy, yy), (P, 3), added to; coarse: Σ c·|u·m_d| along the
            directions m_d at 0°, 45°, 90° and 135° from t1 (:data:`COARSE_ANGLES`), (P, 4), added to.
    """
    P, N = w.shape[0], omega.shape[0]
    half = math.sqrt(0.5)
    for i in range(P):
        ax, ay, az = t1[i, 0], t1[i, 1], t1[i, 2]
        bx, by, bz = t2[i, 0], t2[i, 1], t2[i, 2]
        wx, wy, wz = w[i, 0], w[i, 1], w[i, 2]
        si = 0.0
        sl = 0.0
        wi = 0.0
        txx = 0.0
        txy = 0.0
        tyy = 0.0
        c0 = 0.0
        c45 = 0.0
        c90 = 0.0
        c135 = 0.0
        for k in range(N):
            ox, oy, oz = omega[k, 0], omega[k, 1], omega[k, 2]
            ux = ox * ax + oy * ay + oz * az
            uy = ox * bx + oy * by + oz * bz
            speed = math.sqrt(ux * ux + uy * uy)
            si += speed * dt[k]
            cos = wx * n[k, 0] + wy * n[k, 1] + wz * n[k, 2]
            if cos <= 0.0:
                continue
            sl += speed * dt[k]
            c = coef * load_dt[k] * cos
            wi += c * speed
            if speed > 0.0:
                g = c / speed
                txx += g * ux * ux
                txy += g * ux * uy
                tyy += g * uy * uy
            c0 += c * abs(ux)
            c45 += c * abs(ux + uy)
            c90 += c * abs(uy)
            c135 += c * abs(uy - ux)
        s[i] += si
        s_loaded[i] += sl
        work[i] += wi
        tensor[i, 0] += txx
        tensor[i, 1] += txy
        tensor[i, 2] += tyy
        coarse[i, 0] += c0
        coarse[i, 1] += c45 * half
        coarse[i, 2] += c90
        coarse[i, 3] += c135 * half


@jit(depends_on=())
def direction_pass(t1, t2, w, omega, n, load_dt, coef, active, m, pull, along, across):  # pragma: no cover
    """Add a piece's work along m and across it, and the fixed-point pull Σ c·sign(u·m)·u, for the active points.

    Args:
        t1, t2, w, omega, n, load_dt, coef: as :func:`first_pass`.
        active: which points to do, (P,) booleans.
        m: each point's direction in (t1, t2) coordinates, unit, (P, 2).
        pull: Σ c·sign(u·m)·u, (P, 2), added to.
        along, across: Σ c·|u·m| and Σ c·|u·m⊥| (m⊥ = m turned by 90°), (P,), added to.
    """
    P, N = w.shape[0], omega.shape[0]
    for i in range(P):
        if not active[i]:
            continue
        ax, ay, az = t1[i, 0], t1[i, 1], t1[i, 2]
        bx, by, bz = t2[i, 0], t2[i, 1], t2[i, 2]
        wx, wy, wz = w[i, 0], w[i, 1], w[i, 2]
        mx, my = m[i, 0], m[i, 1]
        px = 0.0
        py = 0.0
        fa = 0.0
        fc = 0.0
        for k in range(N):
            cos = wx * n[k, 0] + wy * n[k, 1] + wz * n[k, 2]
            if cos <= 0.0:
                continue
            ox, oy, oz = omega[k, 0], omega[k, 1], omega[k, 2]
            ux = ox * ax + oy * ay + oz * az
            uy = ox * bx + oy * by + oz * bz
            c = coef * load_dt[k] * cos
            g = ux * mx + uy * my
            h = uy * mx - ux * my
            fa += c * abs(g)
            fc += c * abs(h)
            if g > 0.0:
                px += c * ux
                py += c * uy
            elif g < 0.0:
                px -= c * ux
                py -= c * uy
        pull[i, 0] += px
        pull[i, 1] += py
        along[i] += fa
        across[i] += fc
