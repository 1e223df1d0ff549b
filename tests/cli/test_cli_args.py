"""The argument types and checks that the commands share (``robostereo.cli._args``):
each refuses a bad value with the same message and exit code on every command."""

from __future__ import annotations

import argparse
from pathlib import Path

import pytest

from robostereo.cli import build_parser, main
from robostereo.cli._args import (
    finite,
    require_at_least,
    require_empty_folder,
    require_output_folder,
    require_positive,
    require_seed,
    unit_interval,
)
from robostereo.errors import InputError

#: every command (and robot) that takes --seed, with the arguments it needs besides
SEEDED = {
    "demo": ["demo", "--out", "{tmp}/out"],
    "demo six-axis": ["demo", "--robot", "six-axis", "--out", "{tmp}/out"],
    "capture": ["capture", "--out", "{tmp}/out"],
    "capture six-axis": ["capture", "--robot", "six-axis", "--out", "{tmp}/out"],
    "simulate-handeye": ["simulate-handeye", "--out", "{tmp}/out"],
}


def _refused(args: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> str:
    """Run the command line on `args`; check exit code 2, no output and no file written;
    return the one error line."""
    before = sorted(tmp_path.rglob("*"))
    rc = main([a.replace("{tmp}", str(tmp_path)) for a in args])
    out, err = capsys.readouterr()
    assert rc == 2 and out == ""
    assert len(err.splitlines()) == 1 and err.startswith("robostereo: error: "), err
    assert sorted(tmp_path.rglob("*")) == before
    return err.rstrip("\n")


def _usage_error(args: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    """Run the command line on `args`; check that argparse refuses them with exit code 2;
    return the last line (argparse's error line)."""
    with pytest.raises(SystemExit) as exc:
        main(args)
    assert exc.value.code == 2
    return capsys.readouterr().err.strip().splitlines()[-1]


def _commands_with(option: str) -> set[str]:
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    return {name for name, p in sub.choices.items()
            if any(option in a.option_strings for a in p._actions)}


# -- the seed --------------------------------------------------------------------------


def test_every_command_with_a_seed_is_checked_here() -> None:
    assert _commands_with("--seed") == {args[0] for args in SEEDED.values()}


@pytest.mark.parametrize("command", SEEDED)
def test_a_negative_seed_is_refused_alike_by_every_command(command, tmp_path, capsys) -> None:
    err = _refused([*SEEDED[command], "--seed", "-1"], tmp_path, capsys)
    assert err == "robostereo: error: --seed must be >= 0, got -1"


def test_require_seed_takes_zero_and_refuses_below() -> None:
    require_seed(0)
    require_seed(12345)
    with pytest.raises(InputError, match=r"^--seed must be >= 0, got -7$"):
        require_seed(-7)


# -- whole numbers with a least value, positive numbers --------------------------------


def test_counts_below_their_least_value_are_refused(tmp_path, capsys) -> None:
    err = _refused(["simulate-handeye", "--out", "{tmp}/out", "--views", "2"], tmp_path, capsys)
    assert err == "robostereo: error: --views must be >= 3, got 2"
    (tmp_path / "in").mkdir()
    err = _refused(["batch", "{tmp}/in", "--out", "{tmp}/out", "--workers", "0"], tmp_path,
                   capsys)
    assert err == "robostereo: error: --workers must be >= 1, got 0"
    require_at_least("--views", 3, 3)


def test_a_baseline_that_is_not_positive_is_refused(tmp_path, capsys) -> None:
    for value in ("0", "-1"):
        err = _refused(["capture", "--robot", "six-axis", "--out", "{tmp}/out", "--baseline",
                        value], tmp_path, capsys)
        assert err == f"robostereo: error: --baseline must be > 0, got {float(value)}"
    require_positive("--baseline", 1e-9)
    with pytest.raises(InputError, match="got nan"):
        require_positive("--baseline", float("nan"))


# -- output folders --------------------------------------------------------------------

#: the commands that create a folder, with the arguments they need besides --out
FOLDER_MAKERS = {
    "capture": ["capture"],
    "capture six-axis": ["capture", "--robot", "six-axis"],
    "simulate-handeye": ["simulate-handeye"],
}


@pytest.mark.parametrize("command", FOLDER_MAKERS)
def test_a_new_folder_must_be_new_or_empty_with_a_parent(command, tmp_path, capsys) -> None:
    full = tmp_path / "full"
    full.mkdir()
    (full / "f.txt").write_text("x")
    afile = tmp_path / "afile"
    afile.write_text("x")
    for out, message in [
        (full, f"{full}: exists and is not an empty folder"),
        (afile, f"{afile}: exists and is not an empty folder"),
        (tmp_path / "no" / "out", f"{tmp_path / 'no' / 'out'}: parent folder "
                                  f"{tmp_path / 'no'} does not exist"),
    ]:
        err = _refused([*FOLDER_MAKERS[command], "--out", str(out)], tmp_path, capsys)
        assert err == f"robostereo: error: {message}"


def test_require_empty_folder_takes_a_new_or_an_empty_folder(tmp_path: Path) -> None:
    require_empty_folder(tmp_path / "new")
    require_empty_folder(tmp_path)
    with pytest.raises(InputError, match="exists and is not an empty folder"):
        require_empty_folder(Path(__file__))


def test_an_output_file_needs_its_folder(tmp_path, capsys) -> None:
    missing = tmp_path / "no" / "camera.yaml"
    err = _refused(["handeye", str(tmp_path), "-o", str(missing)], tmp_path, capsys)
    assert err == f"robostereo: error: {missing}: output folder {missing.parent} does not exist"
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    for option in ("-o", "--ply"):
        missing = tmp_path / "no" / "fused.out"
        err = _refused(["locate", str(tmp_path / "a"), "--fuse", str(tmp_path / "b"), option,
                        str(missing)], tmp_path, capsys)
        assert err == (f"robostereo: error: {option} {missing}: output folder "
                       f"{missing.parent} does not exist")
    require_output_folder(Path("here.csv"))  # the working folder


# -- argparse types --------------------------------------------------------------------


def test_finite_refuses_words_nan_inf_and_values_over_its_limit() -> None:
    parse = finite("--lift", 1e6)
    assert parse("79.65") == 79.65 and parse("-1e6") == -1e6
    for text, message in [("abc", "--lift must be a number, got 'abc'"),
                          ("nan", "--lift must be finite, got 'nan'"),
                          ("-inf", "--lift must be finite, got '-inf'"),
                          ("1e7", "--lift must be within +-1e+06, got '1e7'")]:
        with pytest.raises(argparse.ArgumentTypeError) as exc:
            parse(text)
        assert str(exc.value) == message
    assert finite("--threshold")("1e300") == 1e300  # no limit unless one is given


def test_unit_interval_takes_zero_to_one() -> None:
    parse = unit_interval("--min-confidence")
    assert parse("0") == 0.0 and parse("1") == 1.0 and parse("0.95") == 0.95
    for text, word in [("1.5", "in 0..1"), ("-0.1", "in 0..1"), ("nan", "finite"),
                       ("x", "a number")]:
        with pytest.raises(argparse.ArgumentTypeError, match=word):
            parse(text)


@pytest.mark.parametrize("command", ["match", "rig", "evaluate"])
def test_the_matcher_options_are_checked_alike_by_every_matching_command(
        command, capsys) -> None:
    needs = {"match": ["match", "l.png", "r.png", "--min-disparity", "0", "--max-disparity",
                       "8", "-o", "m.csv"],
             "rig": ["rig", "l.png", "r.png", "--calibration", "c.yaml", "-o", "m.csv"],
             "evaluate": ["evaluate", "scene"]}[command]
    assert _commands_with("--min-confidence") == {"match", "rig", "evaluate"}
    err = _usage_error([*needs, "--min-confidence", "2"], capsys)
    assert err == (f"robostereo {command}: error: argument --min-confidence: "
                   "--min-confidence must be in 0..1, got '2'")
    err = _usage_error([*needs, "--method", "sgm"], capsys)
    assert err.startswith(f"robostereo {command}: error: argument --method: invalid choice")


def test_a_number_option_names_itself_in_the_usage_error(capsys) -> None:
    err = _usage_error(["capture", "--out", "x", "--lift", "nan"], capsys)
    assert err == "robostereo capture: error: argument --lift: --lift must be finite, got 'nan'"
    err = _usage_error(["evaluate", "scene", "--scale", "ten"], capsys)
    assert err == ("robostereo evaluate: error: argument --scale: --scale must be a number, "
                   "got 'ten'")
