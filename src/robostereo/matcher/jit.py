"""Compiling the matcher's numba kernels with a cache that can be written.

numba's ``cache=True`` keeps compiled kernels beside the source (``__pycache__``) or in
the user's cache folder (``~/.cache/numba``); when neither can be written -- a package
installed read-only by root for a user without a writable HOME, a container with a
read-only root file system -- numba refuses to compile the function at all, at import
(``cannot cache function ...: no locator available``).  :func:`kernel` decorates a
kernel as ``numba.njit(cache=True, ...)`` and, when numba finds no place to cache,
compiles it with the cache in robostereo's own folder (:func:`fallback_cache_dir`), or
without a cache when no folder at all can be written (every run then compiles the
kernels again: some seconds more, the same results).

``NUMBA_CACHE_DIR``, when set, is numba's and wins, as numba documents.
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numba as nb
from numba.core import config

__all__ = ["fallback_cache_dir", "kernel"]

_fallback: list[str | None] = []  # computed once: [folder or None]
_njit = nb.njit  # the decorator used (a test replaces it)


def _private_dir(path: Path) -> bool:
    """Make `path` (mode 0700) if missing; True if it is ours, a folder, not writable by
    others, and writable by us (a cache holds pickles: another user's must not be read)."""
    try:
        path.mkdir(mode=0o700, parents=True, exist_ok=True)
        st = path.stat()
    except OSError:
        return False
    return (stat.S_ISDIR(st.st_mode) and st.st_uid == os.getuid()
            and not st.st_mode & (stat.S_IWGRP | stat.S_IWOTH)
            and os.access(path, os.W_OK | os.X_OK))


def fallback_cache_dir() -> str | None:
    """robostereo's cache folder for kernels numba cannot cache where it would.

    ``$XDG_CACHE_HOME/robostereo/numba`` (``XDG_CACHE_HOME`` default ``~/.cache``), else
    ``<temp folder>/robostereo-numba-<uid>``; the first that is (or can be made) a
    folder of ours that others cannot write.  None when there is none.

    >>> d = fallback_cache_dir()
    >>> d is None or os.path.isdir(d)
    True
    """
    if not _fallback:
        xdg = os.environ.get("XDG_CACHE_HOME") or os.path.join(
            os.path.expanduser("~"), ".cache")
        found = None
        for cand in (Path(xdg) / "robostereo" / "numba",
                     Path(tempfile.gettempdir()) / f"robostereo-numba-{os.getuid()}"):
            if cand.is_absolute() and _private_dir(cand):
                found = str(cand)
                break
        _fallback.append(found)
    return _fallback[0]


@contextlib.contextmanager
def _cache_dir(path: str) -> Iterator[None]:
    """numba's ``CACHE_DIR`` set to `path` while a kernel is decorated (numba picks the
    cache folder then), and restored after: other packages' kernels are not moved."""
    old = config.CACHE_DIR
    config.CACHE_DIR = path
    try:
        yield
    finally:
        config.CACHE_DIR = old


def kernel(**options: Any) -> Callable[[Callable[..., Any]], Any]:
    """``numba.njit(cache=True, **options)`` that also compiles where nothing is writable.

    Parameters
    ----------
    **options
        numba's ``njit`` options (``nogil``, ``fastmath``, ``inline``...).

    Returns
    -------
    callable
        The decorator.

    Notes
    -----
    1. Decorate with ``cache=True``: numba caches beside the source or in the user's
       cache folder if it can write either.
    2. If numba finds neither (``RuntimeError: cannot cache function ...``), decorate
       again with numba's ``CACHE_DIR`` set to :func:`fallback_cache_dir` for the time
       of the decoration.
    3. If there is no such folder, decorate with ``cache=False``.

    Examples
    --------
    >>> @kernel(nogil=True)
    ... def twice(x):
    ...     return 2 * x
    >>> twice(21)
    42
    """

    def decorate(fn: Callable[..., Any]) -> Any:
        try:
            return _njit(cache=True, **options)(fn)
        except RuntimeError as e:
            if "cannot cache" not in str(e):
                raise
        where = fallback_cache_dir()
        if where is not None:
            try:
                with _cache_dir(where):
                    return _njit(cache=True, **options)(fn)
            except RuntimeError as e:
                if "cannot cache" not in str(e):
                    raise
        return _njit(cache=False, **options)(fn)

    return decorate
