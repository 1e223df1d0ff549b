"""The kernels compile where nothing can be written: a read-only install, no HOME.

The package is copied to a temporary folder that a private mount namespace makes
read-only (``unshare -m`` and a read-only bind mount: unlike ``chmod``, it stops root
too), HOME points where no folder can be made, and the temporary folder is read-only
as well, so neither numba's places nor robostereo's fallback can be written.  Before
:mod:`robostereo.matcher.jit`, ``robostereo --help`` died at import with numba's
``cannot cache function '_pattern': no locator available``.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from robostereo.matcher import jit

SRC = Path(__file__).resolve().parents[2] / "src" / "robostereo"

SCRIPT = """
set -e
mount --bind -o ro "$RO" "$RO"
mount -o remount,bind,ro "$RO"
if touch "$RO/probe" 2>/dev/null; then echo "still writable" >&2; exit 99; fi
cd "$RO"
exec env -u XDG_CACHE_HOME -u NUMBA_CACHE_DIR HOME=/proc/nonexistent TMPDIR="$RO" \
    PYTHONPATH="$RO" PYTHONDONTWRITEBYTECODE=1 "$PY" -c "$CODE"
"""

CODE = """
import sys
import numpy as np
from robostereo.cli import main
from robostereo.matcher.edges import detect_edges
img = np.zeros((24, 24), np.uint8); img[:, 12:] = 100
print("edges", len(detect_edges(img, threshold=8.0, bit_depth=8)))
sys.argv = ["robostereo", "--help"]
main()
"""


def _can_unshare() -> bool:
    if not shutil.which("unshare"):
        return False
    r = subprocess.run(["unshare", "-m", "true"], capture_output=True)
    return r.returncode == 0


@pytest.mark.skipif(not _can_unshare(), reason="needs unshare -m (root or user namespaces)")
def test_read_only_install_and_home_still_imports_and_matches(tmp_path: Path) -> None:
    ro = tmp_path / "ro"
    ro.mkdir()
    shutil.copytree(SRC, ro / "robostereo",
                    ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "*.nbi", "*.nbc"))
    env = {"RO": str(ro), "PY": sys.executable, "CODE": CODE, "PATH": "/usr/bin:/bin"}
    r = subprocess.run(["unshare", "-m", "sh", "-c", SCRIPT], env=env,
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr[-2000:]
    assert "cannot cache" not in r.stderr
    assert "usage: robostereo" in r.stdout
    n = int(r.stdout.split("edges", 1)[1].split()[0])
    assert n > 0
    assert not (ro / "robostereo" / "matcher" / "__pycache__").exists()


def test_kernel_falls_back_to_no_cache_when_nothing_is_writable(
        monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[bool] = []
    real = jit.nb.njit

    def njit(**kw: object) -> object:
        calls.append(bool(kw["cache"]))
        if kw["cache"]:
            raise RuntimeError("cannot cache function 'f': no locator available")
        return real(**kw)

    monkeypatch.setattr(jit, "_njit", njit)
    monkeypatch.setattr(jit, "_fallback", [None])

    @jit.kernel(nogil=True)
    def add(a: np.ndarray) -> float:
        return a.sum()

    assert add(np.ones(3)) == 3.0
    assert calls == [True, False]


def test_kernel_uses_robostereos_folder_when_numba_has_none(
        monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    seen: list[str] = []
    real = jit.nb.njit

    def njit(**kw: object) -> object:
        if kw["cache"] and not jit.config.CACHE_DIR:
            raise RuntimeError("cannot cache function 'f': no locator available")
        seen.append(jit.config.CACHE_DIR)
        return real(**kw)

    monkeypatch.setattr(jit, "_njit", njit)
    monkeypatch.setattr(jit.config, "CACHE_DIR", "")
    monkeypatch.setattr(jit, "_fallback", [str(tmp_path)])

    @jit.kernel()
    def one() -> int:
        return 1

    assert seen == [str(tmp_path)]
    assert jit.config.CACHE_DIR == ""  # restored: other packages' kernels not moved
