"""The bounded YAML loader: alias bombs, recursive aliases, huge integers, deep nesting."""

from __future__ import annotations

import time
import tracemalloc

import pytest
import yaml

from robostereo.errors import InputError
from robostereo.io.yaml_loading import MAX_ALIAS_NODES, load_yaml


def _bomb(levels: int = 9) -> str:
    text = "a0: &a0 [x, x, x, x, x, x, x, x, x]\n"
    for i in range(1, levels):
        text += f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 9)}]\n"
    return text


def test_an_alias_bomb_is_refused_in_one_line_quickly_and_in_little_memory() -> None:
    text = _bomb() + "camera: *a8\n"
    tracemalloc.start()
    t0 = time.perf_counter()
    with pytest.raises(InputError, match=r"capture.yaml: .*alias bomb") as info:
        load_yaml(text, "capture.yaml")
    seconds = time.perf_counter() - t0
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert "\n" not in str(info.value)
    assert seconds < 1.0 and peak < 20e6


def test_aliases_that_expand_modestly_are_read() -> None:
    data = load_yaml("cam: &c {f: 25}\nviews: [{camera: *c}, {camera: *c}]\n", "a.yaml")
    assert data["views"][1]["camera"] == {"f": 25}
    assert load_yaml(_bomb(levels=5), "a.yaml")["a4"][0][0][0][0] == ["x"] * 9  # 66k nodes
    assert 9**5 < MAX_ALIAS_NODES < 9**6


def test_a_recursive_alias_is_refused() -> None:
    with pytest.raises(InputError, match=r"a.yaml: .*recursive alias"):
        load_yaml("bit_depth: &r [*r]\n", "a.yaml")


def test_an_integer_too_long_to_read_is_refused_in_one_line() -> None:
    with pytest.raises(InputError, match=r"a.yaml: .*number too long"):
        load_yaml("f: " + "9" * 5000 + "\n", "a.yaml")


def test_nesting_too_deep_is_refused_in_one_line() -> None:
    with pytest.raises(InputError, match=r"a.yaml: .*nested too deep"):
        load_yaml("a: " + "[" * 5000 + "]" * 5000 + "\n", "a.yaml")


def test_invalid_yaml_is_left_to_the_reader_to_word() -> None:
    with pytest.raises(yaml.YAMLError):
        load_yaml("a: [1, 2\n", "a.yaml")
