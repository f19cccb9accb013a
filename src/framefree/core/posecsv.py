"""Reading pose CSV files: the format check, with one clear message for every common mistake, and
plausibility checks that catch wrong units and quaternion orders.

A pose file is UTF-8 text, one sample per line, 8 comma-separated numbers
``t, x, y, z, qw, qx, qy, qz`` (time [s], position [m], unit quaternion scalar first). A first
row that names exactly these columns (``t,x,y,z,qw,qx,qy,qz``, or ``...,qx,qy,qz,qw`` for a
scalar-last file) is a header and is read as one; any other header needs ``skip_header``.
Headers are told apart by what they say (:func:`header_kind`): framefree's multi-tracker CSV
names its columns ``t,NAME.x,NAME.y,...``.
Whatever bytes a file holds, :func:`read_pose_csv` either returns an array or raises
:class:`~framefree.errors.TrajectoryError` naming the file, the row and the problem.
"""

from __future__ import annotations

import math
import re
import warnings
from pathlib import Path

import numpy as np

from ..errors import FramefreeWarning, TrajectoryError

__all__ = [
    "QUAT_ORDERS",
    "UNITS",
    "PlausibilityWarning",
    "header_kind",
    "known_non_pose",
    "plausibility_problems",
    "read_pose_csv",
    "warn_if_implausible",
]

#: quaternion column orders a file may have
QUAT_ORDERS = ("wxyz", "xyzw")
#: position units a file may have, and their size in metres
UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001}

#: 95 % of a recording's samples faster than this [m/s] is not a hand: a whole-arm stroke cut to its
#: motion reaches 10.3 m/s at its 95th percentile (a Machete person's uppercut, cut at a fifth of
#: its peak speed), and positions read in the wrong unit move 100 or 1000 times faster than they did
MAX_HAND_SPEED = 20.0
#: positions farther than this from the origin [m] are not a tracking volume
MAX_POSITION = 100.0
#: positions of a hand in a room lie within this of the origin [m] (to tell the unit they came in)
ROOM = 10.0

_MAGIC = (
    (b"\x89PNG", "a PNG image"),
    (b"\xff\xd8\xff", "a JPEG image"),
    (b"%PDF", "a PDF document"),
    (b"PK\x03\x04", "a ZIP archive (an .xlsx spreadsheet? export it as CSV)"),
    (b"\x1f\x8b", "a gzip-compressed file (decompress it first)"),
    (b"\x93NUMPY", "a NumPy .npy file"),
)
_SEPARATORS = ((";", "semicolons"), ("\t", "tabs"), ("|", "vertical bars"))


class PlausibilityWarning(FramefreeWarning):
    """A pose file reads without error but its numbers look wrong for a hand-held tracker.

    Attributes
    ----------
    source : str
        The file.
    problem : str
        What looks wrong and which option fixes it.
    """

    def __init__(self, source: str, problem: str) -> None:
        self.source = source
        self.problem = problem
        super().__init__(f"{source}: {problem}")


def known_non_pose(head: bytes) -> str | None:
    """What a file is when its first bytes say it is no pose recording (``"a PNG image"``, ...),
    else None.

    Parameters
    ----------
    head : bytes
        The file's first bytes (8 are enough).
    """
    return next((what for magic, what in _MAGIC if head.startswith(magic)), None)


def _decode(raw: bytes, path: Path) -> str:
    what = known_non_pose(raw[:8])
    if what is not None:
        raise TrajectoryError(f"this is {what}, not a pose CSV file", path)
    if b"\x00" in raw:
        raise TrajectoryError("binary data (NUL bytes), not a pose CSV text file", path)
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise TrajectoryError(
            f"not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset {exc.start}); "
            "a pose CSV is plain text",
            path,
        ) from None


def _read_text(path: Path) -> str:
    if path.is_dir():
        raise TrajectoryError("is a folder, not a pose CSV file", path)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise TrajectoryError(f"cannot read file ({exc.strerror or exc})", path) from None
    return _decode(raw, path)


def _is_number(item: str) -> bool:
    try:
        float(item)
    except ValueError:
        return False
    return True


def _wrong_separator(line: str) -> str | None:
    """Name of the separator that splits ``line`` into 8 numbers, if not a comma."""
    for sep, name in _SEPARATORS:
        fields = line.split(sep)
        if len(fields) == 8 and all(_is_number(f.replace(",", ".")) for f in fields):
            return name
    fields = line.split()
    if len(fields) == 8 and all(_is_number(f) for f in fields):
        return "spaces"
    return None


