"""Fixtures of the Robotarium tests."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from robotarium_exp.rps.utilities import barrier_certificates


@pytest.fixture
def exact_qp() -> Iterator[None]:
    """The certificates solve their QPs exactly (DAQP) during the test, instead of as the testbed does."""
    previous = barrier_certificates.use_qp_solver('exact')
    yield
    barrier_certificates.use_qp_solver(previous)
