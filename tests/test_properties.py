"""Property tests (hypothesis) over every public entry: bad input gives one clear line.

Every call either succeeds, and its result keeps its invariants, or raises
:class:`~robostereo.errors.InputError` (a :class:`TypeError` for a wrong Python type)
with a one-line message; the command line returns 0 or 2 and writes only lines
starting ``robostereo:`` (or argparse's usage) to standard error, never overwrites an
input and never leaves a partial output.  The profiles are set in ``conftest.py``:
"fast" runs here in the normal test run; the long one with

    ROBOSTEREO_HYPOTHESIS=long python -m pytest tests/test_properties.py -q \\
        --hypothesis-show-statistics
"""

from __future__ import annotations

import contextlib
import faulthandler
import io
import math
import shutil
import sys
import tempfile
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import pytest
import yaml

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import assume, given  # noqa: E402
from hypothesis import strategies as st  # noqa: E402
from hypothesis.extra import numpy as hnp  # noqa: E402
from synthetic import synthetic_pair  # noqa: E402

from robostereo import (  # noqa: E402
    InputError,
    MatchParameters,
    RelaxationParameters,
    StereoCamera,
    detect_edges,
    match_stereo,
    score_matches,
    triangulate,
)
from robostereo.cli import main  # noqa: E402
from robostereo.geometry.calibration import StereoCalibration  # noqa: E402
from robostereo.io import load_stereo_camera  # noqa: E402
from robostereo.io.calibration_files import (  # noqa: E402
    read_calibration,
    write_opencv_calibration,
)
from robostereo.io.cameras import (  # noqa: E402
    load_camera_yaml,
    load_pose_yaml,
    load_stereo_poses_yaml,
)
from robostereo.io.images import load_image  # noqa: E402

EXTS = (".png", ".ppm", ".pgm", ".pnm", ".tif", ".tiff", ".bmp", ".jpg", ".jpeg")

# a NumPy warning printed to the user is a fault too: overflow, division by zero...
pytestmark = pytest.mark.filterwarnings("error::RuntimeWarning")
OK = (InputError, TypeError)


def _one_line(e: BaseException) -> None:
    msg = str(e)
    assert msg and "\n" not in msg, repr(msg)


HANG_SECONDS = 60
"""A call stuck this long -- e.g. looping in native code, where no deadline can stop it
-- ends the whole run with a traceback of where it hangs (exit code 1)."""


@contextlib.contextmanager
def _no_hang() -> Any:
    faulthandler.dump_traceback_later(HANG_SECONDS, exit=True, file=sys.__stderr__)
    try:
        yield
    finally:
        faulthandler.cancel_dump_traceback_later()


def _expect(call: Any, *args: Any, **kwargs: Any) -> Any:
    """The call's result, or None after checking that its error is a one-line one of ours."""
    try:
        with _no_hang():
            return call(*args, **kwargs)
    except OK as e:
        _one_line(e)
        return None


# -- strategies ----------------------------------------------------------------------

any_float = st.floats(allow_nan=True, allow_infinity=True)
numbers = st.one_of(st.integers(-10**20, 10**20), any_float, st.floats(-50, 50))
junk = st.one_of(st.none(), st.booleans(), st.text(max_size=5), st.lists(st.integers(), max_size=3),
                 st.dictionaries(st.text(max_size=3), st.integers(), max_size=2))
values = st.one_of(numbers, junk)


@st.composite
def images(draw: st.DrawFn) -> np.ndarray:
    """Small arrays of any dtype and shape: noise, steps, constants, NaN."""
    kind = draw(st.sampled_from(["noise", "steps", "array", "weird"]))
    if kind == "weird":
        dtype = draw(st.sampled_from([np.complex64, np.bool_, np.int32, np.int64, np.float16]))
        shape = draw(st.one_of(st.tuples(st.integers(0, 12), st.integers(0, 30)),
                               st.tuples(st.integers(0, 30)), st.just(())))
        return draw(hnp.arrays(dtype, shape))
    h, w = draw(st.integers(1, 24)), draw(st.integers(1, 64))
    channels = draw(st.sampled_from([None, None, None, 1, 2, 3, 4, 5]))
    shape = (h, w) if channels is None else (h, w, channels)
    dtype = draw(st.sampled_from([np.uint8, np.uint8, np.uint16, np.int8, np.int16,
                                  np.float32, np.float64]))
    if kind == "array":
        return draw(hnp.arrays(dtype, shape))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    if kind == "noise":
        a = rng.random(shape)
    else:
        cols = np.cumsum(rng.integers(3, 12, w)) % 2
        a = np.broadcast_to(cols[None, :] if channels is None else cols[None, :, None], shape)
    if np.issubdtype(dtype, np.integer):
        return (a * np.iinfo(dtype).max).astype(dtype)
    return (a * draw(st.sampled_from([1.0, 1.0, 127.0, 255.0, -1.0]))).astype(dtype)


