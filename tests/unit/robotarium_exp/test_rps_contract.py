"""The contract with the official simulators' utilities: every wrong input gets the official exception and message.

``rps_contract.json`` is the table, recorded once from the official packages (V2 and classic, commits named in the
file) and kept here as data: each row is a call of a utility (an expression over the ``rps.utilities`` modules and
``np``), the name of the exception the official package raised and its message. Rows cover every assertion of the
official utilities (each argument given a wrong type, a wrong value, a wrong shape) and the Python errors the
official code raises on the way. The ``*_edges`` rows are calls on edge cases (one robot, no robots, empty graphs)
and what the official package answered (an array's shape and values, rounded to 1e-4).

Left out of the table, because the official answer is a defect of its code, not a contract: classic's
``at_position`` (its last check names an undefined variable, so every call that reaches it raises ``NameError``;
ours makes that check as meant and answers), classic's ``uni_to_si_dyn`` given a non-array ``dxu`` (its message
names an unbound variable; ours gives the message meant), and three classic certificate calls with two robots at
one point, where cvxopt itself fails ("domain error").
"""

from __future__ import annotations

import importlib
import json
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest

TABLE = json.loads((Path(__file__).with_name('rps_contract.json')).read_text(encoding='utf-8'))
PACKAGES = {'v2': 'robotarium_exp.rps', 'classic': 'robotarium_exp.rps_classic'}
MODULES = ('graph', 'misc', 'transformations', 'controllers', 'barrier_certificates')


def namespace(generation: str) -> dict[str, Any]:
    """What the table's expressions name: the generation's utility modules (ours, or the official ``rps`` when
    ``generation`` is ``'rps'``) and ``np``."""
    package = PACKAGES.get(generation, generation)
    names: dict[str, Any] = {'np': np}
    for module in MODULES:
        names[module] = importlib.import_module(f'{package}.utilities.{module}')
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


@pytest.mark.parametrize('generation', sorted(PACKAGES))
@pytest.mark.parametrize('module', MODULES)
def test_every_wrong_input_gets_the_official_exception_and_message(generation: str, module: str) -> None:
    rows = [row for row in TABLE[generation] if row[0].startswith(module + '.')]
    if generation == 'v2' and module == 'barrier_certificates':
        assert rows == []  # V2's certificates check nothing
        return
    assert rows, 'the table covers every module'
    names = namespace(generation)
    wrong = [(expression, outcome(expression, names), (kind, message)) for expression, kind, message in rows]
    assert [row for row in wrong if row[1] != row[2]] == []


@pytest.mark.parametrize('generation', sorted(PACKAGES))
def test_edge_cases_answer_as_the_official_packages(generation: str) -> None:
    names = namespace(generation)
    answers = [
        (expression, plain(outcome(expression, names)), expected)
        for expression, expected in TABLE[f'{generation}_edges']
    ]
    assert [row for row in answers if row[1] != row[2]] == []


def test_the_classic_package_answers_one_node_where_v2_refuses() -> None:
    assert namespace('classic')['graph'].lineGL(1).tolist() == [[1.0]]
    assert outcome('graph.lineGL(1)', namespace('v2')) == ('AssertionError', 'n must be an integer >= 2.')
