"""Every exception is a VtubeError and the builtin that describes it."""

from __future__ import annotations

import inspect

import pytest

from vtube_planning import errors
from vtube_planning.errors import (
    LogError,
    ParamsError,
    PlanError,
    SceneError,
    ShapeError,
    SolverError,
    TubeError,
    TubeGenerationError,
    VtubeError,
)


@pytest.mark.parametrize(
    ('error', 'builtin'),
    [
        (ParamsError, ValueError),
        (TubeError, ValueError),
        (SceneError, ValueError),
        (ShapeError, ValueError),
        (PlanError, ValueError),
        (LogError, ValueError),
        (SolverError, RuntimeError),
        (TubeGenerationError, ValueError),
    ],
)
def test_each_error_is_caught_as_vtube_error_and_as_its_builtin(error: type[Exception], builtin: type) -> None:
    for catch in (VtubeError, builtin, error):
        with pytest.raises(catch, match='the message'):
            raise error('the message')


def test_the_module_defines_no_error_outside_the_hierarchy() -> None:
    defined = [c for _, c in inspect.getmembers(errors, inspect.isclass) if c.__module__ == errors.__name__]
    assert len(defined) == 9 and all(issubclass(c, VtubeError) for c in defined)