ranges = st.one_of(
    st.tuples(st.integers(-30, 30), st.integers(-30, 30)).map(lambda t: (min(t), max(t))),
    st.tuples(numbers, numbers),
    st.lists(numbers, max_size=3),
    junk,
)


def _mostly(draw: st.DrawFn, good: st.SearchStrategy[Any]) -> Any:
    """A draw of `good` nine times in ten, else any value at all."""
    return draw(good) if draw(st.integers(0, 9)) else draw(values)


@st.composite
def match_params(draw: st.DrawFn) -> dict[str, Any]:
    kw: dict[str, Any] = {}
    for key, strat in (
        ("threshold", st.floats(0.5, 30)),
        ("right_threshold_ratio", st.floats(0.2, 2)),
        ("row_step", st.integers(1, 4)),
        ("subpixel", st.booleans()),
        ("profile_scale", st.one_of(st.none(), st.floats(0.1, 50))),
        ("min_confidence", st.floats(0, 1)),
        ("method", st.sampled_from(("window", "relaxation"))),
        ("bit_depth", st.one_of(st.none(), st.integers(1, 16))),
    ):
        if draw(st.booleans()):
            kw[key] = _mostly(draw, strat)
    if draw(st.booleans()):
        kw["relaxation"] = ("relax", {
            "iterations": _mostly(draw, st.integers(0, 6)),
            "no_match_support": _mostly(draw, st.floats(0, 2)),
        })
    return kw


def _build_params(kw: dict[str, Any]) -> MatchParameters:
    kw = dict(kw)
    if "relaxation" in kw:
        kw["relaxation"] = RelaxationParameters(**kw["relaxation"][1])
    return MatchParameters(**kw)


camera_kwargs = st.one_of(
    st.fixed_dictionaries(
        {"fx": st.floats(1, 5000), "fy": st.floats(1, 5000), "baseline_mm": st.floats(1, 500)},
        optional={"cx": st.one_of(st.none(), st.floats(-100, 300)), "doffs": st.floats(-20, 20)},
    ),
    st.fixed_dictionaries(
        {"fx": st.one_of(st.floats(1, 5000), numbers), "fy": st.one_of(st.floats(1, 5000), numbers),
         "baseline_mm": st.one_of(st.floats(1, 500), numbers)},
        optional={"cx": st.one_of(st.none(), numbers), "cy": st.one_of(st.none(), numbers),
                  "doffs": numbers, "disparity_uncertainty_px": numbers},
    ),
)


# -- the matcher and its result ------------------------------------------------------


@given(left=images(), right=st.one_of(st.none(), images()), drange=ranges,
       params=match_params(), camera=st.one_of(st.none(), camera_kwargs),
       valid=st.sampled_from([None, "all", "half", "wrong"]), data=st.data())
