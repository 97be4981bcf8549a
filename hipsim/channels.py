"""Tables of channels: a LabVIEW TDMS or an HDF5 file read as the named columns of a CSV table, for every log reader.

An acquisition writes channels, not rows: LabVIEW a TDMS file of groups of
channels (npTDMS reads it, ``pip install 'hipsim[tdms]'``), other systems an
HDF5 file of datasets (h5py, ``pip install 'hipsim[hdf5]'``). :func:`read_channels`
turns one into a :class:`ChannelTable`: the column names a CSV of the same data
would have in its header, and its values, float64, so that a reader takes the
one as it takes the other, exactly (the same numbers give the same bits).

Which channels, by default: the file's one group (HDF5: the root's datasets,
or its one group) and its channels by their names. A table of columns is also
read: an HDF5 dataset of shape (N, C) with its C column names in the attribute
``columns``. Other layouts are named by a column map, ``NAME=GROUP/CHANNEL``
entries separated by commas (:func:`parse_channel_map`; an HDF5 dataset's path
inside the file, a column of a 2-D dataset as ``GROUP/DATASET[k]``), and a bare
``GROUP`` entry reads that group's channels by their names besides.

Units: a channel's own unit (TDMS: the property ``unit_string``, as LabVIEW
writes it; HDF5: the attribute ``unit_string``, ``units`` or ``unit``) is used
where present: a channel named without a unit gets the column name of its
unit (``tau_1`` in N·m → ``tau_1_Nmm``, its values × 1000; :data:`UNITS`); one
whose name states a unit must agree with it. A waveform's time (TDMS:
``wf_increment`` and ``wf_start_offset``) gives ``t_s`` when no channel does.

"Line" in a reader's message of such a file is the sample's number, from 1.
"""

from __future__ import annotations

import hashlib
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .exceptions import FileRowError, MissingDependencyError

__all__ = [
    "CHANNEL_SUFFIXES",
    "UNITS",
    "ChannelTable",
    "channel_kind",
    "parse_channel_map",
    "read_channels",
]

#: The files read as channels, by suffix (lower case): their format.
CHANNEL_SUFFIXES = {".tdms": "TDMS", ".h5": "HDF5", ".hdf5": "HDF5", ".hdf": "HDF5"}
#: A channel's unit (as spelled in its properties, spaces and case ignored) → (the column name's unit, factor).
UNITS = {
    "s": ("s", 1.0),
    "ms": ("s", 1e-3),
    "n": ("N", 1.0),
    "kn": ("N", 1e3),
    "nmm": ("Nmm", 1.0),
    "n·mm": ("Nmm", 1.0),
    "n*mm": ("Nmm", 1.0),
    "n.mm": ("Nmm", 1.0),
    "nm": ("Nmm", 1e3),
    "n·m": ("Nmm", 1e3),
    "n*m": ("Nmm", 1e3),
    "n.m": ("Nmm", 1e3),
    "a": ("A", 1.0),
    "deg": ("deg", 1.0),
    "°": ("deg", 1.0),
    "degree": ("deg", 1.0),
    "degrees": ("deg", 1.0),
    "rad": ("rad", 1.0),
    "mm": ("mm", 1.0),
    "m": ("mm", 1e3),
}
#: The units a column's name may end in (``tau_1_Nmm``).
_NAMED = {unit for unit, _ in UNITS.values()}
_UNIT_KEYS = ("unit_string", "units", "unit")
_TDMS_MAGIC = b"TDSm"
_HDF5_MAGIC = b"\x89HDF\r\n\x1a\n"
_COLUMN = re.compile(r"^(?P<path>.+?)\[(?P<k>\d+)\]$")


@dataclass(frozen=True, eq=False)
class ChannelTable:
    """A channel file as a table.

    Attributes:
        source: the file.
        names: the column names (as a CSV's header would have them), (C,).
        values: the samples, float64, (N, C).
        channels: where each column came from (``GROUP/CHANNEL``), (C,).
        sha256: the file's SHA-256 (hex).
        size: the file's size in [bytes].
    """

    source: str
    names: tuple[str, ...]
    values: np.ndarray
    channels: tuple[str, ...]
    sha256: str
    size: int


