"""PLY point clouds with per-point fields: written, read back by another reader; a full
disk names the output, never its temporary file."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from robostereo.errors import InputError
from robostereo.io import write_ply


def test_fields_are_vertex_properties_another_reader_reads_back(tmp_path):
    rng = np.random.default_rng(2)
    xyz = rng.normal(0.0, 100.0, (50, 3))
    xyz[7] = np.nan  # left out, with its fields
    bound = rng.uniform(0.1, 5.0, 50)
    count = rng.integers(2, 9, 50)
    p = write_ply(tmp_path / "f.ply", xyz, fields={"bound_mm": bound, "view_count": count})
    assert b"property float bound_mm\nproperty int view_count\n" in p.read_bytes()
    cloud = trimesh.load(p, file_type="ply")
    keep = np.ones(50, bool)
    keep[7] = False
    assert np.allclose(cloud.vertices, xyz[keep], rtol=1e-6, atol=1e-4)
    attrs = cloud.metadata["_ply_raw"]["vertex"]["data"]
    assert np.allclose(attrs["bound_mm"], bound[keep], rtol=1e-6)
    assert np.array_equal(attrs["view_count"], count[keep])


def test_no_points_with_fields_is_an_empty_cloud_and_bad_fields_are_refused(tmp_path):
    data = write_ply(tmp_path / "e.ply", np.full((3, 3), np.nan),
                     fields={"c": np.ones(3)}).read_bytes()
    assert b"element vertex 0\n" in data and data.endswith(b"end_header\n")
    with pytest.raises(InputError, match=r"field 'c' must have shape \(3,\)"):
        write_ply(tmp_path / "b.ply", np.zeros((3, 3)), fields={"c": np.ones(4)})
    with pytest.raises(InputError, match="plain identifier"):
        write_ply(tmp_path / "b.ply", np.zeros((3, 3)), fields={"a b": np.ones(3)})
    with pytest.raises(InputError, match="colors or fields"):
        write_ply(tmp_path / "b.ply", np.zeros((3, 3)), np.zeros((3, 4), np.uint8),
                  fields={"c": np.ones(3)})
    assert not (tmp_path / "b.ply").exists()


# -- a full disk: the error names the output asked for, never its temporary file ------


def _disk_full(monkeypatch, method: str) -> None:
    """Make every ``Path.<method>`` fail as a full disk does (ENOSPC)."""
    import errno
    import os
    from pathlib import Path

    def full(self, *args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(self))

    monkeypatch.setattr(Path, method, full)


@pytest.mark.parametrize("nested", [False, True])
def test_a_full_disk_names_the_output_not_the_hidden_part_file(tmp_path, monkeypatch, nested):
    from robostereo.io import atomic_outputs, write_csv

    _disk_full(monkeypatch, "write_text")
    target = tmp_path / "m.csv"
    with pytest.raises(InputError) as err:
        if nested:  # a command's outputs: write_csv's own temporary inside the command's
            with atomic_outputs({"-o": target}) as tmp:
                write_csv(tmp["-o"], {"x": np.arange(3)})
        else:
            write_csv(target, {"x": np.arange(3)})
    msg = str(err.value)
    assert msg.startswith(f"{target}: cannot write output") and "No space left" in msg
    assert ".part" not in msg
    assert list(tmp_path.iterdir()) == []  # no output, no temporary file


def test_a_full_disk_while_writing_an_image_folder_names_the_folders_file(tmp_path,
                                                                          monkeypatch):
    from robostereo.io import write_image_folder

    _disk_full(monkeypatch, "write_bytes")
    with pytest.raises(InputError) as err:
        write_image_folder(tmp_path / "cap", {"a.png": np.zeros((4, 4), np.uint8)},
                           {"c.yaml": "x: 1\n"})
    msg = str(err.value)
    assert msg.startswith(f"{tmp_path / 'cap' / 'a.png'}: cannot write output")
    assert ".part" not in msg and list(tmp_path.iterdir()) == []
