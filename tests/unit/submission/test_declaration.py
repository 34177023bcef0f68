"""The duration to declare: a high quantile of the initializer plus the experiment, and its line in the header."""

from __future__ import annotations

from dataclasses import replace

import pytest

from robotarium_exp.initializer import InitializerSample
from submission.declaration import DECLARE_QUANTILE, FULL_BUILD_INITIALIZER_SEEDS, Declaration, declare
from submission.errors import CheckError


def test_the_declared_duration_covers_a_high_quantile_of_the_initializer() -> None:
    """Synthetic samples: the 99.5 % quantile plus the experiment, rounded up to 10 s; risks as measured shares."""
    spread = InitializerSample(tuple(float(k) for k in range(1, 201)), ())
    plain = declare(spread, experiment_s=30.0)
    assert plain.quantile_s == 200.0 and plain.duration_s == 230 and plain.overrun_share == 0.0  # 200: the longest
    heavy = declare(InitializerSample((10.0,) * 190 + (500.0,) * 10, ()), experiment_s=30.0)
    assert heavy.duration_s == 530  # a tail over 0.5 % is covered, not averaged away
    tail = declare(InitializerSample((10.0,) * 399 + (2000.0,), ()), experiment_s=30.0)
    assert tail.duration_s == 40 and tail.overrun_share == pytest.approx(0.0025)  # beyond 1.5 x 40 s: reported
    stuck = declare(InitializerSample((10.0,) * 399, (5,)), experiment_s=30.0)
    assert stuck.stuck_share == pytest.approx(0.0025) and stuck.overrun_share == pytest.approx(0.0025)
    with pytest.raises(CheckError, match=r'3 of 200 initializations did not finish .* change the initial'):
        declare(InitializerSample((10.0,) * 197, (1, 2, 3)), experiment_s=30.0)


def test_an_empty_sample_declares_nothing() -> None:
    with pytest.raises(CheckError, match='the initializer sample is empty'):
        declare(InitializerSample((), ()), experiment_s=30.0)


def test_the_header_lines_read_back_as_the_same_declaration() -> None:
    declaration = Declaration(230, 199.5, 30.25, 200, 0.005, 0.0)
    lines = declaration.header_lines(6)
    assert lines[0] == 'Declare on the web form: 6 robots and 230 s, derived by `vtube submission check`'
    assert lines[1] == f'from {declaration.basis()}.'
    assert declaration.basis() == (
        f'initializer {DECLARE_QUANTILE:.1%} over 200 seeds 199.5 s + experiment 30.2 s; overruns 0.5%, stuck 0.0%'
    )
    text = '"""\n' + '\n'.join(lines) + '\n"""\n'
    assert Declaration.from_header(text) == Declaration(230, 199.5, 30.2, 200, 0.005, 0.0)  # as printed: 0.1 s
    assert Declaration.from_header('no declaration here') is None


def test_a_declaration_from_fewer_seeds_than_a_full_build_marks_the_file_not_for_upload() -> None:
    """The mark comes first and says why; the declaration below it reads back the same; a full build has none."""
    preview = Declaration(130, 81.6, 43.5, FULL_BUILD_INITIALIZER_SEEDS - 1, 0.0, 0.0)
    lines = preview.header_lines(6)
    assert not preview.for_upload and lines[:2] == preview.not_for_upload()
    assert lines[0] == 'NOT FOR UPLOAD: this duration rests on 199 initializer seeds, not the 200 of a full build'
    assert 'the command under "Rebuild with" below builds the file to upload' in lines[1]
    assert lines[2].startswith('Declare on the web form: 6 robots and 130 s') and len(lines) == 4
    assert Declaration.from_header('"""\n' + '\n'.join(lines) + '\n"""\n') == preview
    full = replace(preview, runs=FULL_BUILD_INITIALIZER_SEEDS)
    assert full.for_upload and full.not_for_upload() == [] and full.header_lines(6)[0].startswith('Declare on')