def test_match_stereo(left, right, drange, params, camera, valid, data) -> None:
    right = left if right is None else right
    if right is left and left.ndim >= 2 and left.shape[1] > 4:
        right = np.roll(left, -data.draw(st.integers(0, 4)), axis=1)
    p = _expect(_build_params, params)
    cam = _expect(StereoCamera, **camera) if camera is not None else None
    assume(p is not None and (camera is None or cam is not None))
    masks = {}
    if valid is not None and left.ndim >= 2:
        shape = left.shape[:2] if valid != "wrong" else (left.shape[0] + 1, left.shape[1])
        m = np.ones(shape, bool)
        if valid == "half":
            m[:, : shape[1] // 2] = False
        masks = {"valid_left": m, "valid_right": m}
    res = _expect(match_stereo, left, right, drange, params=p, camera=cam, **masks)
    if res is None:
        return
    lo, hi = res.disparity_range
    assert lo <= hi and abs(lo) <= res.image_shape[1] and abs(hi) <= res.image_shape[1]
    d = res.edge_disparity[np.isfinite(res.edge_disparity)]
    assert ((d >= lo - 0.5 - 1e-9) & (d <= hi + 0.5 + 1e-9)).all()
    conf = res.edge_confidence[np.isfinite(res.edge_confidence)]
    assert ((conf >= -1e-9) & (conf <= 1 + 1e-9)).all()
    assert np.all(res.confidence >= res.parameters.acceptance - 1e-12)
    t = res.table()
    assert {len(v) for v in t.values()} == {len(res)}
    assert {len(v) for v in res.edge_table().values()} == {len(res.left_edges)}
    if res.parameters.method == "relaxation":
        c = res.candidates
        assert ((c.disparity >= lo - 0.5 - 1e-9) & (c.disparity <= hi + 0.5 + 1e-9)).all()
        assert res.match.shape == (len(res.left_edges),)
        prob = res.relaxation.probability
        assert np.isfinite(prob).all() and ((prob >= -1e-9) & (prob <= 1 + 1e-9)).all()
        for k in (0, 1, res.relaxation.iterations, 99):
            assert res.matches_after(k).shape == res.match.shape
        assert np.array_equal(np.isfinite(res.disparity_of(res.match)), res.match >= 0)
        _expect(res.matches_after, data.draw(values))
    else:
        assert res.candidates is None and res.window is not None
    if cam is not None:
        xyz, zb = res.triangulated()
        assert xyz.shape == (len(res), 3) and zb.shape == (len(res),)
        z = xyz[:, 2]
        assert (z[np.isfinite(z)] > 0).all()


@given(image=images(), threshold=st.one_of(st.floats(0.5, 30), values),
       row_step=st.one_of(st.integers(1, 5), values), row_offset=st.one_of(st.integers(0, 5),
                                                                            values),
       bit_depth=st.one_of(st.none(), st.integers(-1, 40), values), subpixel=st.booleans())
def test_detect_edges(image, threshold, row_step, row_offset, bit_depth, subpixel) -> None:
    e = _expect(detect_edges, image, threshold=threshold, row_step=row_step,
                row_offset=row_offset, bit_depth=bit_depth, subpixel=subpixel)
    if e is None:
        return
    w = image.shape[1]
    assert ((e.x >= 0) & (e.x <= w - 1)).all() and (e.magnitude >= threshold - 1e-6).all()
    assert ((e.pattern >= 1) & (e.pattern <= 16)).all()
    assert (np.diff(e.line * (w + 1) + e.x) > 0).all()  # sorted by (line, x)


@given(camera=camera_kwargs, n=st.integers(0, 6), extra=st.integers(-1, 1),
       coords=st.lists(numbers, min_size=18, max_size=18),
       shape=st.one_of(st.tuples(st.integers(1, 600), st.integers(1, 800)), junk))
def test_triangulate(camera, n, extra, coords, shape) -> None:
    cam = _expect(StereoCamera, **camera)
    if cam is None:
        return
    xl, xr, rows = coords[:n], coords[6:6 + n], coords[12:12 + max(n + extra, 0)]
    out = _expect(triangulate, cam, xl, xr, rows, shape)
    if out is None:
        return
    xyz, zb = out
    assert xyz.shape == (n, 3) and zb.shape == (n,)
    z = xyz[:, 2]
    assert (z[np.isfinite(z)] > 0).all()


@given(gt=st.one_of(hnp.arrays(np.float64, st.tuples(st.integers(0, 6), st.integers(0, 9))),
                    hnp.arrays(np.float64, st.tuples(st.integers(0, 9))), junk),
       n=st.integers(0, 8), rows=st.lists(st.one_of(st.integers(-2, 8), numbers), max_size=8),
       x=st.lists(st.one_of(st.floats(-1, 10), numbers), max_size=8),
       d=st.lists(numbers, max_size=8), tol=st.one_of(st.floats(0, 3), numbers))
def test_score_matches(gt, n, rows, x, d, tol) -> None:
    s = _expect(score_matches, rows[:n], x[:n], d[:n], gt, tolerance=tol)
    if s is not None:
        assert 0 <= s.false <= s.matched <= s.counted <= n


# -- files: images, cameras, poses, captures, calibrations ---------------------------


def _encoded(ext: str, seed: int, kind: str) -> bytes:
    import cv2.utils.logging as cv_log

    rng = np.random.default_rng(seed)
    img = {"grey": rng.integers(0, 256, (9, 13), dtype=np.uint8),
           "colour": rng.integers(0, 256, (9, 13, 3), dtype=np.uint8),
           "16bit": rng.integers(0, 65536, (9, 13), dtype=np.uint16),
           "float": rng.random((9, 13), dtype=np.float32) * (2.0 if seed % 2 else 1.0)}[kind]
    cv_log.setLogLevel(cv_log.LOG_LEVEL_SILENT)
    try:
        ok, buf = cv2.imencode(ext, img)
    except cv2.error:
        ok = False
    if not ok:
        ok, buf = cv2.imencode(".ppm" if img.ndim == 3 else ".pgm", img.astype(np.uint8))
    return buf.tobytes()


@st.composite
def image_bytes(draw: st.DrawFn) -> tuple[str, bytes]:
    ext = draw(st.sampled_from(EXTS + tuple(e.upper() for e in EXTS[:3])))
    how = draw(st.sampled_from(["random", "truncated", "flipped", "valid"]))
    if how == "random":
        return ext, draw(st.binary(max_size=300))
    data = _encoded(ext.lower(), draw(st.integers(0, 1000)),
                    draw(st.sampled_from(["grey", "colour", "16bit", "float"])))
    if how == "truncated":
        data = data[: draw(st.integers(0, len(data)))]
    elif how == "flipped":
        b = bytearray(data)
        for _ in range(draw(st.integers(1, 8))):
            i = draw(st.integers(0, len(b) - 1))
            b[i] = draw(st.integers(0, 255))
        data = bytes(b)
    return ext, data


@given(item=image_bytes())
def test_load_image(item) -> None:
    ext, data = item
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / f"img{ext}"
        p.write_bytes(data)
        out = _expect(load_image, p)
    if out is None:
        return
    img, depth = out
    assert img.ndim in (2, 3) and img.size > 0 and img.dtype.kind in "ui"
    assert isinstance(depth, int) and 1 <= depth <= 64


def _yaml_text(draw: st.DrawFn, keys: tuple[str, ...]) -> str:
    how = draw(st.sampled_from(["mapping", "mapping", "text", "scalar"]))
    if how == "text":
        return draw(st.text(max_size=80))
    if how == "scalar":
        return yaml.safe_dump(draw(values))
    doc = {}
    for k in draw(st.lists(st.sampled_from((*keys, "other")), unique=True, max_size=len(keys) + 1)):
        doc[k] = draw(st.one_of(values, st.lists(numbers, min_size=2, max_size=2),
                                st.dictionaries(st.sampled_from(["x", "y", "z", "phi_deg"]),
                                                numbers, max_size=4)))
    return yaml.safe_dump(doc)


CAMERA_KEYS = ("fx", "fy", "cx", "cy", "baseline_mm", "doffs", "focal_length_mm",
               "pixel_pitch_mm")
ROBOT_CAMERA_KEYS = ("focal_length_mm", "pixel_pitch_mm", "image_size", "principal_point",
                     "grey_levels")


@given(data=st.data(), reader=st.sampled_from(["stereo", "camera", "pose", "poses"]))
def test_camera_and_pose_readers(data, reader) -> None:
    keys = {"stereo": CAMERA_KEYS, "camera": ROBOT_CAMERA_KEYS, "pose": ("x", "y", "z", "phi_deg"),
            "poses": ("left", "right", "pose_left", "pose_right")}[reader]
    text = _yaml_text(data.draw, keys)
    fn = {"stereo": load_stereo_camera, "camera": load_camera_yaml, "pose": load_pose_yaml,
          "poses": load_stereo_poses_yaml}[reader]
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "f.yaml"
        p.write_text(text)
        _expect(fn, p)


@given(data=st.data(), name=st.sampled_from(["c.yml", "c.yaml", "c.xml", "c.json", "calib.txt"]),
       how=st.sampled_from(["text", "bytes", "valid", "edited"]))
def test_read_calibration(data, name, how) -> None:
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / name
        if how == "text":
            p.write_text(data.draw(st.text(max_size=200)))
        elif how == "bytes":
            p.write_bytes(data.draw(st.binary(max_size=200)))
        else:
            K = [[800.0, 0, 99.5], [0, 800.0, 29.5], [0, 0, 1]]
            if name == "calib.txt":
                p.write_text("cam0=[800 0 99.5; 0 800 29.5; 0 0 1]\n"
                             "cam1=[800 0 99.5; 0 800 29.5; 0 0 1]\ndoffs=0\nbaseline=60\n"
                             "width=200\nheight=60\nndisp=64\n")
            else:
                write_opencv_calibration(StereoCalibration(K, None, K, None, np.eye(3),
                                                           [-60, 0, 0], (200, 60)),
                                         Path(d) / ("c.yml" if name == "c.yaml" else name))
                if name == "c.yaml":
                    (Path(d) / "c.yml").rename(p)
            if how == "edited":
                text = p.read_text()
                i = data.draw(st.integers(0, max(len(text) - 1, 0)))
                n = data.draw(st.integers(0, 20))
                p.write_text(text[:i] + data.draw(st.text(max_size=6)) + text[i + n:])
        _expect(read_calibration, p)


@given(data=st.data())
def test_read_ros_calibration(data) -> None:
    """A ROS camera_info pair (rectified, 60 mm baseline), one entry of one file altered."""
    K = [800.0, 0.0, 99.5, 0.0, 800.0, 29.5, 0.0, 0.0, 1.0]
    with tempfile.TemporaryDirectory() as d:
        paths = []
        for name, tx in (("left", 0.0), ("right", -800.0 * 0.06)):
            info: dict[str, Any] = {
                "image_width": 200, "image_height": 60, "camera_name": name,
                "camera_matrix": {"rows": 3, "cols": 3, "data": K},
                "distortion_model": "plumb_bob",
                "distortion_coefficients": {"rows": 1, "cols": 5, "data": [0.0] * 5},
                "rectification_matrix": {"rows": 3, "cols": 3,
                                         "data": [1.0, 0, 0, 0, 1.0, 0, 0, 0, 1.0]},
                "projection_matrix": {"rows": 3, "cols": 4,
                                      "data": [800.0, 0, 99.5, tx, 0, 800.0, 29.5, 0, 0, 0, 1, 0]},
            }  # fmt: skip
            paths.append(Path(d) / f"{name}.yaml")
            if data.draw(st.booleans()):
                key = data.draw(st.sampled_from(sorted(info)))
                if isinstance(info[key], dict) and data.draw(st.booleans()):
                    sub = data.draw(st.sampled_from(["rows", "cols", "data"]))
                    info[key] = {**info[key], sub: data.draw(st.one_of(
                        values, st.lists(numbers, max_size=13)))}
                elif data.draw(st.booleans()):
                    del info[key]
                else:
                    info[key] = data.draw(values)
            paths[-1].write_text(yaml.safe_dump(info))
        _expect(read_calibration, paths[0], paths[1])


@pytest.fixture(scope="module")
def capture_images() -> tuple[bytes, bytes]:
    left, right, _ = synthetic_pair(np.random.default_rng(3), height=60, width=120)
    return (cv2.imencode(".png", left)[1].tobytes(), cv2.imencode(".png", right)[1].tobytes())


@given(data=st.data())
def test_read_capture(capture_images, data) -> None:
    from robostereo.robot.capture import locate_capture, read_capture

    doc: dict[str, Any] = {
        "camera": {"focal_length_mm": 25.0, "pixel_pitch_mm": [0.0172, 0.0137],
                   "image_size": [120, 60]},
        "pose_left": {"x": -10.0, "y": 0.0, "z": 900.0, "phi_deg": 0.0},
        "pose_right": {"x": 10.0, "y": 0.0, "z": 900.0, "phi_deg": 0.0},
        "bit_depth": 8, "disparity_range": [4, 16],
    }
    for _ in range(data.draw(st.integers(0, 3))):  # break it a little
        key = data.draw(st.sampled_from([*doc, "other", "uncertainty", "depth_range_mm"]))
        if data.draw(st.booleans()) and isinstance(doc.get(key), dict) and doc[key]:
            sub = data.draw(st.sampled_from(sorted(doc[key])))
            doc[key] = {**doc[key], sub: data.draw(values)}
        elif data.draw(st.booleans()):
            doc.pop(key, None)
        else:
            doc[key] = data.draw(st.one_of(values, st.lists(numbers, min_size=2, max_size=2)))
    with tempfile.TemporaryDirectory() as d:
        dd = Path(d)
        (dd / "capture.yaml").write_text(yaml.safe_dump(doc))
        (dd / "left.png").write_bytes(capture_images[0])
        (dd / "right.png").write_bytes(capture_images[1])
        if data.draw(st.booleans()):
            _expect(read_capture, dd)
        else:
            located = _expect(locate_capture, dd)
            if located is not None:
                assert located.world.shape == (len(located), 3)


# -- the command line ----------------------------------------------------------------


@pytest.fixture(scope="module")
def workdir(capture_images) -> Any:
    """Input files for the command line: a pair, junk, a camera, a calibration, a capture,
    a scene and a batch folder."""
    from robostereo.robot.capture import write_capture  # noqa: F401 - the folder is written by hand

    with tempfile.TemporaryDirectory() as d:
        root = Path(d)
        left, right, gt = synthetic_pair(np.random.default_rng(4), height=60, width=200)
        cv2.imwrite(str(root / "l.png"), left)
        cv2.imwrite(str(root / "r.png"), right)
        (root / "junk.png").write_bytes(b"\x89PNG\r\n\x1a\n not really")
        (root / "empty.ppm").write_bytes(b"")
        (root / "cam.yaml").write_text("fx: 800\nfy: 800\nbaseline_mm: 60\n")
        K = [[800.0, 0, 99.5], [0, 800.0, 29.5], [0, 0, 1]]
        write_opencv_calibration(StereoCalibration(K, None, K, None, np.eye(3), [-60, 0, 0],
                                                   (200, 60)), root / "rig.yml")
        cap = root / "cap"
        cap.mkdir()
        (cap / "left.png").write_bytes(capture_images[0])
        (cap / "right.png").write_bytes(capture_images[1])
        (cap / "capture.yaml").write_text(yaml.safe_dump({
            "camera": {"focal_length_mm": 25.0, "pixel_pitch_mm": [0.0172, 0.0137],
                       "image_size": [120, 60]},
            "pose_left": {"x": -10.0, "y": 0.0, "z": 900.0},
            "pose_right": {"x": 10.0, "y": 0.0, "z": 900.0},
            "bit_depth": 8, "disparity_range": [4, 16]}))
        scene = root / "scenes" / "tiny"
        scene.mkdir(parents=True)
        cv2.imwrite(str(scene / "left.png"), left)
        cv2.imwrite(str(scene / "right.png"), right)
        cv2.imwrite(str(scene / "gt_disp_left.png"),
                    np.nan_to_num(gt * 4, nan=0).astype(np.uint8))
        (root / "scenes" / "scenes.json").write_text('{"scenes": {"tiny": {"scale": 4}}}')
        batch = root / "pairs" / "p"
        batch.mkdir(parents=True)
        cv2.imwrite(str(batch / "left.png"), left)
        cv2.imwrite(str(batch / "right.png"), right)
        (root / "adir").mkdir()
        yield root


def _snapshot(root: Path) -> dict[str, bytes]:
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*"))
            if p.is_file()}


