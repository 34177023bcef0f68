"""Swarm parameters: Table 1 defaults, derived quantities recomputed by hand, validation."""

from __future__ import annotations

import math

import pytest

from vtube_planning.errors import ParamsError
from vtube_planning.params import PlanningOptions, SwarmParams


def test_defaults_are_table_1() -> None:
    p = SwarmParams()
    table = (20, 2.0, 5.0, 1.0, 1.0, 0.3, 0.4, 0.8, 0.1989, 0.9974)
    assert (
        p.n_robots,
        p.v_min_mps,
        p.v_max_mps,
        p.a_v_mps2,
        p.a_n_mps2,
        p.r_p_m,
        p.r_s_m,
        p.r_a_m,
        p.rho_d_per_m2,
        p.rho_max_per_m2,
    ) == table


def test_derived_quantities_of_table_1() -> None:
    p = SwarmParams()
    assert p.n_side == 5
    # (p8) by hand: sqrt(2) * 20 * 5 / (4 * 5^3 * 0.8^3), magnitude (resolution A2)
    assert p.a_rho == pytest.approx(141.42135623730951 / 256.0, rel=1e-15)
    assert p.a_rho == pytest.approx(0.5524, abs=5e-5)
    assert p.rho_packing == pytest.approx(20.0 / 64.0)  # 0.3125, docs/theory.md §7.1


def test_rho_max_variants_explain_table_1() -> None:
    variants = SwarmParams().rho_max_variants()
    assert variants['table'] == 0.9974
    assert variants['printed_formula'] == pytest.approx(1.0 / 0.09)  # 11.11, not the table's value
    assert variants['square_safety'] == pytest.approx(1.5625)
    assert variants['square_physical'] == pytest.approx(1.0 / 0.36)
    assert variants['circle_safety'] == pytest.approx(0.99472, abs=5e-6)
    # the table's rho_d is the circle formula over five, to the printed four digits
    assert round(variants['circle_safety'] / 5, 4) == SwarmParams().rho_d_per_m2


@pytest.mark.parametrize(('n', 'side'), [(1, 1), (2, 2), (4, 2), (5, 3), (16, 4), (17, 5), (20, 5), (25, 5), (26, 6)])
def test_n_side_is_ceil_sqrt(n: int, side: int) -> None:
    assert SwarmParams(n_robots=n).n_side == side == math.ceil(math.sqrt(n))


@pytest.mark.parametrize(
    ('kwargs', 'match'),
    [
        ({'v_min_mps': 6.0}, r'v_min_mps \(6.0\) exceeds v_max_mps \(5.0\)'),
        ({'r_s_m': 0.2}, r'r_p <= r_s <= r_a; got r_p_m=0.3, r_s_m=0.2'),
        ({'r_a_m': 0.35}, 'r_p <= r_s <= r_a'),
        ({'n_robots': 0}, 'n_robots must be an integer >= 1; got 0'),
        ({'n_robots': 2.5}, 'n_robots must be an integer'),
        ({'n_robots': True}, 'n_robots must be an integer'),
        ({'a_v_mps2': -1.0}, 'a_v_mps2 must be a finite number > 0; got -1.0'),
        ({'a_n_mps2': float('nan')}, 'a_n_mps2 must be a finite number > 0'),
        ({'v_max_mps': '5'}, "v_max_mps must be a finite number > 0; got '5'"),
        ({'rho_d_per_m2': 2.0}, r'rho_d_per_m2 \(2.0\) exceeds rho_max_per_m2'),
    ],
)
def test_invalid_swarm_params_raise(kwargs: dict, match: str) -> None:
    with pytest.raises(ParamsError, match=match):
        SwarmParams(**kwargs)


def test_params_error_is_a_value_error() -> None:
    with pytest.raises(ValueError):
        SwarmParams(n_robots=-3)


@pytest.mark.parametrize(
    ('kwargs', 'match'),
    [
        ({'grid_step_m': 0.0}, 'grid_step_m must be a finite number > 0'),
        ({'lookahead_m': -1.0}, 'lookahead_m must be a finite number > 0'),
        ({'v0_mps': 0.0}, 'v0_mps'),
        ({'density_weight': -0.1}, 'density_weight must be a finite number >= 0'),
        ({'predictive_model': 'magic'}, "predictive_model must be one of \\('local_width', 'rigid_shift', 'none'\\)"),
    ],
)
def test_invalid_planning_options_raise(kwargs: dict, match: str) -> None:
    with pytest.raises(ParamsError, match=match):
        PlanningOptions(**kwargs)


def test_planning_options_accept_unset_initial_conditions_and_zero_weight() -> None:
    options = PlanningOptions(density_weight=0.0)
    assert options.v0_mps is None and options.rho0_per_m2 is None
