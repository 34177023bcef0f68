"""StepParams and the modes it chooses between: the tuples of choices are the Literal types' values."""

from __future__ import annotations

import dataclasses
from typing import get_args

import pytest

from vtube_planning.onboard.params import (
    DENSITY_PADDINGS,
    KDTREE_ABOVE,
    LAWS,
    PLAN_AT,
    SATURATIONS,
    DensityPadding,
    Law,
    PlanAt,
    Saturation,
    StepParams,
)


def test_the_choices_are_the_literal_values() -> None:
    assert LAWS == get_args(Law) == ('practical', 'barrier')
    assert DENSITY_PADDINGS == get_args(DensityPadding) == ('initial', 'current')
    assert SATURATIONS == get_args(Saturation) == ('radial', 'forward')
    assert PLAN_AT == get_args(PlanAt) == ('robot', 'center')


def test_defaults_are_the_papers_law_and_the_measured_crossover() -> None:
    p = StepParams(r_s_m=0.4, r_a_m=0.8, r_a_max_m=2.0, v_min_mps=2.0, v_max_mps=5.0)
    assert (p.law, p.saturation, p.density_padding, p.plan_at) == ('barrier', 'radial', 'initial', 'robot')
    assert (p.avoidance_gain, p.keeping_gain, p.k_ra_m3ps, p.feedforward) == (1.0, 1.0, 5.0, False)
    assert p.kdtree_above == KDTREE_ABOVE == 64


def test_step_params_are_frozen_and_compare_by_value() -> None:
    a = StepParams(r_s_m=0.4, r_a_m=0.8, r_a_max_m=2.0, v_min_mps=2.0, v_max_mps=5.0)
    assert a == dataclasses.replace(a) and hash(a) == hash(dataclasses.replace(a))
    assert a != dataclasses.replace(a, law='practical')
    with pytest.raises(dataclasses.FrozenInstanceError):
        a.r_s_m = 0.5  # type: ignore[misc]
