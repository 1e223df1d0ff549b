"""Tests for robostereo.io.images: image and PFM files."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from robostereo.errors import InputError
from robostereo.io.images import load_image, read_pfm, write_pfm


def test_load_image_ppm_channel_order_and_depth(tmp_path: Path) -> None:
    rgb = np.zeros((2, 3, 3), dtype=np.uint8)
    rgb[..., 0], rgb[..., 1], rgb[..., 2] = 200, 100, 7  # R, G, B
    p = tmp_path / "a.ppm"
    p.write_bytes(b"P6\n3 2\n255\n" + rgb.tobytes())
    img, depth = load_image(p)
    assert img.shape == (2, 3, 3) and img.dtype == np.uint8 and depth == 8
    assert img[1, 2].tolist() == [200, 100, 7]


def test_load_image_16bit_pgm_maxval(tmp_path: Path) -> None:
    g = np.array([[0, 4095], [1234, 17]], dtype=">u2")  # PNM 16-bit is big-endian
    p = tmp_path / "g.pgm"
    p.write_bytes(b"P5\n# a comment\n2 2\n4095\n" + g.tobytes())
    img, depth = load_image(p)
    assert img.dtype == np.uint16 and depth == 12
    assert img.tolist() == [[0, 4095], [1234, 17]]


@pytest.mark.parametrize("ext", ["png", "tif"])
def test_load_image_png_tiff(tmp_path: Path, ext: str) -> None:
    rng = np.random.default_rng(0)
    g16 = rng.integers(0, 65536, (5, 7), dtype=np.uint16)
    cv2.imwrite(str(tmp_path / f"g.{ext}"), g16)
    img, depth = load_image(tmp_path / f"g.{ext}")
    assert depth == 16 and np.array_equal(img, g16)
    rgba = rng.integers(0, 256, (4, 6, 4), dtype=np.uint8)
    cv2.imwrite(str(tmp_path / f"c.{ext}"), cv2.cvtColor(rgba, cv2.COLOR_RGBA2BGRA))
    img, depth = load_image(tmp_path / f"c.{ext}")
    assert depth == 8 and np.array_equal(img, rgba)


def test_load_image_errors(tmp_path: Path) -> None:
    with pytest.raises(InputError, match=r"nope\.png: image file not found"):
        load_image(tmp_path / "nope.png")
    (tmp_path / "empty.ppm").write_bytes(b"")
    with pytest.raises(InputError, match=r"empty\.ppm: image file is empty"):
        load_image(tmp_path / "empty.ppm")
    (tmp_path / "junk.png").write_bytes(b"this is not an image at all" * 10)
    with pytest.raises(InputError, match=r"junk\.png: cannot decode image"):
        load_image(tmp_path / "junk.png")


def test_pfm_bottom_to_top_and_endianness(tmp_path: Path) -> None:
    top_row, bottom_row = [1.0, 2.0, 3.0], [4.0, np.inf, 6.0]
    # big-endian (positive scale), rows stored bottom row first
    body = np.array([bottom_row, top_row], dtype=">f4").tobytes()
    p = tmp_path / "be.pfm"
    p.write_bytes(b"Pf\n3 2\n1.0\n" + body)
    a = read_pfm(p)
    assert a.dtype == np.float32 and a.tolist() == [top_row, bottom_row]
    q = tmp_path / "le.pfm"
    q.write_bytes(b"Pf\n3 2\n-1.0\n" + np.array([bottom_row, top_row], dtype="<f4").tobytes())
    assert read_pfm(q).tolist() == [top_row, bottom_row]


def test_pfm_round_trip_colour_and_errors(tmp_path: Path) -> None:
    rng = np.random.default_rng(1)
    c = rng.normal(size=(4, 5, 3)).astype(np.float32)
    for le in (True, False):
        write_pfm(tmp_path / "c.pfm", c, little_endian=le)
        np.testing.assert_array_equal(read_pfm(tmp_path / "c.pfm"), c)
    (tmp_path / "t.pfm").write_bytes(b"Pf\n3 2\n-1.0\n" + b"\0" * 20)
    with pytest.raises(InputError, match=r"t\.pfm: PFM data truncated: 20 bytes, expected 24"):
        read_pfm(tmp_path / "t.pfm")
    (tmp_path / "h.pfm").write_bytes(b"P6\n3 2\n255\n" + b"\0" * 18)
    with pytest.raises(InputError, match=r"h\.pfm: not a PFM file"):
        read_pfm(tmp_path / "h.pfm")
    with pytest.raises(InputError, match=r"x\.pfm: PFM file not found"):
        read_pfm(tmp_path / "x.pfm")


def test_truncated_png_gives_our_line_only(tmp_path, capfd):
    """libpng writes its complaint to file descriptor 2 from C; it must not show."""
    import cv2

    from robostereo.cli import main

    img = np.random.default_rng(0).integers(0, 255, (100, 100)).astype(np.uint8)
    data = cv2.imencode(".png", img)[1].tobytes()
    for n in (len(data) // 2, len(data) - 12):  # in the pixel data; the end chunk cut
        p = tmp_path / f"t{n}.png"
        p.write_bytes(data[:n])
        code = main(["plan", "--depth", "1000", "--accuracy", "5", "--image", str(p)])
        err = capfd.readouterr().err
        assert "libpng" not in err
        if code == 2:
            assert err.splitlines() == [err.splitlines()[0]]
            assert err.startswith(f"robostereo: error: {p}: cannot decode image")
        else:  # every pixel was there: read in full
            assert code == 0 and err == ""