def channel_kind(path: str | Path) -> str | None:
    """ "TDMS" or "HDF5" for a file read as channels (by its suffix), else None."""
    return CHANNEL_SUFFIXES.get(Path(path).suffix.lower())


def parse_channel_map(text: str | Mapping[str, str] | None) -> tuple[dict[str, str], tuple[str, ...]]:
    """``"t_s=Timing/Time,Fe_N=Load/Fz,Rig"`` → ({column: GROUP/CHANNEL}, (groups read by their names,)).

    Raises:
        ValueError: an entry that is neither ``NAME=GROUP/CHANNEL`` nor a group, or a name given twice.
    """
    if text is None:
        return {}, ()
    if isinstance(text, Mapping):
        return {str(k): str(v) for k, v in text.items()}, ()
    named: dict[str, str] = {}
    groups: list[str] = []
    for entry in (e.strip() for e in str(text).split(",")):
        if not entry:
            continue
        if "=" not in entry:
            groups.append(entry)
            continue
        name, _, where = (part.strip() for part in entry.partition("="))
        if not name or not where.strip("/"):
            raise ValueError(f"'{entry}' is not NAME=GROUP/CHANNEL (e.g. Fe_N=Load/Fz)")
        if name in named:
            raise ValueError(f"column '{name}' is named twice")
        named[name] = where.strip("/")
    return named, tuple(groups)


def _name(
    channel: str, unit: str | None, source: str, error: type[FileRowError], convert: bool = False
) -> tuple[str, float]:
    """A column's name and the factor its values take, from the name and the channel's own unit (module docstring).

    A name without a unit gets the channel's; a name stating one must agree with the channel's, or, with
    ``convert`` (a column named by the map), be of its kind (the values converted: N·m into a column in N·mm).
    """
    stated = channel.rsplit("_", 1)[1] if "_" in channel else None
    known = UNITS.get(re.sub(r"\s+", "", unit).lower()) if unit else None
    if stated in _NAMED:
        if known is None or known == (stated, 1.0):
            return channel, 1.0
        if convert and known[0] == stated:
            return channel, known[1]
        raise error(
            f"its unit is '{unit}', its name says {stated}: rename it, or drop the unit", source=source, column=channel
        )
    if known is None:
        return channel, 1.0
    return f"{channel}_{known[0]}", known[1]


def _identity(path: str, source: str, what: str, error: type[FileRowError]) -> tuple[bytes, str, int]:
    """(first bytes, SHA-256, size) of the file, read once, or a one-line error naming it."""
    digest, size, head = hashlib.sha256(), 0, b""
    try:
        with open(path, "rb") as stream:
            for block in iter(lambda: stream.read(1 << 22), b""):
                if not head:
                    head = block[:8]
                digest.update(block)
                size += len(block)
    except FileNotFoundError:
        raise error(f"no such {what}", source=source) from None
    except IsADirectoryError:
        raise error(f"is a folder, not a {what}", source=source) from None
    except OSError as failure:
        raise error(f"cannot read ({failure.strerror})", source=source) from None
    return head, digest.hexdigest(), size


