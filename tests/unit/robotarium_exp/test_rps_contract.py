"""The contract with the official simulators' utilities: every call gets the official's answer, or its exception.

``rps_contract.json`` is the table, recorded from the official sources (V2 and classic, commits named in the file)
and kept here as data; ``public`` lists every public function of the official ``rps.utilities`` modules of each
generation (found by introspection). Each row is a call of a utility (an expression over the ``rps.utilities``
modules and ``np``): in ``v2`` and ``classic``, the name of the exception the official raised and its message; in
``*_edges``, the official's answer (an array's shape and values rounded to 1e-4; ours must agree to 1e-4). Rows cover
every assertion of the official utilities and, for every public function (and the functions they create), each
argument given a wrong type, a wrong value (``'a'``, ``None``, ``True``, -1, 0, ``np.int64``, ``np.float32``, 1.5),
a list, a 1-D array, wrong rows or columns; where the official accepts (a negative barrier gain, a list of
boundary points), its answer is the row.

Recording (nothing of the official code enters this repository): extract the two official trees outside it
(``git archive b23069e rps | tar -x -C /tmp/v2``, likewise ``019e21a`` to ``/tmp/classic``; classic's
``barrier_certificates2`` needs ``quadprog``), put one first on ``sys.path`` and evaluate every expression with
this module's `outcome` and `plain` over ``namespace('rps')``, the official modules; ours is the same run over
``namespace('v2')`` or ``namespace('classic')``.

``left_out`` lists, with a reason each, the calls whose official answer is a defect of its code, not a contract, or
one we do not reproduce: classic's ``at_position`` reaching its last check (it names an undefined variable,
``NameError``), classic's ``uni_to_si_dyn`` given a non-array (its message names an unbound variable), classic's CLF
pose controller on its approach line (0/0, NaN; ours takes the limit), its hybrid controller with a negative
``position_epsilon`` (it rebinds its state to an int), and classic's robust certificates (differential drive,
``create_robust_barriers``): without walls every solve is a ``NameError`` (``solver2``); obstacles of a wrong shape
(broadcasting errors naming other shapes), any obstacles with walls (a crash), one pose broadcast to two robots,
``max_num_robots=True`` and no robots (an empty list) meet classic's preallocated matrices in ways ours does not
reproduce; with walls, a few ill-posed QPs that cvxopt, stopped at its loose tolerance, answers with a point the
slightest change of the data moves. Also left out, unlisted: three classic certificate calls with two robots at one
point, where cvxopt itself fails ("domain error").
"""

from __future__ import annotations

import importlib
import json
import sys
import traceback
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from robotarium_exp import rps_alias
from tests.support.regression import openblas_core

TABLE = json.loads((Path(__file__).with_name('rps_contract.json')).read_text(encoding='utf-8'))
OPENBLAS_CORE = openblas_core()
PACKAGES = {'v2': 'robotarium_exp.rps', 'classic': 'robotarium_exp.rps_classic'}
MODULES = ('graph', 'misc', 'transformations', 'controllers', 'barrier_certificates', 'barrier_certificates2')


def namespace(generation: str) -> dict[str, Any]:
    """What the table's expressions name: the generation's utility modules (ours, or the official ``rps`` when
    ``generation`` is ``'rps'``) and ``np``."""
    package = PACKAGES.get(generation, generation)
    names: dict[str, Any] = {'np': np}
    for module in MODULES:
        try:
            names[module] = importlib.import_module(f'{package}.utilities.{module}')
        except ModuleNotFoundError:  # V2 has no barrier_certificates2
            continue
    return names


def outcome(expression: str, names: dict[str, Any]) -> tuple[str, str] | Any:
    """What ``expression`` raises (the exception's exact type name, so a subclass of ``AssertionError`` does not pass
    for one, and its message), else its value."""
    np.random.seed(0)
    try:
        with warnings.catch_warnings():  # a warning is no answer: the official's QP failures warn, so do ours
            warnings.simplefilter('ignore')
            return eval(expression, dict(names))  # the table's own expressions
    except Exception as error:  # noqa: BLE001 - the table records every kind
        return type(error).__name__, str(error)


def plain(value: Any) -> Any:
    """A value as the table records it: arrays as their shape and values rounded to 1e-4."""
    if isinstance(value, tuple):
        return [plain(item) for item in value]
    if isinstance(value, np.ndarray):
        return {'shape': list(value.shape), 'values': np.round(value.astype(float), 4).tolist()}
    return value


