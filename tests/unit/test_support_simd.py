"""The suite's numpy dispatch pinned to the golden file's (`tests.support.simd`): what a machine dispatches beyond the
golden environment, from a golden file that lists it all, none, or nothing readable."""

from __future__ import annotations

import json

from tests.support.simd import beyond_golden


def _golden(tmp_path, simd: str):
    path = tmp_path / 'golden.json'
    path.write_text(json.dumps({'environment': {'numpy_simd': simd}}), encoding='utf-8')
    return path


def test_the_features_beyond_the_golden_environment_are_those_it_lacks(tmp_path) -> None:
    from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__

    available = [name for name in __cpu_dispatch__ if __cpu_features__.get(name)]
    assert beyond_golden(_golden(tmp_path, ' '.join(available))) == ''
    assert beyond_golden(_golden(tmp_path, '')).split() == available
    assert beyond_golden(tmp_path / 'missing.json') == ''
    (tmp_path / 'bad.json').write_text('{"environment": {}}', encoding='utf-8')
    assert beyond_golden(tmp_path / 'bad.json') == ''