def read_channels(
    path: str | Path,
    columns: str | Mapping[str, str] | None = None,
    what: str = "log file",
    error: type[FileRowError] = FileRowError,
) -> ChannelTable:
    """A TDMS or HDF5 file's channels as a table (module docstring).

    Args:
        path: the file (``.tdms``; ``.h5``, ``.hdf5``, ``.hdf``).
        columns: the column map (:func:`parse_channel_map`), or None for the file's one group by its names.
        what: the kind of file, for messages.
        error: the error class raised, called as ``error(message, source=path, column=name)``.

    Raises:
        error: not such a file, a named channel or group the file lacks, several groups and no map, channels of
            different lengths, a dataset of another shape, a channel that is not numbers, a unit that disagrees.
        MissingDependencyError: npTDMS or h5py not installed (the extra to install named).
    """
    source = str(path)
    kind = channel_kind(path)
    if kind is None:
        raise error("not a TDMS (.tdms) or HDF5 (.h5, .hdf5) file by its name", source=source)
    try:
        named, groups = parse_channel_map(columns)
    except ValueError as failure:
        raise error(f"--columns: {failure}", source=source) from None
    head, sha, size = _identity(source, source, what, error)
    if kind == "TDMS":
        if not head.startswith(_TDMS_MAGIC):
            raise error("not a TDMS file (it does not start with a TDMS segment)", source=source)
        channels = _tdms(source, error)
    else:
        if not head.startswith(_HDF5_MAGIC):
            raise error("not an HDF5 file (it does not start with the HDF5 signature)", source=source)
        channels = _hdf5(source, error)
    picked = _pick(channels, named, groups, source, error)
    lengths = {where: values.size for where, (values, _, _) in picked.items()}
    if not picked:
        raise error("no channels of numbers", source=source)
    longest = max(lengths, key=lengths.__getitem__)
    for where, n in lengths.items():
        if n != lengths[longest]:
            raise error(
                f"channel '{where}' has {n} values, '{longest}' {lengths[longest]}: a table's channels are one length",
                source=source,
            )
    names: list[str] = []
    factors: list[float] = []
    wheres: list[str] = []
    for where, (_, unit, name) in picked.items():
        column, factor = (name, 1.0) if name is not None else _name(where.rsplit("/", 1)[-1], unit, source, error)
        if column in names:
            raise error(f"two channels give column '{column}' ({wheres[names.index(column)]}, {where})", source=source)
        names.append(column)
        factors.append(factor)
        wheres.append(where)
    n = lengths[longest]
    table = np.empty((n, len(names)))
    for c, where in enumerate(wheres):
        values = picked[where][0]
        table[:, c] = values if factors[c] == 1.0 else values * factors[c]
    if "t_s" not in names:
        time = _waveform_time(channels, wheres, n)
        if time is not None:
            names.append("t_s")
            wheres.append("waveform time (wf_start_offset + k·wf_increment)")
            table = np.column_stack([table, time])
    return ChannelTable(source, tuple(names), table, tuple(wheres), sha, size)


#: A channel as found: GROUP/CHANNEL → (values or a reason it is not numbers, its unit or None, properties).
_Found = dict[str, tuple[np.ndarray | str, str | None, dict]]


def _unit(properties: Mapping) -> str | None:
    for key in _UNIT_KEYS:
        value = properties.get(key)
        if isinstance(value, bytes):
            value = value.decode("utf-8", "replace")
        if isinstance(value, str) and value.strip():
            return value.strip()
    return None


def _numbers(values, where: str) -> np.ndarray | str:
    array = np.asarray(values)
    if array.dtype.kind not in "biuf":
        return f"channel '{where}' holds {array.dtype} values, not numbers"
    return array.astype(np.float64, copy=False)


def _tdms(source: str, error: type[FileRowError]) -> _Found:
    try:
        import nptdms
    except ImportError:
        raise MissingDependencyError("nptdms", "tdms", "reading a TDMS file") from None
    try:
        file = nptdms.TdmsFile.read(source)
    except Exception as failure:  # npTDMS's own errors for a damaged file
        raise error(f"not a readable TDMS file ({failure})", source=source) from None
    found: _Found = {}
    for group in file.groups():
        for channel in group.channels():
            where = f"{group.name}/{channel.name}"
            properties = dict(channel.properties)
            found[where] = (_numbers(channel[:], where), _unit(properties), properties)
    return found


