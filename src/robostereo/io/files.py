"""Writing results: CSV tables, PLY point clouds, image folders.

Every writer is atomic: it writes a temporary file beside the target and renames it
into place only when the whole file is written, so a failure never leaves a partial
output file.  A command with several outputs is all or nothing too:
:func:`check_outputs` refuses, before any work, an output path that is a folder, lies
in a missing or unwritable folder, or names an input or another output;
:func:`atomic_outputs` gives every output a temporary name and renames them into place
only when all are written.  Temporary names are ``.NAME.PID-XXXXXXXX.part`` beside
the target ``NAME``, made by process ``PID``: a command that is killed outright
(SIGKILL, a power cut) cannot remove its own, so :func:`remove_stale_parts` removes
those whose process is gone, on every later write of the same target (and
:func:`check_outputs` before any work; a batch for its whole folder).  Images are
read by :mod:`robostereo.io.images`, cameras by :mod:`robostereo.io.cameras`,
calibrations by :mod:`robostereo.io.calibration_files`, a folder's YAML file by
:mod:`robostereo.io.folder_yaml`.
"""

from __future__ import annotations

import contextlib
import math
import os
import re
import shutil
import tempfile
import time
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robostereo.errors import InputError

__all__ = [
    "atomic_outputs",
    "atomic_path",
    "check_outputs",
    "remove_live_parts",
    "remove_stale_parts",
    "signals_held",
    "write_csv",
    "write_image_folder",
    "write_ply",
]

PathLike = str | os.PathLike[str]

#: names that moved to :mod:`robostereo.io.folder_yaml` (0.2), importable here for a release
_MOVED_NAMES = ("folder_yaml_text", "plain_values", "read_folder_yaml")