def _inputs_of(args: list[str]) -> set[str]:
    """The names of `args` that the command reads (positionals, camera, calibration)."""
    names, skip = set(), False
    for i, a in enumerate(args[1:], start=1):
        if skip:
            skip = False
            continue
        if a.startswith("-"):
            skip = "=" not in a and a not in ("--seed-mode", "--json", "--no-sgbm") and not (
                a == "--ply" and args[0] in ("evaluate", "batch"))
            if a in ("--camera", "--calibration", "--calibration-right") and i + 1 < len(args):
                names.add(args[i + 1])
            continue
        names.add(a)
    if args[0] == "locate":
        names |= {f"{n}/{f}" for n in set(names) for f in ("capture.yaml", "left.png",
                                                             "right.png")}
    return names


INPUT_NAMES = ["l.png", "r.png", "junk.png", "empty.ppm", "missing.png", "adir", "cam.yaml",
               "rig.yml", "cap", "scenes/tiny", "pairs"]
OUTPUT_NAMES = ["o.csv", "o.ply", "e.csv", "v.png", "adir", "l.png", "cam.yaml",
                "nofolder/o.csv", "/proc/robostereo.csv", "o.csv"]


@st.composite
def argv(draw: st.DrawFn) -> list[str]:
    cmd = draw(st.sampled_from(["match", "rig", "evaluate", "locate", "batch"]))
    inp = st.sampled_from(INPUT_NAMES)
    out = st.sampled_from(OUTPUT_NAMES)
    num = st.one_of(st.sampled_from(["4", "16", "8", "2", "1", "-3", "0", "2.5"]),
                    st.sampled_from(["1e9", "-1e18", "nan", "inf", "x", ""]),
                    st.integers(-50, 300).map(str))
    positional = {"match": 2, "rig": 2, "evaluate": 1, "locate": 1, "batch": 1}[cmd]
    good = {"match": ["l.png", "r.png"], "rig": ["l.png", "r.png"], "evaluate": ["scenes/tiny"],
            "locate": ["cap"], "batch": ["pairs"]}[cmd]
    if draw(st.integers(0, 9)) < 7:  # mostly the right inputs, the odd one swapped
        args = [cmd, *good]
        if draw(st.booleans()):
            args[draw(st.integers(1, len(good)))] = draw(inp)
    else:
        args = [cmd, *(draw(inp) for _ in range(draw(st.integers(max(positional - 1, 0),
                                                                 positional + 1))))]
    options = {
        "match": ["--min-disparity", "--max-disparity", "--camera", "-o", "--ply", "--edges",
                  "--overlay", "--threshold", "--row-step", "--iterations", "--seed-mode"],
        "rig": ["--calibration", "--calibration-right", "--min-disparity", "--max-disparity",
                "--min-depth", "--max-depth", "-o", "--ply"],
        "evaluate": ["--json", "--min-disparity", "--max-disparity", "--scale", "--no-sgbm"],
        "locate": ["-o", "--ply"],
        "batch": ["--out", "--min-disparity", "--max-disparity", "--calibration", "--ply",
                  "--scheduler"],
    }[cmd]
    usual = {"match": ["--min-disparity", "4", "--max-disparity", "16", "-o", "o.csv"],
             "rig": ["--calibration", "rig.yml", "--min-disparity", "4", "--max-disparity", "16",
                     "-o", "o.csv"],
             "evaluate": draw(st.sampled_from([["--no-sgbm"], []])), "locate": [],
             "batch": ["--out", "bout"]}[cmd]
    if draw(st.integers(0, 9)) < 8:
        args += usual
    for opt in draw(st.lists(st.sampled_from(options), max_size=4)):
        if opt in ("--seed-mode", "--json", "--no-sgbm", "--ply") and (
                cmd in ("evaluate", "batch") or opt == "--seed-mode"):
            args.append(opt)
        elif opt in ("-o", "--ply", "--edges", "--overlay", "--out"):
            args += [opt, draw(out)]
        elif opt in ("--camera", "--calibration", "--calibration-right"):
            args += [opt, draw(inp)]
        elif opt == "--scheduler":
            args += [opt, draw(st.sampled_from(["notaurl", "", "tcp://", "::::"]))]
        elif draw(st.booleans()):
            args += [opt, draw(num)]
        else:  # the form that takes negative numbers in exponent notation, -1e18
            args.append(f"{opt}={draw(num)}")
    if cmd == "batch":
        args += ["--workers", "1"]
    return args


