"""A folder's YAML file (``capture.yaml``, ``views.yaml``): its text, reading it with
one-line errors, and the files it names.

:func:`folder_yaml_text` writes the file's text (keys in their order, numpy values as
plain ones, :func:`plain_values`), :func:`read_folder_yaml` parses it with one-line
errors naming the file, and :func:`folder_file` checks a file that it names (a view's
``image:``): inside the folder, given relative to it or as an absolute path.  The
folders themselves are written all or nothing by
:func:`~robostereo.io.files.write_image_folder`.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path, PurePosixPath
from typing import Any

import numpy as np
import yaml

from robostereo.errors import InputError
from robostereo.io.yaml_loading import load_yaml

__all__ = [
    "folder_file",
    "folder_yaml_text",
    "plain_values",
    "read_folder_yaml",
]

PathLike = str | os.PathLike[str]


def plain_values(value: Any) -> Any:
    """`value` with numpy scalars and arrays, tuples and mappings as plain Python values
    (int, float, bool, list, dict with str keys), for YAML and JSON.

    >>> plain_values({"n": np.int64(3), "xy": np.array([0.5, 1.0]), "ok": np.bool_(True)})
    {'n': 3, 'xy': [0.5, 1.0], 'ok': True}
    """
    if isinstance(value, Mapping):
        return {str(k): plain_values(x) for k, x in value.items()}
    if isinstance(value, list | tuple | np.ndarray):
        return [plain_values(x) for x in value]
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.floating):
        return float(value)
    return value


class _FolderDumper(yaml.SafeDumper):
    """Block mappings; lists of numbers flow-style, ``[a, b]``; lists of mappings one
    entry to a block."""


_FolderDumper.add_representer(
    list, lambda d, v: d.represent_sequence(
        "tag:yaml.org,2002:seq", v, flow_style=not any(isinstance(x, dict) for x in v))
)


def folder_yaml_text(data: Mapping[str, Any]) -> str:
    """The text of a folder's YAML file (``capture.yaml``): the keys in their order,
    block mappings, flow-style lists of numbers (``[0.0172, 0.0137]``), one block per
    entry of a list of mappings (the views of a capture); numpy values as plain ones
    (:func:`plain_values`).

    >>> print(folder_yaml_text({"size": (509, 481), "views": [{"image": "a.png"}]}), end="")
    size: [509, 481]
    views:
    - image: a.png
    """
    return yaml.dump(plain_values(dict(data)), Dumper=_FolderDumper, sort_keys=False,
                     default_flow_style=False)


def read_folder_yaml(directory: PathLike, filename: str, *, folder: str) -> tuple[Any, Path]:
    """Parse ``directory/filename`` (YAML) with one-line errors naming what is wrong.

    Parameters
    ----------
    directory : path
    filename : str
        E.g. ``capture.yaml``.
    folder : str
        What the folder is, for the messages (``"capture"``, ``"views"``).

    Returns
    -------
    data, path
        The parsed document and the file's path.

    Raises
    ------
    InputError
        The folder or the file is missing, or the file is not readable YAML.
    """
    d = Path(directory)
    if not d.is_dir():
        raise InputError(f"{d}: {folder} folder not found")
    path = d / filename
    if not path.is_file():
        raise InputError(f"{path}: missing {folder} file (expected {filename} in {d})")
    try:
        return load_yaml(path.read_text(encoding="utf-8"), str(path)), path
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as exc:
        raise InputError(f"{path}: not a readable YAML file ({exc.__class__.__name__})") from None


def folder_file(directory: PathLike, name: str) -> str:
    """A file that a folder's YAML names (a view's ``image:``), as a path relative to
    the folder; refused when it leads outside.

    Parameters
    ----------
    directory : path
        The folder.
    name : str
        The file as written: relative to the folder, or an absolute path.

    Returns
    -------
    str
        `name` when relative; an absolute path inside the folder relative to it.

    Raises
    ------
    InputError
        `name` with a ``..`` part or a backslash, or an absolute path that does not lie
        inside the folder.

    Notes
    -----
    An absolute path is compared with the links resolved in the folder's path and in
    the file's folders, not in the file itself: the folder given by way of a link (or
    the file named by way of one to the folder) is the same folder, a subfolder that is
    a link to elsewhere is outside, and a file of the folder that is itself a link is
    the folder's file, as it is when named relative to the folder.

    Examples
    --------
    >>> import os, tempfile
    >>> d = tempfile.mkdtemp()
    >>> folder_file(d, os.path.join(d, "view_00.png")), folder_file(d, "view_01.png")
    ('view_00.png', 'view_01.png')
    >>> folder_file(d, "/elsewhere/view_00.png")
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: /elsewhere/view_00.png: the file must lie inside the folder ...
    """
    p = PurePosixPath(name)
    if ".." in p.parts or "\\" in name:
        raise InputError(f"{name}: the file must lie inside the folder {directory} (no '..' "
                         "or backslash)")
    if not (p.is_absolute() or Path(name).is_absolute()):
        return name
    folder = Path(os.path.realpath(directory))
    where = Path(os.path.realpath(Path(name).parent)) / Path(name).name
    try:
        return where.relative_to(folder).as_posix()
    except ValueError:
        raise InputError(f"{name}: the file must lie inside the folder {directory} "
                         f"({folder})") from None