def __getattr__(name: str) -> Any:
    if name in _MOVED_NAMES:
        import warnings

        from robostereo.io import folder_yaml

        warnings.warn(f"robostereo.io.files.{name} moved to robostereo.io.folder_yaml; the "
                      "old path goes in the next release", DeprecationWarning, stacklevel=2)
        return getattr(folder_yaml, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


_PART = re.compile(r"\.(\d+)-[A-Za-z0-9_]+\.part$")
_OLD_PART = re.compile(r"\.[A-Za-z0-9_]{8}\.part$")
OLD_PART_SECONDS = 3600.0
"""Age after which a temporary file of the former naming (no process id) is stale."""
#: this process's temporary outputs (for remove_live_parts) -> the output each becomes
_live: dict[Path, Path] = {}


def _alive(pid: int) -> bool:
    if pid <= 0:
        return False
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # another user's process: alive
        return True
    return True


def remove_stale_parts(folder: PathLike, names: Iterable[str] | None = None) -> list[Path]:
    """Remove the temporary outputs of processes that are gone.

    Parameters
    ----------
    folder : path
        Where the outputs are written.
    names : iterable of str, optional
        Target file or folder names whose temporaries are meant; default all.

    Returns
    -------
    list of Path
        What was removed.

    Notes
    -----
    A temporary output ``.NAME.PID-XXXXXXXX.part`` (a file, or a folder for an image
    folder) is stale when no process ``PID`` runs on this machine; one of the former
    naming ``.NAME.XXXXXXXX.part`` when it is older than :data:`OLD_PART_SECONDS`.
    A nested one, ``..NAME.PID-XXXXXXXX.part.PID-YYYYYYYY.part`` (what a writer's own
    atomic file inside a command's temporary file was named before :func:`atomic_path`
    wrote such files in place), counts as NAME's too.

    Output folders shared by machines (a network file system with a batch on several
    hosts) should not be written by two runs at once anyway: a process id of another
    machine is taken as gone.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (d / ".m.csv.999999999-abcdefgh.part").write_text("half")
    >>> [p.name for p in remove_stale_parts(d, ["m.csv"])]
    ['.m.csv.999999999-abcdefgh.part']
    """
    d = Path(folder)
    # NAME's temporaries, nested ones (a temporary's own temporary) included
    wanted = None if names is None else tuple(f"{n.lstrip('.')}." for n in names)
    removed: list[Path] = []
    try:
        entries = list(os.scandir(d))
    except OSError:
        return removed
    now = time.time()
    for e in entries:
        name = e.name
        if not (name.startswith(".") and name.endswith(".part")):
            continue
        if wanted is not None and not name.lstrip(".").startswith(wanted):
            continue
        m = _PART.search(name)
        try:
            if m is not None:
                stale = not _alive(int(m.group(1)))
            elif _OLD_PART.search(name):
                stale = now - e.stat(follow_symlinks=False).st_mtime > OLD_PART_SECONDS
            else:
                stale = False
            if not stale:
                continue
            if e.is_dir(follow_symlinks=False):
                shutil.rmtree(e.path)
            else:
                os.unlink(e.path)
            removed.append(Path(e.path))
        except OSError:
            continue
    return removed


def remove_live_parts() -> None:
    """Remove this process's temporary outputs now (a worker ended by a signal, which
    leaves no time to unwind); they would be stale once the process is gone anyway."""
    for p in list(_live):
        with contextlib.suppress(OSError):
            if p.is_dir() and not p.is_symlink():
                shutil.rmtree(p)
            else:
                p.unlink()
        _live.pop(p, None)


def _part_prefix(target: Path) -> str:
    return f".{target.name}.{os.getpid()}-"


@contextlib.contextmanager
def atomic_path(path: PathLike) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; rename it to ``path`` on success.

    On an exception the temporary file is removed and ``path`` is left untouched.  A
    ``path`` that is already one of this process's temporary outputs (a writer such as
    :func:`write_csv` given a command's file from :func:`atomic_outputs`) is written in
    place: the command renames it, and an error names the output it stands for.
    """
    target = Path(path)
    if target.is_dir():
        raise InputError(f"{target}: is a folder, not an output file name")
    if target in _live:
        try:
            yield target
        except OSError as e:
            raise InputError(f"{_live[target]}: cannot write output ({_why(e)})") from None
        return
    with atomic_outputs({"path": target}) as tmp:
        yield tmp["path"]


def write_image_folder(directory: PathLike, images: Mapping[str, NDArray[Any]],
                       texts: Mapping[str, str],
                       blobs: Mapping[str, bytes] | None = None) -> Path:
    """Write a folder of 8-bit PNG images and text files, all or nothing.

    The files are written into a temporary folder beside `directory`, which is then
    renamed to it; on an error nothing is left behind.

    Parameters
    ----------
    directory : path
        The folder to make: it must not exist or be empty, its parent must exist.
    images : mapping of str to ndarray
        File name to a uint8 image, written as PNG.
    texts : mapping of str to str
        File name to its UTF-8 text.
    blobs : mapping of str to bytes, optional
        Relative path (``/``-separated, subfolders made) to its bytes.

    Returns
    -------
    Path
        `directory`.
    """
    import cv2

    target = Path(directory)
    parent = target.parent if str(target.parent) else Path(".")
    if not parent.is_dir():
        raise InputError(f"{target}: parent folder {parent} does not exist")
    if target.exists() and (not target.is_dir() or any(target.iterdir())):
        raise InputError(f"{target}: exists and is not an empty folder")
    remove_stale_parts(parent, [target.name])
    try:
        tmp = Path(tempfile.mkdtemp(prefix=_part_prefix(target), suffix=".part", dir=parent))
    except OSError as e:
        raise InputError(f"{target}: cannot write in {parent} ({_why(e)})") from None
    _live[tmp] = target
    try:
        name = ""
        for name, img in images.items():
            ok, buf = cv2.imencode(".png", np.asarray(img, dtype=np.uint8))
            if not ok:  # pragma: no cover - OpenCV always encodes uint8 grey
                raise InputError(f"{target / name}: cannot encode PNG")
            (tmp / name).write_bytes(buf.tobytes())
        for name, text in texts.items():
            (tmp / name).write_text(text, encoding="utf-8")
        for name, data in (blobs or {}).items():
            (tmp / name).parent.mkdir(parents=True, exist_ok=True)
            (tmp / name).write_bytes(data)
        name = ""
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o777 & ~umask)
        if target.is_dir():
            target.rmdir()
        os.replace(tmp, target)
    except OSError as e:  # a full disk: name the folder asked for, not the temporary one
        raise InputError(f"{target / name if name else target}: cannot write output "
                         f"({_why(e)})") from None
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)
        _live.pop(tmp, None)
    return target


def _why(e: OSError) -> str:
    return f"{e.__class__.__name__}: {e.strerror}" if e.strerror else e.__class__.__name__


def _same_file(a: Path, b: Path) -> bool:
    try:
        if a.exists() and b.exists():
            return os.path.samefile(a, b)
    except OSError:
        pass
    return a.resolve() == b.resolve()


def check_outputs(
    outputs: Mapping[str, PathLike | None], *, inputs: Iterable[PathLike | None] = ()
) -> dict[str, Path]:
    """Check a command's output paths before any work is done.

    Parameters
    ----------
    outputs : mapping
        Option name (e.g. ``"-o"``, ``"--ply"``) to path; None entries are left out.
    inputs : iterable of path
        The command's input files (None entries are left out).

    Returns
    -------
    dict
        Option name to :class:`~pathlib.Path`, the outputs to write.

    Raises
    ------
    InputError
        An output that is an existing folder or other non-file, lies in a missing or
        unwritable folder, is the same file as an input, or the same as another output.

    Notes
    -----
    Stale temporary files of these outputs (:func:`remove_stale_parts`) are removed when
    each is written (:func:`atomic_outputs`, :func:`atomic_path`), not here.

    Examples
    --------
    >>> check_outputs({"-o": "m.csv", "--edges": "./m.csv"})
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: --edges m.csv is the same file as -o m.csv; give each ...
    """
    outs = {k: Path(v) for k, v in outputs.items() if v is not None}
    ins = [Path(v) for v in inputs if v is not None]
    seen: list[tuple[str, Path]] = []
    for opt, p in outs.items():
        if p.is_dir():
            raise InputError(f"{opt} {p}: is a folder; give an output file name")
        if p.exists() and not p.is_file():
            raise InputError(f"{opt} {p}: exists and is not a regular file")
        parent = p.parent if str(p.parent) else Path(".")
        if not parent.is_dir():
            raise InputError(f"{opt} {p}: output folder {parent} does not exist")
        if not os.access(parent, os.W_OK | os.X_OK):
            raise InputError(f"{opt} {p}: output folder {parent} is not writable")
        for q in ins:
            if _same_file(p, q):
                raise InputError(f"{opt} {p} is an input of the command; refusing to "
                                 "overwrite it")
        for other, q in seen:
            if _same_file(p, q):
                raise InputError(f"{opt} {p} is the same file as {other} {q}; give each "
                                 "output its own name")
        seen.append((opt, p))
    return outs


@contextlib.contextmanager
def signals_held() -> Iterator[None]:
    """SIGINT and SIGTERM held back on this thread while the block runs, delivered on
    leaving it (POSIX; elsewhere a plain block).

    For the steps that must not be cut in two by an interrupt: renaming a command's
    outputs into place (all or none), starting worker threads.  Threads started inside
    inherit the held mask, so the signals go to the main thread.

    >>> with signals_held():
    ...     pass
    """
    import signal

    if not hasattr(signal, "pthread_sigmask"):  # pragma: no cover - not POSIX
        yield
        return
    held = {signal.SIGINT, signal.SIGTERM}
    old = signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


@contextlib.contextmanager
def atomic_outputs(outputs: Mapping[str, Path]) -> Iterator[dict[str, Path]]:
    """Temporary paths for all of a command's outputs, renamed into place together.

    Yields a mapping like `outputs` of temporary files beside the targets.  When the
    block completes, every temporary file is renamed to its target; when it raises,
    every temporary file is removed and no target is touched.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> with atomic_outputs({"a": d / "a.txt", "b": d / "b.txt"}) as tmp:
    ...     _ = tmp["a"].write_text("A"); _ = tmp["b"].write_text("B")
    >>> sorted(p.name for p in d.iterdir())
    ['a.txt', 'b.txt']
    """
    with contextlib.ExitStack() as stack:
        temps: dict[str, Path] = {}
        for key, target in outputs.items():
            temps[key] = stack.enter_context(_temp_beside(Path(target)))
        yield temps
        with signals_held():  # an interrupt between two renames: some outputs, not all
            for key, target in outputs.items():
                try:
                    os.replace(temps[key], target)
                except OSError as e:
                    raise InputError(f"{target}: cannot write output ({_why(e)})") from None


@contextlib.contextmanager
def _temp_beside(target: Path) -> Iterator[Path]:
    """A temporary file beside `target` with the umask's permissions, removed on exit
    unless renamed."""
    parent = target.parent if str(target.parent) else Path(".")
    if not parent.is_dir():
        raise InputError(f"{target}: output folder {parent} does not exist")
    remove_stale_parts(parent, [target.name])
    try:
        fd, tmp = tempfile.mkstemp(prefix=_part_prefix(target), suffix=".part", dir=parent)
    except OSError as e:
        raise InputError(f"{target}: cannot write in {parent} ({_why(e)})") from None
    os.close(fd)
    tmp_path = Path(tmp)
    _live[tmp_path] = target
    umask = os.umask(0)
    os.umask(umask)
    try:
        os.chmod(tmp_path, 0o666 & ~umask)
        yield tmp_path
    except OSError as e:
        raise InputError(f"{target}: cannot write output ({_why(e)})") from None
    finally:
        if tmp_path.exists():
            tmp_path.unlink()
        _live.pop(tmp_path, None)


def _column_text(values: NDArray[Any]) -> list[str]:
    """Format a column: floats with 6 significant digits, NaN and inf as empty cells."""
    if values.dtype.kind == "f":
        return ["" if not math.isfinite(v) else f"{v:.6g}" for v in values.tolist()]
    return [str(v) for v in values.tolist()]


def write_csv(path: PathLike, columns: Mapping[str, NDArray[Any]]) -> Path:
    """Write equal-length columns as a CSV file with a header (NaN as empty cells).

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "m.csv"
    >>> _ = write_csv(p, {"row": np.array([3]), "x": np.array([1.25]), "d": np.array([np.nan])})
    >>> p.read_text().splitlines()
    ['row,x,d', '3,1.25,']
    """
    names = list(columns)
    arrays = [np.asarray(columns[n]).reshape(-1) for n in names]
    lengths = {a.shape[0] for a in arrays}
    if len(lengths) > 1:
        raise ValueError(f"columns differ in length: {[a.shape[0] for a in arrays]}")
    for n in names:
        if "," in n or "\n" in n:
            raise ValueError(f"column name {n!r} cannot be written as CSV")
    lines = [",".join(names), *map(",".join, zip(*map(_column_text, arrays), strict=True))]
    with atomic_path(path) as tmp:
        tmp.write_text("\n".join(lines) + "\n")
    return Path(path)


def write_ply(
    path: PathLike, xyz: NDArray[np.floating], colors: NDArray[np.uint8] | None = None,
    *, fields: Mapping[str, NDArray[Any]] | None = None,
) -> Path:
    """Write 3-D points (``(N, 3)``, millimetres) as a binary PLY point cloud (trimesh).

    Points with a NaN coordinate are left out; with none left the file is a valid PLY
    with zero vertices.  `fields` adds per-point vertex properties (name to an ``(N,)``
    array: integers as ``int``, anything else as ``float``), e.g. a bound and a
    confidence; it cannot be combined with `colors`.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "empty.ply"
    >>> b"element vertex 0" in write_ply(p, np.full((2, 3), np.nan)).read_bytes()
    True
    >>> q = write_ply(p, np.zeros((2, 3)), fields={"bound_mm": np.array([0.5, 1.0])})
    >>> b"property float bound_mm" in q.read_bytes()
    True
    """
    import trimesh

    pts = np.asarray(xyz, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise InputError(f"3-D points must have shape (N, 3), got {pts.shape}")
    good = np.isfinite(pts).all(axis=1)
    if fields is not None:
        if colors is not None:
            raise InputError("write_ply: give colors or fields, not both")
        data_f = _ply_with_fields(pts[good], {k: np.asarray(v) for k, v in fields.items()},
                                  good)
        with atomic_path(path) as tmp:
            tmp.write_bytes(data_f)
        return Path(path)
    if not good.any():  # trimesh cannot export an empty cloud
        header = ["ply", "format binary_little_endian 1.0", "comment robostereo: no points",
                  "element vertex 0", *(f"property float {c}" for c in "xyz")]
        if colors is not None:
            header += [f"property uchar {c}" for c in ("red", "green", "blue", "alpha")]
        data: Any = ("\n".join([*header, "end_header"]) + "\n").encode()
    else:
        cloud = trimesh.PointCloud(
            pts[good], colors=None if colors is None else np.asarray(colors)[good]
        )
        data = cloud.export(file_type="ply")
    with atomic_path(path) as tmp:
        tmp.write_bytes(data if isinstance(data, bytes) else str(data).encode())
    return Path(path)


def _ply_with_fields(pts: NDArray[np.float64], fields: Mapping[str, NDArray[Any]],
                     good: NDArray[np.bool_]) -> bytes:
    """Binary little-endian PLY of points `pts` (M, 3) with the `fields` (N,) at `good`."""
    cols: list[tuple[str, str]] = [("x", "<f4"), ("y", "<f4"), ("z", "<f4")]
    for name, v in fields.items():
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
            raise InputError(f"write_ply: field name {name!r} must be a plain identifier")
        if v.shape != good.shape:
            raise InputError(f"write_ply: field {name!r} must have shape {good.shape}, got "
                             f"{v.shape}")
        is_int = np.issubdtype(v.dtype, np.integer) or np.issubdtype(v.dtype, np.bool_)
        cols.append((name, "<i4" if is_int else "<f4"))
    rec = np.zeros(len(pts), dtype=cols)
    for k, c in enumerate("xyz"):
        rec[c] = pts[:, k]
    for name, v in fields.items():
        rec[name] = v[good]
    kind = {"<f4": "float", "<i4": "int"}
    header = ["ply", "format binary_little_endian 1.0", f"element vertex {len(pts)}",
              *(f"property {kind[t]} {n}" for n, t in cols), "end_header"]
    return ("\n".join(header) + "\n").encode() + rec.tobytes()
