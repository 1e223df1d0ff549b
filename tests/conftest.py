"""Shared fixtures: the real scenes of ../shared/data/stereo (or $ROBOSTEREO_DATA)."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

from robostereo.datasets import StereoScene, available_scenes, find_data_dir, load_scene
from robostereo.simulation.occluders import OccluderPair, occluder_pair


@pytest.fixture(scope="session")
def data_dir() -> Path:
    d = find_data_dir()
    if d is None:
        pytest.skip("real stereo data not found (../shared/data/stereo or $ROBOSTEREO_DATA)")
    return d


@pytest.fixture(scope="session")
def real_scenes(data_dir: Path) -> dict[str, StereoScene]:
    return {name: load_scene(data_dir / name) for name in available_scenes(data_dir)}


@pytest.fixture(scope="session")
def held_out_occluders() -> list[OccluderPair]:
    """Occluder pairs 40-42: seeds no default was chosen on (made once, about 1 s each)."""
    return [occluder_pair(seed) for seed in (40, 41, 42)]


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261122)


# -- hypothesis profiles (tests/test_properties.py) --------------------------------------
# "fast" (default): a few cases per property, derandomised, in the normal test run.
# "long": ROBOSTEREO_HYPOTHESIS=long python -m pytest tests/test_properties.py
#         --hypothesis-show-statistics   (>= 10 000 cases; see docs/guide/development.md)
try:
    from datetime import timedelta

    from hypothesis import HealthCheck, settings

    _common = dict(
        deadline=timedelta(seconds=30),  # a case that takes this long counts as a hang
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                               HealthCheck.filter_too_much],
    )
    settings.register_profile("fast", max_examples=50, derandomize=True, database=None,
                              **_common)
    settings.register_profile("long", max_examples=1200, **_common)
    settings.load_profile(os.environ.get("ROBOSTEREO_HYPOTHESIS", "fast"))
except ImportError:  # pragma: no cover - hypothesis is in the test extra
    pass