@given(args=argv())
def test_command_line(workdir: Path, args: list[str]) -> None:
    import os

    before = _snapshot(workdir)
    err = io.StringIO()
    cwd = os.getcwd()
    os.chdir(workdir)
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            try:
                with _no_hang():
                    rc = main(args)
            except SystemExit as e:  # argparse: usage and one error line
                rc = e.code
                hypothesis.event(f"{args[0]}: argparse exit {rc}")
                assert rc in (0, 2) and (rc == 0 or err.getvalue().startswith("usage:"))
                return
    finally:
        os.chdir(cwd)
        after = _snapshot(workdir)
        new = set(after) - set(before)
        for name in new | {"bout"}:
            p = workdir / name
            if p.is_file():
                p.unlink()
        for name, data in before.items():  # outputs written over files: put them back
            if after.get(name) != data:
                shutil.rmtree(workdir / name, ignore_errors=True)
                (workdir / name).write_bytes(data)
        for p in sorted(workdir.rglob("*"), reverse=True):  # folders made by the command
            if p.is_dir() and str(p.relative_to(workdir)) not in {
                    "adir", "cap", "scenes", "scenes/tiny", "pairs", "pairs/p"}:
                with contextlib.suppress(OSError):
                    p.rmdir()
    text = err.getvalue()
    hypothesis.event(f"{args[0]}: exit {rc}")
    assert rc in (0, 2), (rc, text)
    lines = text.splitlines()
    assert all(ln.startswith("robostereo: ") for ln in lines), text
    assert not any(".part" in n for n in new), new
    changed = {k for k in before if after.get(k) != before[k]}
    assert not (changed & _inputs_of(args)), (changed, args)  # an input is never overwritten
    if rc == 2:
        assert any(ln.startswith("robostereo: error: ") for ln in lines), text
        if args[0] in ("match", "rig", "locate"):
            assert len([ln for ln in lines if "error" in ln]) == 1, text
            assert not new, new  # all or nothing
    assert math.isfinite(rc)


