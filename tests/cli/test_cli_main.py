"""The ``robostereo`` entry point: the commands, one module each, ``python -m
robostereo.cli``."""

from __future__ import annotations

import argparse
import subprocess
import sys

import pytest

from robostereo.cli import build_parser, main

#: the commands in the order ``robostereo --help`` lists them
COMMANDS = ["match", "rig", "evaluate", "batch", "demo", "capture", "import", "locate",
            "handeye", "simulate-handeye", "plan"]


def _subcommands() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices)


#: the module that holds each command
MODULES = {"match": "match", "rig": "rig_command", "evaluate": "evaluate",
           "batch": "batch_command", "demo": "demo", "capture": "capture_command",
           "import": "import_command",
           "locate": "locate", "handeye": "handeye_commands",
           "simulate-handeye": "handeye_commands", "plan": "plan"}


def test_the_parser_registers_every_command_in_order() -> None:
    assert list(_subcommands()) == COMMANDS


def test_each_command_is_handled_by_its_own_module() -> None:
    for name, parser in _subcommands().items():
        handler = parser.get_default("handler")
        assert handler.__module__ == f"robostereo.cli.{MODULES[name]}", (name, handler)


def test_no_command_is_a_usage_error(capsys) -> None:
    with pytest.raises(SystemExit) as exc:
        main([])
    assert exc.value.code == 2
    assert capsys.readouterr().err.splitlines()[-1] == (
        "robostereo: error: the following arguments are required: COMMAND")


def test_python_dash_m_runs_the_command_line() -> None:
    r = subprocess.run([sys.executable, "-m", "robostereo.cli", "plan", "--depth", "500",
                        "--accuracy", "0.5", "--json"],
                       capture_output=True, text=True, check=False, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith('{"baseline_mm": 131.3333')
