"""The house's size rules, outside tests: no module over 400 lines, no function over 60 lines."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SOURCES = ('vtube', 'vtube_planning', 'unicycle_mapping', 'robotarium_exp', 'submission', 'benchmarks', 'examples')
MODULE_LINES = 400
FUNCTION_LINES = 60


def python_files() -> list[Path]:
    return sorted(path for folder in SOURCES for path in (ROOT / folder).rglob('*.py'))


def test_the_sources_are_found() -> None:
    names = {path.relative_to(ROOT).as_posix() for path in python_files()}
    assert {'vtube/cli/app.py', 'vtube_planning/onboard/stepper.py', 'submission/builder.py'} <= names


@pytest.mark.parametrize('path', python_files(), ids=lambda path: path.relative_to(ROOT).as_posix())
def test_module_and_function_sizes(path: Path) -> None:
    source = path.read_text(encoding='utf-8')
    lines = source.count('\n')
    assert lines <= MODULE_LINES, f'{lines} lines: split the module along its concepts'
    long = [
        f'{node.name} (line {node.lineno}): {node.end_lineno - node.lineno + 1} lines'
        for node in ast.walk(ast.parse(source))
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))
        and node.end_lineno is not None
        and node.end_lineno - node.lineno + 1 > FUNCTION_LINES
    ]
    assert not long, f'functions over {FUNCTION_LINES} lines: {long}'
