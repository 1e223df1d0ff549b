"""A folder's YAML file: its text reads back as plain values; the files it names lie
inside the folder, named relative to it or by an absolute path."""

from __future__ import annotations

import os
import warnings

import numpy as np
import pytest

from robostereo.errors import InputError


def test_folder_yaml_reads_back_the_plain_values_of_numpy_ones():
    import yaml

    from robostereo.io import folder_yaml_text

    data = {"camera": {"size": np.array([509, 481])}, "bits": np.int64(7),
            "range": (np.float32(0.5), 900.0), "ok": np.bool_(False),
            "views": [{"image": "a.png", "pose": {"x": np.float64(-20.0)}},
                      {"image": "b.png", "pose": {"x": 20.0}}]}
    text = folder_yaml_text(data)
    assert yaml.safe_load(text) == {
        "camera": {"size": [509, 481]}, "bits": 7, "range": [0.5, 900.0], "ok": False,
        "views": [{"image": "a.png", "pose": {"x": -20.0}},
                  {"image": "b.png", "pose": {"x": 20.0}}]}
    # numbers in flow lists, each view a block of its own, keys in their order
    assert "  size: [509, 481]\n" in text and "\n- image: b.png\n" in text
    assert text.index("camera") < text.index("bits") < text.index("views")


def test_folder_file_takes_an_absolute_path_inside_the_folder_relative_to_it(tmp_path):
    from robostereo.io import folder_file

    real = tmp_path / "real"
    (real / "sub").mkdir(parents=True)
    (tmp_path / "link").symlink_to(real, target_is_directory=True)
    (tmp_path / "elsewhere.png").write_bytes(b"x")
    (real / "own.png").symlink_to(tmp_path / "elsewhere.png")  # the folder's own link
    for folder in (real, tmp_path / "link"):
        for base in (real, tmp_path / "link"):
            assert folder_file(folder, str(base / "a.png")) == "a.png"
            assert folder_file(folder, str(base / "sub" / "b.png")) == "sub/b.png"
            assert folder_file(folder, str(base / "own.png")) == "own.png"
    assert folder_file(real, "sub/b.png") == "sub/b.png"  # relative: as written
    os.symlink(tmp_path, real / "up", target_is_directory=True)
    for name in (str(tmp_path / "elsewhere.png"), str(real / "up" / "elsewhere.png"),
                 "../elsewhere.png", f"{real}/../elsewhere.png", "sub\\b.png"):
        with pytest.raises(InputError, match="must lie inside the folder"):
            folder_file(real, name)


def test_the_moved_names_still_import_from_files_with_a_warning():
    import robostereo.io.files as files
    from robostereo.io import folder_yaml

    with pytest.warns(DeprecationWarning, match="moved to robostereo.io.folder_yaml"):
        assert files.read_folder_yaml is folder_yaml.read_folder_yaml
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(AttributeError):
            _ = files.no_such_name
