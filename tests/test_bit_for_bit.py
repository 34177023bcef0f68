"""Every case of :mod:`tests.bit_for_bit` flies the bits of the committed reference, tests/bit_for_bit.json.

Bits are defined for one environment (the reference's key): elsewhere each case is skipped, naming the difference.
"""

from __future__ import annotations

import pytest

from tests.bit_for_bit import CASES, Case, differences, environment_differences, fingerprint, load_reference

REFERENCE = load_reference()


def test_every_reference_case_is_a_case() -> None:
    assert sorted(REFERENCE['cases']) == sorted(case.name for case in CASES)


@pytest.mark.parametrize(
    'case', [pytest.param(case, id=case.name, marks=[pytest.mark.slow] if case.slow else []) for case in CASES]
)
def test_the_same_bits_as_the_reference(case: Case) -> None:
    changed = environment_differences(REFERENCE['environment'])
    if changed:
        pytest.skip(f'the reference bits were written in another environment: {changed}')
    found, _ = differences(REFERENCE['cases'][case.name], fingerprint(case)[0])
    assert not found, f'{case.name} flies other bits:\n' + '\n'.join(found)
