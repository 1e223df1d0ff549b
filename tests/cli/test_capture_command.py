"""``robostereo capture``: an option given where it does not apply is refused (one line,
exit 2, nothing written), at any value, its default too; the options that do apply to
``--views`` change the views."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from robostereo.cli import main
from robostereo.robot.views.views_folder import read_views_capture


def _refused(args: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> str:
    rc = main(["capture", "--out", str(tmp_path / "c"), *args])
    out, err = capsys.readouterr()
    assert rc == 2 and out == "", (rc, out, err)
    assert len(err.splitlines()) == 1 and err.startswith("robostereo: error: "), err
    assert list(tmp_path.iterdir()) == []  # no folder, no temporary one
    return err.strip()


@pytest.mark.parametrize(("extra", "words"), [
    # --baseline with --views was ignored at 20, its default: any value is refused now
    (["--views", "3", "--baseline", "20"], "--baseline is for two views; with --views give "
                                           "--span"),
    (["--views", "3", "--span", "40", "--baseline", "35"], "--baseline is for two views"),
    (["--pattern", "arc", "--views", "3", "--baseline", "20"], "--baseline is for two views"),
    # the other robot's options, at their defaults too
    (["--views", "3", "--tilt", "25"], "--tilt and --handeye are for --robot six-axis"),
    (["--tilt", "25"], "--tilt and --handeye are for --robot six-axis"),
    (["--handeye", "camera.yaml"], "--tilt and --handeye are for --robot six-axis"),
    (["--robot", "six-axis", "--direction", "0"],
     "--direction, --roll and --center are for --robot adeptone"),
    (["--robot", "six-axis", "--roll", "0", "--center", "400", "0"],
     "--direction, --roll and --center are for --robot adeptone"),
    (["--robot", "six-axis", "--views", "3", "--roll", "0"],
     "are for --robot adeptone; the six-axis arm takes --tilt"),
    (["--robot", "six-axis", "--views", "3", "--center", "400", "0"],
     "are for --robot adeptone; the six-axis arm takes --tilt"),
])
def test_an_option_that_does_not_apply_is_refused_even_at_its_default(extra, words, tmp_path,
                                                                      capsys):
    assert words in _refused(extra, tmp_path, capsys)


def test_direction_and_roll_apply_to_views_on_the_adeptone(tmp_path):
    """--direction turns the whole set-up (the views' line with it), --roll the camera
    and its pattern together: both reach the views, as the help says."""
    caps = {}
    for name, extra in [("plain", []), ("direction", ["--direction", "30"]),
                        ("roll", ["--roll", "30"])]:
        d = tmp_path / name
        assert main(["capture", "--views", "2", "--span", "40", "--out", str(d), *extra]) == 0
        caps[name] = read_views_capture(d)
    for name, cap in caps.items():
        c = cap.centres
        along = math.degrees(math.atan2(c[1][1] - c[0][1], c[1][0] - c[0][0]))
        assert along == pytest.approx(0.0 if name == "plain" else 30.0, abs=1e-6), name
        scene = yaml.safe_load((tmp_path / name / "capture.yaml").read_text())["scene"]
        assert scene["direction_deg"] == (30.0 if name == "direction" else 0.0)
        assert scene["roll_deg"] == (30.0 if name == "roll" else 0.0)
    # the set-up turned whole: the same images but for rendering's rounding (0.14 grey
    # levels); the camera turned against the block: other images (1.6 grey levels)
    for k in range(2):
        plain = caps["plain"].images[k].astype(int)
        assert np.abs(caps["direction"].images[k] - plain).mean() < 0.4
        assert np.abs(caps["roll"].images[k] - plain).mean() > 1.0


def test_a_six_axis_baseline_of_20_is_20_not_its_default_40(tmp_path):
    from robostereo.robot.capture import read_capture

    for extra, want in [([], 40.0), (["--baseline", "20"], 20.0)]:
        d = tmp_path / f"six{len(extra)}"
        assert main(["capture", "--robot", "six-axis", "--out", str(d), *extra]) == 0
        # (the tilted camera's optical centres stand a little further apart: 20.6, 40.3)
        assert read_capture(d).epipolar.baseline_mm == pytest.approx(want, rel=0.05)


def test_a_capture_with_a_calibrated_hand_eye_carries_its_sigma_in_every_bound(
        tmp_path, capsys):
    """``capture --handeye``: the calibration's hand_eye_sigma (three times its rotation)
    is written as ``uncertainty: hand_eye_deg``, and locate's bounds grow by Z tan of it;
    a file without it records none."""
    from robostereo.robot.capture import locate, read_capture
    from robostereo.robot.handeye import write_views
    from robostereo.robot.simulated.sixaxis_handeye import simulate_handeye_views

    views, _ = simulate_handeye_views(views=8, seed=2)
    write_views(tmp_path / "hv", views)
    assert main(["handeye", str(tmp_path / "hv"), "-o", str(tmp_path / "cam.yaml")]) == 0
    sigma = yaml.safe_load((tmp_path / "cam.yaml").read_text())["hand_eye_sigma"]
    assert 0 < sigma["rotation_deg"] < 0.1
    assert main(["capture", "--robot", "six-axis", "--handeye", str(tmp_path / "cam.yaml"),
                 "--out", str(tmp_path / "cap")]) == 0
    assert "its rotation may be off by 3 x" in capsys.readouterr().out
    spec = yaml.safe_load((tmp_path / "cap" / "capture.yaml").read_text())
    assert spec["uncertainty"]["hand_eye_deg"] == pytest.approx(3 * sigma["rotation_deg"])
    cap = read_capture(tmp_path / "cap")
    bare = dataclasses.replace(cap, hand_eye_uncertainty_deg=0.0)
    with_it, without = locate(cap), locate(bare)
    z = without.epipolar_xyz[:, 2]
    np.testing.assert_allclose(with_it.z_bound - without.z_bound,
                               z * math.tan(math.radians(3 * sigma["rotation_deg"])),
                               rtol=0.02)
    # a camera file without hand_eye_sigma records no such uncertainty
    data = yaml.safe_load((tmp_path / "cam.yaml").read_text())
    del data["hand_eye_sigma"]
    (tmp_path / "old.yaml").write_text(yaml.safe_dump(data))
    assert main(["capture", "--robot", "six-axis", "--handeye", str(tmp_path / "old.yaml"),
                 "--out", str(tmp_path / "cap2")]) == 0
    spec = yaml.safe_load((tmp_path / "cap2" / "capture.yaml").read_text())
    assert "hand_eye_deg" not in spec.get("uncertainty", {})