def agrees(answer: Any, expected: Any) -> bool:
    """Whether a recorded answer and ours agree: the same exception and message, or arrays of one shape whose values
    (rounded to 1e-4 each) differ by at most 1e-4 (NaN where the official's is NaN, inf of its sign where it is
    inf), or equal plain values."""
    if isinstance(answer, dict) and isinstance(expected, dict):
        ours, theirs = np.array(answer['values'], dtype=float), np.array(expected['values'], dtype=float)
        return answer['shape'] == expected['shape'] and bool(
            np.allclose(ours, theirs, rtol=0, atol=1.01e-4, equal_nan=True)
        )
    if isinstance(answer, list) and isinstance(expected, list) and len(answer) == len(expected):
        return all(agrees(a, e) for a, e in zip(answer, expected, strict=True))
    return bool(answer == expected)


def compared_here(expression: str) -> bool:
    """Whether a row is compared on this machine: a row the table marks kernel-dependent (an ill-posed QP whose
    recorded answer moves with OpenBLAS's kernels) only where OpenBLAS runs kernels that give the recorded answer."""
    dependent = TABLE['kernel_dependent']
    return expression not in dependent['expressions'] or OPENBLAS_CORE in dependent['openblas_core']


def rows_of(generation: str, module: str) -> list[tuple[str, Any]]:
    """The rows of one module: (expression, recorded outcome), exceptions as [name, message]."""
    raised = [(expression, [kind, message]) for expression, kind, message in TABLE[generation]]
    return [
        row for row in raised + [tuple(row) for row in TABLE[f'{generation}_edges']] if row[0].startswith(module + '.')
    ]


@pytest.mark.parametrize('generation', sorted(PACKAGES))
@pytest.mark.parametrize('module', MODULES)
def test_every_call_gets_the_official_answer_or_exception(generation: str, module: str) -> None:
    if module not in TABLE['public'][generation]:
        assert rows_of(generation, module) == []
        return
    names = namespace(generation)
    answers = [
        (expression, plain(outcome(expression, names)), expected)
        for expression, expected in rows_of(generation, module)
        if compared_here(expression)
    ]
    assert answers, 'the table covers every module'
    assert [row for row in answers if not agrees(row[1], row[2])] == []


@pytest.mark.parametrize('generation', sorted(PACKAGES))
def test_the_table_calls_every_public_function_of_the_official_utilities(generation: str) -> None:
    expressions = [row[0] for row in TABLE[generation] + TABLE[f'{generation}_edges']]
    uncalled = [
        f'{module}.{name}'
        for module, names in TABLE['public'][generation].items()
        for name in names
        if sum(f'{module}.{name}(' in expression for expression in expressions) < 3
    ]
    assert uncalled == []
    assert {row[0] for row in TABLE['left_out'][generation]}.isdisjoint(expressions)


def test_the_classic_package_answers_one_node_where_v2_refuses() -> None:
    assert namespace('classic')['graph'].lineGL(1).tolist() == [[1.0]]
    assert outcome('graph.lineGL(1)', namespace('v2')) == ('AssertionError', 'n must be an integer >= 2.')


SCRIPT_CALLS = [
    ('classic', 'transformations.create_si_to_uni_dynamics()(np.zeros((3, 2)), np.array([[0.0, 1.0], [0.0, 0.5], '),
    ('v2', 'barrier_certificates.create_uni_barrier_certificate()(np.array([[0.1, 0.1], [0.0, 0.5]]), np.zeros((2,'),
    ('v2', 'barrier_certificates.create_si_barrier_certificate()([[0.0, 0.0], [0.0, 0.0]], '),
]
"""Bad calls of the issue's kind (a map given 3-row commands, a unicycle certificate given 2-row poses, a list
given to a certificate), each a row of the table (by its start)."""


@pytest.mark.usefixtures('clean_rps')
@pytest.mark.parametrize(('generation', 'start'), SCRIPT_CALLS)
def test_a_script_stopping_on_a_bad_call_ends_with_the_officials_last_traceback_line(
    generation: str, start: str, tmp_path, monkeypatch
) -> None:
    """The last line Python prints for the uncaught exception (``Type: message``) is the official's, word for word:
    ``AssertionError: ...``, not a subclass of ours."""
    expression, kind, message = next(row for row in TABLE[generation] if row[0].startswith(start))
    module = expression.split('.')[0]
    script = tmp_path / 'bad_call.py'
    script.write_text(f'import numpy as np\nfrom rps.utilities import {module}\n\n{expression}\n', encoding='utf-8')
    monkeypatch.setattr(sys, 'argv', ['rps_alias', *(['--classic'] if generation == 'classic' else []), str(script)])
    with pytest.raises(Exception) as stopped:  # any type: the test compares it
        rps_alias.main()
    assert traceback.format_exception_only(stopped.value)[-1] == f'{kind}: {message}\n'