def _parse_row(line: str, path: Path, lineno: int) -> list[float]:
    fields = line.split(",")
    if len(fields) != 8:
        sep = _wrong_separator(line)
        if sep is not None:
            raise TrajectoryError(
                f"columns are separated by {sep}; framefree reads comma-separated files "
                "(8 columns t,x,y,z,qw,qx,qy,qz, '.' as decimal point)",
                path,
                lineno,
            )
        raise TrajectoryError(
            f"expected 8 comma-separated columns (t, x, y, z and a quaternion), found {len(fields)}",
            path,
            lineno,
        )
    values = []
    for col, item in enumerate(fields, start=1):
        try:
            v = float(item)
        except ValueError:
            raise TrajectoryError(
                f"column {col}: {item.strip()[:40]!r} is not a number", path, lineno
            ) from None
        if not math.isfinite(v):
            raise TrajectoryError(f"column {col}: value {item.strip()} is not finite", path, lineno)
        values.append(v)
    return values


def _looks_like_header(line: str) -> bool:
    """Column names: 4 to 12 short fields, none a number, each starting with a letter."""
    fields = [f.strip().strip("'\"") for f in re.split(r"[,;\t|]", line)]
    return 4 <= len(fields) <= 12 and all(
        f[:1].isalpha() and len(f) <= 24 and not _is_number(f) for f in fields
    )


#: the column names of a single-tracker header, per quaternion order
SINGLE_HEADERS = {
    "wxyz": ("t", "x", "y", "z", "qw", "qx", "qy", "qz"),
    "xyzw": ("t", "x", "y", "z", "qx", "qy", "qz", "qw"),
}


def _header_cells(line: str) -> list[str]:
    return [c.strip().strip("'\"").lower() for c in line.split(",")]


def header_kind(line: str) -> str | None:
    """What a file's first line says it is.

    Parameters
    ----------
    line : str
        The first non-empty line of a CSV file.

    Returns
    -------
    {"wxyz", "xyzw", "multi"} or None
        ``"wxyz"`` / ``"xyzw"``: a single-tracker header naming exactly the 8 pose columns (in
        that quaternion order); ``"multi"``: a multi-tracker header (``t`` then ``NAME.x``-style
        columns); None: anything else (samples, or a header of other names).
    """
    cells = _header_cells(line)
    for order, names in SINGLE_HEADERS.items():
        if tuple(cells) == names:
            return order
    if len(cells) > 1 and cells[0] == "t" and all("." in c for c in cells[1:]):
        return "multi"
    return None


def _drop_header(lines: list[tuple[int, str]], path: Path, quat_order: str,
                 skip_header: bool) -> list[tuple[int, str]]:
    """The sample lines: a single-tracker header is read by its names, ``skip_header`` drops any
    other first line that is not numbers, another header-like first line is one clear error."""
    if not lines:
        return lines
    kind = header_kind(lines[0][1])
    if kind in SINGLE_HEADERS:
        if kind != quat_order:
            order = ",".join(SINGLE_HEADERS[kind][4:])
            raise TrajectoryError(
                f"the header names the quaternion columns {order} ({kind}) but the quaternion "
                f"order given is {quat_order}; use --quat-order {kind} (Python: "
                f"quat_order={kind!r})", path, lines[0][0])
        return lines[1:]
    if skip_header:  # a first line of numbers is a sample, never dropped
        first = lines[0][1].split(",")
        return lines if all(_is_number(f) for f in first) else lines[1:]
    if _looks_like_header(lines[0][1]):
        raise TrajectoryError(
            f"{lines[0][1][:60]!r} looks like a header row; drop the header line "
            "(command line: --skip-header; Python: skip_header=True)",
            path,
            lines[0][0],
        )
    return lines


def read_pose_csv(
    path: str | Path, quat_order: str = "wxyz", *, skip_header: bool = False, units: str = "m"
) -> np.ndarray:
    """Read an 8-column pose CSV into an (N, 8) array ``t, x, y, z, qw, qx, qy, qz``.

    Only the file format is checked here (text, separator, column count, numbers, finiteness);
    see :meth:`Trajectory.from_csv <framefree.Trajectory.from_csv>` for the full validation.

    Parameters
    ----------
    path : str or Path
        CSV file, comma separated; a first row ``t,x,y,z,qw,qx,qy,qz`` (or ``...,qx,qy,qz,qw``)
        is read as the header it is; any other header needs ``skip_header``.
    quat_order : {"wxyz", "xyzw"}
        Order of the quaternion columns in the file; the result is always scalar first.
    skip_header : bool
        Ignore a header row of any names (e.g. ``time,px,py,...``) in the first non-empty line;
        a first line of numbers is a sample and is kept, so the flag is safe on files without one.
    units : {"m", "cm", "mm"}
        Unit of the position columns in the file; the result is always in metres.

    Returns
    -------
    ndarray, shape (N, 8)
        Time [s], position [m], quaternion ``(w, x, y, z)`` (as stored, not normalized).

    Raises
    ------
    TrajectoryError
        Naming the file, the 1-based row and the problem.
    """
    if quat_order not in QUAT_ORDERS:
        raise ValueError(f"quat_order must be one of {QUAT_ORDERS}, got {quat_order!r}")
    if units not in UNITS:
        raise ValueError(f"units must be one of {tuple(UNITS)}, got {units!r}")
    path = Path(path)
    lines = [(k, s.strip()) for k, s in enumerate(_read_text(path).splitlines(), start=1)]
    lines = _drop_header([(k, s) for k, s in lines if s], path, quat_order, skip_header)
    if not lines:
        raise TrajectoryError("the file is empty (no samples)", path)
    data = np.asarray([_parse_row(s, path, k) for k, s in lines], dtype=np.float64)
    if quat_order == "xyzw":
        data = data[:, [0, 1, 2, 3, 7, 4, 5, 6]]
    data[:, 1:4] *= UNITS[units]
    return data


