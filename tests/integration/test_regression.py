"""The regression harness (:mod:`tests.support.regression`): every case flies the golden metrics and fingerprints of
tests/integration/regression.json in every environment, and its exact bits in the environments the golden file holds
(its own and its variants: other machine kinds).

Regenerate the golden file on purpose only: ``python -m tests.support.regression --write``.
"""

from __future__ import annotations

import copy

import pytest

from tests.support.regression import (
    CASES,
    GAINS,
    TOLERANCE,
    Case,
    changed_gains,
    deviation,
    differences,
    fingerprint,
    golden,
    load_reference,
    ulp_moves,
)

REFERENCE = load_reference()
GOLDEN, BITS = golden(REFERENCE)
GAIN_CASE = 'grid_C_N80_kdtree_first_8s'
"""A short case whose fingerprints every gain of ControlParams changed by 1e-9 moves by 40 x the tolerance or more,
in every environment (``--sensitivity``)."""


def test_every_golden_case_is_a_case() -> None:
    assert sorted(REFERENCE['cases']) == sorted(case.name for case in CASES)


@pytest.mark.parametrize('case', [pytest.param(case, id=case.name) for case in CASES])
def test_no_drift_from_the_golden_file(case: Case) -> None:
    drift = differences(GOLDEN[case.name], fingerprint(case)[0], bits=BITS)
    assert not drift.found, f'{case.name} drifted from the golden file:\n' + '\n'.join(drift.found)


@pytest.mark.parametrize('gain', GAINS)
def test_a_gain_changed_by_1e_9_is_drift(gain: str) -> None:
    (case,) = (c for c in CASES if c.name == GAIN_CASE)
    with changed_gains(lambda name, value: value + 1e-9 * min(1.0, abs(value)) if name == gain else value):
        new, _ = fingerprint(case)
    drift = differences(REFERENCE['cases'][case.name], new, bits=False)
    assert any(line.startswith('fingerprint') for line in drift.found), drift.largest


def test_drift_names_the_metric_or_fingerprint_beyond_the_tolerance() -> None:
    golden = REFERENCE['cases'][GAIN_CASE]
    assert differences(golden, golden).found == []
    moved = copy.deepcopy(golden)
    step = f'step {golden["fingerprints"]["steps"][-1]}'
    moved['fingerprints'][step][3 + 5] += 2 * TOLERANCE * max(1.0, abs(moved['fingerprints'][step][3 + 5]))
    passed = int(golden['scalars']['metrics.robots_passed'])
    moved['scalars']['metrics.robots_passed'] = str(passed + 1)
    found = differences(golden, moved).found
    assert any(line.startswith(f'fingerprint {step} robot 5 x') for line in found), found
    assert f'metric metrics.robots_passed: {passed} -> {passed + 1}' in found
    within = copy.deepcopy(golden)
    within['fingerprints'][step][0] += 0.5 * TOLERANCE * max(1.0, abs(within['fingerprints'][step][0]))
    assert differences(golden, within, bits=False).found == []


@pytest.mark.parametrize(
    ('golden', 'value', 'expected'),
    [(2.0, 2.0, 0.0), (0.5, 0.25, 0.25), (-4.0, -3.0, 0.25), (float('nan'), float('nan'), 0.0)],
)
def test_deviation_is_absolute_below_one_relative_above(golden: float, value: float, expected: float) -> None:
    assert deviation(golden, value) == expected


def test_deviation_of_nan_against_a_number_is_infinite() -> None:
    assert deviation(1.0, float('nan')) == float('inf')
    assert deviation(float('inf'), 1.0) == float('inf')


def test_a_variant_environment_is_compared_with_its_own_records_bit_for_bit() -> None:
    name = GAIN_CASE
    moved = copy.deepcopy(REFERENCE['cases'][name])
    step = f'step {moved["fingerprints"]["steps"][0]}'
    moved['fingerprints'][step][3] += 1e-6
    other = REFERENCE['environment'] | {'numpy_simd': 'X86_V2 X86_V3 X86_V4', 'openblas_core': 'SkylakeX'}
    reference = {**REFERENCE, 'variants': {'other': {'environment': other, 'cases': {name: moved}}}}
    records, bits = golden(reference, here=other)
    assert bits and records[name] is moved and records['plan_C'] is REFERENCE['cases']['plan_C']
    records, bits = golden(reference, here=REFERENCE['environment'])
    assert bits and records[name] is REFERENCE['cases'][name]


def test_elsewhere_what_moved_between_known_environments_is_not_compared() -> None:
    name = GAIN_CASE
    original = REFERENCE['cases'][name]
    moved = copy.deepcopy(original)
    step = f'step {moved["fingerprints"]["steps"][0]}'
    moved['fingerprints'][step][3] += 1e-6
    other = REFERENCE['environment'] | {'openblas_core': 'SkylakeX'}
    reference = {**REFERENCE, 'variants': {'other': {'environment': other, 'cases': {name: moved}}}}
    records, bits = golden(reference, here=REFERENCE['environment'] | {'openblas_core': 'Zen'})
    assert not bits
    assert f'fingerprint {step}' in records[name]['environments']
    assert ulp_moves(original, moved) == {f'fingerprint {step}': records[name]['environments'][f'fingerprint {step}']}
    third = copy.deepcopy(original)
    third['fingerprints'][step][3] -= 1e-6  # a third machine kind, beyond the tolerance where the two known differ
    assert differences(records[name], third, bits=False).found == []
    assert differences(original, third, bits=False).found != []
