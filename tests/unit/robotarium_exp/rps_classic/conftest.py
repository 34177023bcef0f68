"""Fixtures of the classic generation's tests."""

from __future__ import annotations

import numpy as np
import pytest

from robotarium_exp.rps_classic import robotarium_abc


@pytest.fixture(autouse=True)
def fresh_counters():
    """Classic shares its counters across instances; each test starts from none and leaves none behind."""
    robotarium_abc.SHARED_ERRORS.clear()
    yield
    robotarium_abc.SHARED_ERRORS.clear()


@pytest.fixture
def states() -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(7)
    x = np.vstack([rng.uniform(-1, 1, (2, 9)), rng.uniform(-np.pi, np.pi, 9)])
    goals = np.vstack([rng.uniform(-1, 1, (2, 9)), rng.uniform(-np.pi, np.pi, 9)])
    return x, goals
