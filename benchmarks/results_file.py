"""The data files of the results page: a benchmark's figures as JSON, with its command.

``docs/results/*.json`` hold the figures that ``docs/guide/results.md`` shows (rendered
at build time by ``docs/_ext/results_tables.py``).  A benchmark run with
``--write-results PATH`` writes its figures there through :func:`write_results`, with the
command that produced them (its own arguments, less the ones that name output files) and
when and where it ran.
"""

from __future__ import annotations

import datetime
import json
import math
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

__all__ = ["command", "measured", "write_results"]

ROOT = Path(__file__).resolve().parents[1]


def command(argv: list[str], outputs: tuple[str, ...] = ("--write-results",),
            env: str = "") -> str:
    """``[ENV] python benchmarks/<script> ARGS`` for the running script, less ``outputs``
    and their values."""
    args, skip = [], False
    for a in argv:
        if skip:
            skip = False
        elif a in outputs:
            skip = True
        elif not a.startswith(tuple(o + "=" for o in outputs)):
            args.append(a)
    script = Path(sys.argv[0]).resolve()
    try:
        name = script.relative_to(ROOT).as_posix()
    except ValueError:
        name = script.name
    return " ".join([*env.split(), "python", name, *args])


def measured(note: str = "") -> str:
    """When and where: the date, the commit (and whether the tree had changes), the cores."""
    def git(*args: str) -> str:
        try:
            return subprocess.run(["git", *args], cwd=ROOT, capture_output=True, text=True,
                                  check=True).stdout.strip()
        except (OSError, subprocess.CalledProcessError):
            return ""

    commit = git("rev-parse", "--short", "HEAD") or "unknown commit"
    dirty = " with uncommitted changes" if git("status", "--porcelain", "--untracked-files=no") \
        else ""
    day = datetime.datetime.now(datetime.UTC).date().isoformat()
    text = f"{day}, commit {commit}{dirty}, {os.cpu_count()} cores"
    return f"{text}; {note}" if note else text


def _plain(value: Any) -> Any:
    """JSON-ready: NaN and infinities become None, floats keep 4 decimals."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    if isinstance(value, float):
        return round(value, 4) if math.isfinite(value) else None
    return value


def write_results(path: Path, argv: list[str], note: str = "",
                  outputs: tuple[str, ...] = ("--write-results",), env: str = "",
                  **figures: Any) -> None:
    """Write ``figures`` to ``path`` as the data file of a results table (``env``: the
    environment the command needs, as ``PYTHONPATH=src:tests``)."""
    data = {"command": command(argv, outputs, env), "measured": measured(note), **figures}
    Path(path).write_text(json.dumps(_plain(data), indent=2) + "\n")
    print(f"figures written to {path}", file=sys.stderr)