# -- planning, fusing, quaternions, signals --------------------------------------------

extreme = st.one_of(st.floats(allow_nan=True, allow_infinity=True),
                    st.sampled_from([1e-300, 1e300, 1e200, 5e-324, 0.0, -1.0, 1000.0, 5.0]),
                    st.floats(1e-3, 1e5))


@given(depth=extreme, accuracy=extreme, near=st.one_of(st.none(), extreme),
       far=st.one_of(st.none(), extreme), unc=st.one_of(st.just(0.2), extreme))
def test_plan_command(depth, accuracy, near, far, unc) -> None:
    args = ["plan", f"--depth={depth!r}", f"--accuracy={accuracy!r}",
            f"--disparity-uncertainty={unc!r}", "--json"]
    args += [] if near is None else [f"--near={near!r}"]
    args += [] if far is None else [f"--far={far!r}"]
    err, out = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
        try:
            rc = main(args)
        except SystemExit as e:  # argparse refused a number
            assert e.code == 2 and err.getvalue().startswith("usage:")
            return
    lines = err.getvalue().splitlines()
    if rc == 0:
        import json

        plan = json.loads(out.getvalue())
        assert math.isfinite(plan["baseline_mm"]) and plan["baseline_mm"] > 0
        lo, hi = plan["disparity_range"]
        assert 0 <= lo <= hi <= 509 and plan["disparity_px"] >= 1
        assert lines == []
    else:
        assert rc == 2 and len(lines) == 1 and lines[0].startswith("robostereo: error: ")