def _hdf5(source: str, error: type[FileRowError]) -> _Found:
    try:
        import h5py
    except ImportError:
        raise MissingDependencyError("h5py", "hdf5", "reading an HDF5 file") from None
    found: _Found = {}
    try:
        with h5py.File(source, "r") as file:

            def visit(name, item):
                if not isinstance(item, h5py.Dataset):
                    return
                attrs = dict(item.attrs)
                group = name.rsplit("/", 1)[0] if "/" in name else ""
                if item.ndim == 2 and "columns" in attrs:
                    labels = [v.decode() if isinstance(v, bytes) else str(v) for v in np.ravel(attrs["columns"])]
                    if len(labels) != item.shape[1]:
                        found[name] = (
                            f"dataset '{name}' has {item.shape[1]} columns, its attribute 'columns' "
                            f"{len(labels)} names",
                            None,
                            attrs,
                        )
                        return
                    data = item[()]
                    for k, label in enumerate(labels):
                        where = f"{group}/{label}" if group else label
                        found[where] = (_numbers(data[:, k], f"{name}[{k}]"), None, attrs | {"_column": k})
                        found[f"{name}[{k}]"] = found[where]
                    return
                if item.ndim != 1:
                    found[name] = (
                        f"dataset '{name}' has shape {item.shape}: a channel is one column (N,), a table "
                        "(N, C) has its column names in the attribute 'columns' (or name its columns with --columns "
                        f"NAME={name}[k])",
                        None,
                        attrs,
                    )
                    if item.ndim == 2:  # its columns by index, for a map that names them
                        data = item[()]
                        for k in range(item.shape[1]):
                            found[f"{name}[{k}]"] = (_numbers(data[:, k], f"{name}[{k}]"), _unit(attrs), attrs)
                    return
                found[name] = (_numbers(item[()], name), _unit(attrs), attrs)

            file.visititems(visit)
    except OSError as failure:
        raise error(f"not a readable HDF5 file ({failure})", source=source) from None
    return found


def _group_of(where: str) -> str:
    return where.rsplit("/", 1)[0] if "/" in where else ""


def _pick(found: _Found, named: dict[str, str], groups: tuple[str, ...], source: str, error) -> dict:
    """The channels to read: GROUP/CHANNEL → (values, unit, column name or None for the channel's own)."""
    # A table's columns are found twice (by label and as DATASET[k]): by default, by label only.
    plain = {w: v for w, v in found.items() if not _COLUMN.match(w)}
    present = sorted({_group_of(w) for w in plain})
    shown = ", ".join(repr(g or "/") for g in present) or "none"
    picked: dict = {}
    if not named and not groups:
        if len(present) != 1:
            raise error(
                f"has {len(present)} groups of channels ({shown}): name the channels with --columns "
                "NAME=GROUP/CHANNEL,… or read one group by its names with --columns GROUP",
                source=source,
            )
        groups = (present[0],)
    for group in groups:
        if group.strip("/") not in present:
            raise error(f"no group '{group}' (the file's: {shown})", source=source)
        for where, value in plain.items():
            if _group_of(where) == group.strip("/"):
                if isinstance(value[0], str):
                    continue  # a channel of text or of another shape, not asked for by name: ignored, as CSV columns are
                picked[where] = (value[0], value[1], None)
    for name, where in named.items():
        if where not in found:
            group = _group_of(where)
            inside = sorted(w.rsplit("/", 1)[-1] for w in plain if _group_of(w) == group)
            hint = f"group '{group}' has {', '.join(inside[:12])}" if inside else f"the file's groups: {shown}"
            raise error(f"no channel '{where}' for column '{name}' ({hint})", source=source, column=name)
        values, unit, _ = found[where]
        if isinstance(values, str):
            raise error(values, source=source, column=name)
        if where in picked and picked[where][2] is not None:
            raise error(f"channel '{where}' is named for two columns ('{picked[where][2]}', '{name}')", source=source)
        picked.pop(where, None)
        factor_name, factor = _name(name, unit, source, error, convert=True)
        picked[where] = (values * factor if factor != 1.0 else values, None, factor_name)
    for where, value in plain.items():  # a wrongly shaped dataset in a group read by its names is refused, not skipped
        if isinstance(value[0], str) and "shape" in value[0] and _group_of(where) in {g.strip("/") for g in groups}:
            raise error(value[0], source=source)
    return picked


def _waveform_time(found: _Found, wheres: list[str], n: int) -> np.ndarray | None:
    """t = wf_start_offset + k·wf_increment when the channels read share a waveform's timing, else None."""
    timings = set()
    for where in wheres:
        properties = found[where][2] if where in found else {}
        if "wf_increment" not in properties:
            return None
        timings.add((float(properties.get("wf_start_offset", 0.0)), float(properties["wf_increment"])))
    if len(timings) != 1:
        return None
    start, step = timings.pop()
    if not step > 0:
        return None
    return start + np.arange(n) * step