def _unit_problem(data: np.ndarray) -> str | None:
    dt = np.diff(data[:, 0])
    ok = dt > 0
    if ok.sum() < 2:
        return None
    speed = np.linalg.norm(np.diff(data[:, 1:4], axis=0), axis=1)[ok] / dt[ok]
    fast = float(np.percentile(speed, 95))
    far = float(np.abs(data[:, 1:4]).max())
    if fast <= MAX_HAND_SPEED and far <= MAX_POSITION:
        return None
    # the units in which these numbers are a hand in a room; both where a slow, small motion in
    # millimetres reads like a fast, large one in centimetres
    names = {"mm": "millimetres", "cm": "centimetres"}
    units = [u for u in names if fast * UNITS[u] <= MAX_HAND_SPEED and far * UNITS[u] <= ROOM]
    units = units or ["mm"]
    return (
        f"positions look like {' or '.join(names[u] for u in units)} (95 % of speeds below "
        f"{fast:.3g} m/s, positions up to {far:.3g} m; the fastest real strokes reach about "
        f"10 m/s); use {' or '.join(f'--units {u}' for u in units)} (Python: units="
        f"{' or '.join(repr(u) for u in units)})"
    )


def _order_problem(raw_quaternions: np.ndarray) -> str | None:
    """Sign jumps explained by a scalar kept non-negative in the *last* column, not the first."""
    q = raw_quaternions / np.linalg.norm(raw_quaternions, axis=1, keepdims=True)
    jumps = np.flatnonzero(np.einsum("ij,ij->i", q[1:], q[:-1]) < 0)
    if jumps.size == 0:
        return None
    around = np.concatenate([jumps, jumps + 1])

    def kept_non_negative(col: int) -> bool:
        return bool(q[:, col].min() >= 0 and np.abs(q[around, col]).max() < 0.2)

    if kept_non_negative(3) and not kept_non_negative(0):
        return (
            "the quaternion's last column is never negative and its sign jumps where that column "
            "crosses zero: the file looks scalar-last (x, y, z, w); use --quat-order xyzw "
            "(Python: quat_order='xyzw')"
        )
    return None


def plausibility_problems(data: np.ndarray, quat_order: str = "wxyz") -> list[str]:
    """What looks wrong for a hand-held tracker in pose data as read from a file.

    Parameters
    ----------
    data : ndarray, shape (N, 8)
        ``t, x, y, z`` [s, m] and the quaternion, scalar first (as :func:`read_pose_csv` returns).
    quat_order : {"wxyz", "xyzw"}
        The order the file was read with (the scalar-last check only applies to ``"wxyz"``).

    Returns
    -------
    list of str
        One sentence per problem, each naming the option that fixes it; empty if none.

    Notes
    -----
    Two heuristics. *Units*: 95 % of the sample-to-sample speeds above 20 m/s, or positions
    farther than 100 m from the origin. *Quaternion order*: many tracking SDKs keep the scalar
    non-negative, so the quaternion's sign jumps where the scalar crosses zero; when the last
    column is never negative and the sign jumps happen where it is near zero (and the first column
    is not), the file is scalar-last. A scalar-last file without such jumps is not detected.
    """
    problems = [_unit_problem(data)]
    if quat_order == "wxyz":
        problems.append(_order_problem(data[:, 4:8]))
    return [p for p in problems if p is not None]


def warn_if_implausible(data: np.ndarray, source: str | Path, quat_order: str = "wxyz") -> None:
    """Issue a :class:`PlausibilityWarning` for each of :func:`plausibility_problems`."""
    for problem in plausibility_problems(data, quat_order):
        warnings.warn(PlausibilityWarning(str(source), problem), stacklevel=3)