class _Points:
    def __init__(self, world: Any, z_bound: Any) -> None:
        self.world, self.z_bound = world, z_bound


point_sets = st.integers(0, 12).flatmap(lambda n: st.tuples(
    hnp.arrays(np.float64, st.sampled_from([(n, 3), (n, 3), (n, 2), (n,)]),
               elements=st.one_of(st.floats(-1e3, 1e3), any_float)),
    hnp.arrays(np.float64, st.sampled_from([(n,), (n,), (n + 1,)]),
               elements=st.one_of(st.floats(0, 10), any_float))))


@given(a=point_sets, b=point_sets, merge=st.one_of(st.floats(0.01, 10), numbers))
def test_fuse_located(a, b, merge) -> None:
    from robostereo.robot.planning import fuse_located

    fused = _expect(fuse_located, _Points(*a), _Points(*b), merge_mm=merge)
    if fused is not None:
        assert np.isfinite(fused.world).all() and np.isfinite(fused.z_bound).all()
        assert len(fused) + fused.duplicates == len(a[0]) + len(b[0])


@given(image=images(), crossing=st.one_of(st.just(30.0), numbers),
       threshold=st.one_of(st.just(8.0), numbers))
def test_best_baseline_direction(image, crossing, threshold) -> None:
    from robostereo.robot.planning import best_baseline_direction

    bd = _expect(best_baseline_direction, image, min_crossing_deg=crossing, threshold=threshold)
    if bd is not None:
        assert 0 <= bd.direction_deg < 180 and 0 <= bd.matchable_fraction <= 1 + 1e-9


