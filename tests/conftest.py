"""Shared fixtures: the real scenes of ../shared/data/stereo (or $ROBOSTEREO_DATA)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

from robostereo.datasets import StereoScene, available_scenes, find_data_dir, load_scene

#: the developer scenes every real-scene test runs on (all of ../shared/data/stereo)
SCENES = ("tsukuba", "venus", "motorcycle", "cloth3", "reindeer", "wood2")


@pytest.fixture(scope="session")
def data_dir() -> Path:
    d = find_data_dir()
    if d is None:
        pytest.skip("real stereo data not found (../shared/data/stereo or $ROBOSTEREO_DATA)")
    return d


@pytest.fixture(scope="session")
def real_scenes(data_dir: Path) -> dict[str, StereoScene]:
    return {name: load_scene(data_dir / name) for name in available_scenes(data_dir)}


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261122)
