"""Session fixtures of the end-to-end runs: ONE ``vtube demo``, whose built and checked submission (scene
robotarium_curve, planned) is the one built file every test of a preflight shares."""

from __future__ import annotations

import contextlib
import io
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

CHECK_SEEDS = 1
"""Bundled runs of the demo's preflight (the demo itself asks for 2; one more seed of the same file adds no check)."""
INITIALIZER_SEEDS = 1
"""V2's initializer alone in the demo's preflight (the demo asks for 20: the same run repeated for a quantile)."""


@dataclass(frozen=True)
class DemoRun:
    """``vtube demo`` run once: its exit code, what it printed (stdout, stderr), its folder and each stage's result."""

    code: int
    out: str
    err: str
    folder: Path
    stages: tuple[Any, ...]

    def stage(self, kind: type) -> Any:
        """The first stage of a type (``pipeline.Planned``, ``WrittenSubmission``, ...)."""
        return next(stage for stage in self.stages if isinstance(stage, kind))


@pytest.fixture(scope='session')
def demo_run(tmp_path_factory: pytest.TempPathFactory) -> DemoRun:
    """``vtube demo`` in this process, its stages recorded as they end; the submission's preflight with
    :data:`CHECK_SEEDS` and :data:`INITIALIZER_SEEDS` (the only change to the demo: fewer repetitions)."""
    from vtube import pipeline
    from vtube.cli.app import main

    folder = tmp_path_factory.mktemp('demo') / 'demo'
    stages: list[Any] = []
    demo, build_submission = pipeline.demo, pipeline.build_submission

    def recorded(out: Path, **kwargs: Any) -> Any:
        for stage in demo(out, **kwargs):
            stages.append(stage)
            yield stage

    def fewer_seeds(*args: Any, **kwargs: Any) -> Any:
        return build_submission(*args, **(kwargs | {'seeds': CHECK_SEEDS, 'initializer_seeds': INITIALIZER_SEEDS}))

    out, err = io.StringIO(), io.StringIO()
    with pytest.MonkeyPatch.context() as patch, contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        patch.setattr(pipeline, 'demo', recorded)
        patch.setattr(pipeline, 'build_submission', fewer_seeds)
        code = main(['demo', '--out', str(folder)])
    return DemoRun(code, out.getvalue(), err.getvalue(), folder, tuple(stages))