@given(q=hnp.arrays(np.float64, 4, elements=st.floats(-1, 1)).filter(
           lambda v: np.linalg.norm(v) > 0.1),
       decimals=st.integers(1, 9), scale=st.sampled_from([1.0, 1.0, 1.0005, 1.5, 0.9]))
def test_pose_quaternions(q, decimals, scale) -> None:
    """Printed with few decimals (or scaled): normalised with a warning within 1e-3 of
    unit norm, refused beyond, never silently wrong."""
    import warnings

    from robostereo.errors import PlausibilityWarning
    from robostereo.geometry.poses import QUATERNION_TOLERANCE, pose_from_dict

    printed = np.round(q / np.linalg.norm(q) * scale, decimals)
    n = float(np.linalg.norm(printed))
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        T = _expect(pose_from_dict, {"position": [1, 2, 3], "quaternion": printed.tolist()},
                    source="p.yaml")
    if abs(n - 1) > QUATERNION_TOLERANCE:
        assert T is None
        return
    assert T is not None
    noted = [w for w in rec if issubclass(w.category, PlausibilityWarning)]
    assert bool(noted) == (abs(n - 1) > 1e-6)
    assert np.allclose(T.quaternion, np.sign(printed[3] or 1) * printed / n, atol=1e-9) or \
        np.allclose(T.quaternion, -np.sign(printed[3] or 1) * printed / n, atol=1e-9)


@hypothesis.settings(max_examples=6, deadline=None)
@given(delay=st.floats(0.0, 0.4), sig=st.sampled_from(["SIGTERM", "SIGINT"]))
def test_interrupted_command_leaves_no_output(delay, sig, tmp_path_factory) -> None:
    """A command interrupted at a random moment of its work (counted from when its
    matcher threads start, so that the moments fall in the matching and the writing,
    not in Python's start-up): either it finished (exit 0, whole outputs) or it stopped
    (130/143, one line, no output and no .part at all).  An interrupt that lands after
    the outputs were renamed into place, while the command prints its summary, stops it
    with 130/143 and the outputs whole: never some of them, never a .part."""
    import os
    import signal
    import subprocess
    import time

    d = tmp_path_factory.mktemp("sig")
    left, right, _ = synthetic_pair(np.random.default_rng(1), height=480, width=640)
    cv2.imwrite(str(d / "l.png"), left)
    cv2.imwrite(str(d / "r.png"), right)
    src = Path(__file__).resolve().parents[1] / "src"
    p = subprocess.Popen(
        [sys.executable, "-m", "robostereo.cli", "match", str(d / "l.png"), str(d / "r.png"),
         "--min-disparity", "0", "--max-disparity", "32", "-o", str(d / "m.csv"),
         "--edges", str(d / "e.csv")],
        env={**os.environ, "PYTHONPATH": str(src), "ROBOSTEREO_THREADS": "2",
             **{k: "1" for k in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS",
                                 "MKL_NUM_THREADS")}},
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    while p.poll() is None and len(os.listdir(f"/proc/{p.pid}/task")) < 2:
        time.sleep(0.002)  # the matcher's pool is up: the work has begun
    time.sleep(delay)
    p.send_signal(getattr(signal, sig))
    _, err = p.communicate(timeout=120)
    names = sorted(q.name for q in d.iterdir())
    whole, none = ["e.csv", "l.png", "m.csv", "r.png"], ["l.png", "r.png"]
    hypothesis.event(f"exit {p.returncode}")
    if p.returncode == 0:
        assert names == whole
    elif p.returncode in (130, 143):
        assert names in (none, whole), names
        assert len(err.splitlines()) == 1 and err.startswith("robostereo: ")
    else:  # after the command had returned (its outputs whole): killed on the way out
        assert p.returncode in (-signal.SIGINT, -signal.SIGTERM), (p.returncode, err)
        assert names in (whole, none), names
