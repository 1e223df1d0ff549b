"""Batch runs over many stereo inputs, on the local cores or a Dask cluster, resumable.

:func:`run_batch` processes every input folder of a directory -- pair folders, capture
folders of two views and of N (:mod:`robostereo.batch_inputs`) -- each by
:func:`~robostereo.batch_inputs.process_input`, which writes, per input ``NAME``,
``OUT/NAME.csv`` (the matched points) [and ``OUT/NAME.ply``] and then ``OUT/NAME.json``
(its summary row and timings), all atomically; the JSON file marks the input as
finished, so a second run skips it (resume).  The marker records what shaped the
outputs (:func:`~robostereo.batch_inputs.run_signature`), and a rerun whose options or
input files differ **redoes** that input (reported as *redone*), replacing its outputs;
an old ``NAME.ply`` that the new options no longer ask for is removed.  A failed input
is reported and the others go on; it leaves no output, so the next run retries it.
Empty subfolders are not inputs and are left out.  Local worker processes die with the
main process, however it ends (Ctrl-C, SIGTERM, SIGKILL; :mod:`robostereo.batch_workers`).
At the end ``OUT/summary.csv`` lists every input (its columns hold no timings, so runs
on different machines give identical files).  The work runs in a local process pool,
or with ``scheduler`` on an existing ``dask.distributed`` cluster, whose workers must
see the same file system.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from robostereo.batch_inputs import (
    SUMMARY_COLUMNS,
    BatchOptions,
    PathLike,
    find_inputs,
    process_input,
    run_signature,
)
from robostereo.batch_workers import start_worker, stop_workers
from robostereo.errors import InputError
from robostereo.matcher.parallel import n_threads

__all__ = [
    "BatchOptions",
    "BatchReport",
    "run_batch",
]


@dataclass(frozen=True)
class BatchReport:
    """What :func:`run_batch` did.

    Attributes
    ----------
    rows : tuple of dict
        One summary row per input (see
        :data:`~robostereo.batch_inputs.SUMMARY_COLUMNS`), sorted by name.
    processed, skipped, failed : tuple of str
        Inputs run now, inputs already finished (resumed), inputs that failed.
    errors : dict
        Input name to its one-line error, for the failed ones.
    redone : tuple of str
        Processed inputs that had finished with other options or input files.
    summary : Path
        ``OUT/summary.csv``.
    seconds : float
        Wall time of the run.
    """

    rows: tuple[dict[str, Any], ...]
    processed: tuple[str, ...]
    skipped: tuple[str, ...]
    failed: tuple[str, ...]
    summary: Path
    seconds: float
    errors: dict[str, str] = field(default_factory=dict)
    redone: tuple[str, ...] = ()


def _finished(
    out: Path, name: str, signature: dict[str, Any] | None = None
) -> dict[str, Any] | None:
    """The stored row of a finished input, or None (missing, partial or failed, or
    finished with another signature than `signature`)."""
    j = out / f"{name}.json"
    if not j.is_file():
        return None
    try:
        row = json.loads(j.read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError):
        return None
    if not isinstance(row, dict) or row.get("status") != "ok":
        return None
    if not (out / str(row.get("output", ""))).is_file():
        return None
    if signature is not None and row.get("signature") != signature:
        return None
    sig = row.get("signature")
    opts = sig.get("options") if isinstance(sig, dict) else None
    if isinstance(opts, dict) and opts.get("ply") and row.get("points_3d") and not (
            out / f"{name}.ply").is_file():
        return None  # its PLY file was removed
    return row


def _was_finished(out: Path, name: str) -> bool:
    """Whether `name` has a finished marker of any signature."""
    return _finished(out, name) is not None


def _write_summary(path: Path, rows: list[dict[str, Any]]) -> None:
    from robostereo.io import write_csv

    cols = {c: np.array([r.get(c, "") for r in rows], dtype=object) for c in SUMMARY_COLUMNS}
    write_csv(path, cols)


ProgressCallback = Callable[[int, int, dict[str, Any]], None]


def run_batch(
    input_dir: PathLike,
    out_dir: PathLike,
    *,
    options: BatchOptions | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: ProgressCallback | None = None,
) -> BatchReport:
    """Run the pipeline over every input folder of `input_dir`, skipping finished ones.

    Parameters
    ----------
    input_dir : path
        A folder of input folders (or one input folder), see
        :func:`~robostereo.batch_inputs.find_inputs`.
    out_dir : path
        Output folder (created if missing).
    options : BatchOptions, optional
    scheduler : str, optional
        Address of a ``dask.distributed`` scheduler (``tcp://host:8786``); default: a
        local process pool.
    workers : int, optional
        Local processes (default: the number of cores); 1 runs in this process.
    progress : callable, optional
        ``progress(done, total, row)`` after each input (finished ones count at once).

    Returns
    -------
    BatchReport

    Raises
    ------
    InputError
        No input folders, an output folder that cannot be made or is an input folder, a
        scheduler that cannot be reached.

    Notes
    -----
    1. List the inputs; those with a finished ``NAME.json`` (and its CSV) are skipped.
    2. Submit the others to the pool or the cluster
       (:func:`~robostereo.batch_inputs.process_input`) and collect them as they finish;
       a failure is a row with ``status = error``.
    3. Write ``summary.csv`` over all inputs (sorted by name).  An interrupted run
       leaves every finished input's files in place for the next run.
    """
    t0 = time.perf_counter()
    opts = options or BatchOptions()
    out = Path(out_dir)
    inputs = find_inputs(input_dir, exclude=out)  # no output folder unless there is input
    if any(p.resolve() == out.resolve() for p in inputs):
        raise InputError(f"{out}: the output folder is an input folder; give another one")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise InputError(f"{out}: cannot create output folder ({e.__class__.__name__})") from None
    if not os.access(out, os.W_OK | os.X_OK):
        raise InputError(f"{out}: output folder is not writable")
    from robostereo.io import remove_stale_parts

    remove_stale_parts(out)  # what killed workers of an earlier run left half-written
    names = [p.name for p in inputs]
    if len(set(names)) != len(names):
        raise InputError(f"{input_dir}: input folder names must be unique")
    rows: dict[str, dict[str, Any]] = {}
    skipped: list[str] = []
    todo: list[Path] = []
    redone: list[str] = []
    for p in inputs:
        row = _finished(out, p.name, run_signature(p, opts))
        if row is None:
            todo.append(p)
            if _was_finished(out, p.name):
                redone.append(p.name)
        else:
            rows[p.name] = row
            skipped.append(p.name)
    total = len(inputs)
    done = len(skipped)
    if progress is not None:
        for name in skipped:
            progress(done, total, rows[name])

    def collect(row: dict[str, Any]) -> None:
        nonlocal done
        rows[row["input"]] = row
        done += 1
        if progress is not None:
            progress(done, total, row)

    if todo:
        if scheduler is not None:
            _run_dask(todo, out, opts, scheduler, collect)
        elif (workers or os.cpu_count() or 1) <= 1 or len(todo) == 1:
            for p in todo:
                collect(process_input(p, out, opts))
        else:
            import multiprocessing

            n = min(workers or os.cpu_count() or 1, len(todo))
            ctx = multiprocessing.get_context("spawn")  # safe beside threads (dask, BLAS)
            # the cores shared out: n processes of n_threads() threads each would make
            # n times too many (a ROBOSTEREO_THREADS the user set is kept)
            share = max(1, n_threads() // n)
            with ProcessPoolExecutor(max_workers=n, mp_context=ctx, initializer=start_worker,
                                     initargs=(os.getpid(), share)) as pool:
                futs = [pool.submit(process_input, str(p), str(out), opts) for p in todo]
                try:
                    for f in as_completed(futs):
                        collect(f.result())
                except BaseException:
                    for f in futs:
                        f.cancel()
                    stop_workers(pool)
                    raise
    ordered = [rows[n] for n in sorted(rows)]
    summary = out / "summary.csv"
    _write_summary(summary, ordered)
    failed = tuple(r["input"] for r in ordered if r["status"] != "ok")
    return BatchReport(
        rows=tuple(ordered), processed=tuple(sorted(p.name for p in todo)),
        skipped=tuple(sorted(skipped)), failed=failed, summary=summary,
        seconds=time.perf_counter() - t0,
        errors={r["input"]: r["error"] for r in ordered if r["status"] != "ok"},
        redone=tuple(sorted(redone)),
    )  # fmt: skip


def _run_dask(
    todo: list[Path], out: Path, opts: BatchOptions, scheduler: str,
    collect: Callable[[dict[str, Any]], None],
) -> None:
    try:
        from distributed import Client
        from distributed import as_completed as dask_completed
    except ImportError:
        raise InputError(
            "--scheduler needs dask.distributed: pip install 'robostereo[distributed]'"
        ) from None
    try:
        client = Client(scheduler, timeout="10s")
    except Exception as e:  # OSError, TimeoutError, ValueError for a malformed address...
        why = str(e).splitlines()[0] if str(e) else ""
        raise InputError(
            f"cannot reach the Dask scheduler at {scheduler!r} ({e.__class__.__name__}"
            f"{': ' + why if why else ''})"
        ) from None
    try:
        futs = [
            client.submit(process_input, str(p), str(out), opts, pure=False,
                          key=f"robostereo-{p.name}-{time.time_ns()}")
            for p in todo
        ]  # fmt: skip
        try:
            for f in dask_completed(futs):
                collect(f.result())
        except BaseException:
            client.cancel(futs)
            raise
    finally:
        client.close()
