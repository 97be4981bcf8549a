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

import numpy as np

from ..physics.laws import jit

__all__ = ["COARSE_ANGLES", "direction_pass", "exact_direction", "first_pass"]

#: The fixed directions of :func:`first_pass` in [rad] from t1.
COARSE_ANGLES = (0.0, math.pi / 4, math.pi / 2, 3 * math.pi / 4)


@jit(depends_on=())
def first_pass(t1, t2, w, omega, n, load_dt, dt, coef, s, s_loaded, work, tensor, coarse, rough):  # pragma: no cover
    """Add a piece's sliding, work, work tensor and work along fixed directions to each point's sums.

    Args:
        t1, t2, w: tangent basis and point, (P, 3) each.
        omega: Ω in [rad/s], (N, 3); n: contact centre, (N, 3).
        load_dt: F·dt in [N·s], (N,); dt: quadrature weights in [s], (N,).
        coef: 3/(2π·r²) in [1/mm²], the pressure per newton at the contact centre.
        s, s_loaded, work: Σ|u|·dt, the same while loaded, Σ c·|u| (in [rad], [rad], [N·rad/mm²]), (P,), added to.
        tensor: Σ c·u·uᵀ/|u| as (xx, xy, yy), (P, 3), added to; coarse: Σ c·|u·m_d| along the
            directions m_d at 0°, 45°, 90° and 135° from t1 (:data:`COARSE_ANGLES`), (P, 4), added to.
        rough: whether to sum ``tensor`` and ``coarse`` (the iteration's start and check; the exact search needs neither).
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
            if not rough:
                continue
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


@jit(depends_on=())
def _run_order(key, K, order, spare, bounds):  # pragma: no cover
    """``order[:K]``: the indices of ``key[:K]`` sorted, by merging its monotone runs (a natural merge sort).

    A point's kinks, taken in time order, turn smoothly: a few long runs up or down, so the sort costs
    O(K·log runs), not quicksort's O(K·log K), and the sort was most of the exact search's cost.
    ``spare`` (K integers) and ``bounds`` (K + 1 integers) are scratch.
    """
    runs = 0
    start = 0
    while start < K:
        end = start + 1
        if end < K and key[end] < key[start]:
            while end < K and key[end] <= key[end - 1]:
                end += 1
            for j in range(start, end):  # a run down, reversed
                order[j] = end - 1 - (j - start)
        else:
            while end < K and key[end] >= key[end - 1]:
                end += 1
            for j in range(start, end):
                order[j] = j
        bounds[runs] = start
        runs += 1
        start = end
    bounds[runs] = K
    in_spare = False
    while runs > 1:
        src = spare if in_spare else order
        dst = order if in_spare else spare
        merged = 0
        r = 0
        while r < runs:
            lo = bounds[r]
            mid = bounds[r + 1]
            hi = bounds[r + 2] if r + 2 <= runs else mid
            i, j, o = lo, mid, lo
            while i < mid and j < hi:
                if key[src[j]] < key[src[i]]:
                    dst[o] = src[j]
                    j += 1
                else:
                    dst[o] = src[i]
                    i += 1
                o += 1
            while i < mid:
                dst[o] = src[i]
                i += 1
                o += 1
            while j < hi:
                dst[o] = src[j]
                j += 1
                o += 1
            bounds[merged] = lo
            merged += 1
            r += 2
        bounds[merged] = K
        runs = merged
        in_spare = not in_spare
    if in_spare:
        for j in range(K):
            order[j] = spare[j]


@jit(depends_on=())
def exact_direction(t1, t2, w, omega, n, load_dt, coef, active, theta, along, across):  # pragma: no cover
    """The direction of most work at each active point, exactly: the global maximum of f(θ) = Σ a_k·|cos(θ − φ_k)|.

    With u_k = |u_k|·(cos φ_k, sin φ_k), φ_k ∈ [0, π), and a_k = c_k·|u_k|, f is A·cos θ + B·sin θ between
    consecutive kinks β_k = φ_k ± π/2 ∈ [0, π), where one term's sign flips; every kink is convex, so the maximum
    lies inside an arc: the one where f' goes from ≥ 0 to ≤ 0, and there f = √(A² + B²) along (A, B). The kinks
    are sorted once per point (by −cos β, which rises with β on [0, π): no angle is computed) and walked round one
    period, A and B updated at each, without a trigonometric call. Needs the whole motion in memory:
    O(N log N) a point.

    Args:
        t1, t2, w, omega, n, load_dt, coef: as :func:`first_pass`, over the whole motion.
        active: which points to do, (P,) booleans.
        theta: the direction m of most work, its angle from t1 in [rad] in [0, π), (P,), written.
        along, across: Σ c·|u·m| and Σ c·|u·m⊥| at it, (P,), written.
    """
    P, N = w.shape[0], omega.shape[0]
    cx = np.empty(N)  # a_k·cos φ_k
    cy = np.empty(N)  # a_k·sin φ_k (≥ 0)
    kx = np.empty(N)  # the kink's direction (cos β_k, sin β_k), sin β_k ≥ 0
    ky = np.empty(N)
    key = np.empty(N)
    sign = np.empty(N)
    order = np.empty(N, dtype=np.int64)
    spare = np.empty(N, dtype=np.int64)
    bounds = np.empty(N + 1, dtype=np.int64)
    for i in range(P):
        if not active[i]:
            continue
        K = 0
        for k in range(N):
            cos = w[i, 0] * n[k, 0] + w[i, 1] * n[k, 1] + w[i, 2] * n[k, 2]
            if cos <= 0.0:
                continue
            ux = omega[k, 0] * t1[i, 0] + omega[k, 1] * t1[i, 1] + omega[k, 2] * t1[i, 2]
            uy = omega[k, 0] * t2[i, 0] + omega[k, 1] * t2[i, 1] + omega[k, 2] * t2[i, 2]
            if ux == 0.0 and uy == 0.0:
                continue
            if uy < 0.0 or (uy == 0.0 and ux < 0.0):  # φ into [0, π)
                ux, uy = -ux, -uy
            c = coef * load_dt[k] * cos
            cx[K], cy[K] = c * ux, c * uy
            speed = math.sqrt(ux * ux + uy * uy)
            # β = φ + π/2 when φ < π/2 (direction (−sin φ, cos φ)), else φ − π/2 (direction (sin φ, −cos φ)).
            if ux > 0.0:
                kx[K], ky[K] = -uy / speed, ux / speed
            else:
                kx[K], ky[K] = uy / speed, -ux / speed
            if ky[K] <= 0.0:  # β = 0 exactly: the direction (1, 0)
                kx[K], ky[K] = 1.0, 0.0
            key[K] = -kx[K]
            K += 1
        if K == 0:
            theta[i], along[i], across[i] = 0.0, 0.0, 0.0
            continue
        _run_order(key, K, order, spare, bounds)
        # Start in the middle of the widest gap between kinks (round π: the last to the first's opposite), where
        # every sign is clear; 1 − cos of a gap rises with its width on [0, π].
        g = 0
        widest = -1.0
        for j in range(K):
            a, b = order[j], order[(j + 1) % K]
            turn = -1.0 if j + 1 == K else 1.0
            gap = 1.0 - turn * (kx[a] * kx[b] + ky[a] * ky[b])
            if gap > widest:
                widest, g = gap, j
        a, b = order[g], order[(g + 1) % K]
        turn = -1.0 if g + 1 == K else 1.0
        sx, sy = kx[a] + turn * kx[b], ky[a] + turn * ky[b]
        if widest >= 2.0 or sx * sx + sy * sy < 1e-24:  # a gap of π: all the kinks at one angle
            sx, sy = -ky[a], kx[a]
        A = 0.0
        B = 0.0
        for j in range(K):
            s = 1.0 if sx * cx[j] + sy * cy[j] >= 0.0 else -1.0
            sign[j] = s
            A += s * cx[j]
            B += s * cy[j]
        best = -1.0
        best_x, best_y = 1.0, 0.0
        low_x, low_y = kx[a], ky[a]
        for step in range(K):  # arcs from kink g round one period; past π a kink's direction is negated
            j = g + step
            nxt = order[(j + 1) % K]
            flip = -1.0 if j + 1 >= K else 1.0
            high_x, high_y = flip * kx[nxt], flip * ky[nxt]
            rising = -A * low_y + B * low_x  # f' at the arc's start and end
            falling = -A * high_y + B * high_x
            if rising >= 0.0 and falling <= 0.0 and (high_x != low_x or high_y != low_y):
                value = math.sqrt(A * A + B * B)
                if value > best:
                    best, best_x, best_y = value, A, B
            value = A * low_x + B * low_y  # a kink, for safety
            if value > best:
                best, best_x, best_y = value, low_x, low_y
            A -= 2.0 * sign[nxt] * cx[nxt]
            B -= 2.0 * sign[nxt] * cy[nxt]
            sign[nxt] = -sign[nxt]
            low_x, low_y = high_x, high_y
        size = math.sqrt(best_x * best_x + best_y * best_y)
        mx, my = best_x / size, best_y / size
        fa = 0.0
        fc = 0.0
        for j in range(K):
            fa += abs(cx[j] * mx + cy[j] * my)
            fc += abs(cy[j] * mx - cx[j] * my)
        theta[i] = math.atan2(my, mx) % math.pi
        along[i] = fa
        across[i] = fc
