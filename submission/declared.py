"""A submission file that records the duration to declare: built, preflighted, and rebuilt with the declaration.

The duration rests on runs of the file itself (:func:`submission.check.check`), so the file is written once
without it, checked, and written again with the declaration in its header; a file that fails the check keeps none.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from submission.builder import Submission, build, write
from submission.check import CheckReport, Declaration, check
from vtube_planning.geometry.scene import Scene
from vtube_planning.planning.plan import Plan


@dataclass(frozen=True)
class WrittenSubmission:
    """A submission written to ``path`` and its preflight (None: not checked)."""

    submission: Submission
    path: Path
    report: CheckReport | None

    @property
    def declaration(self) -> Declaration | None:
        """The duration the header records (None: it records none)."""
        if self.report is None or not self.report.passed:
            return None
        return self.report.declaration


def write_submission(
    scene: Scene,
    path: Path,
    plan: Plan,
    *,
    planning: bool = True,
    declare: bool = True,
    seeds: int = 3,
    initializer_seeds: int = 200,
) -> WrittenSubmission:
    """Write the submission for ``scene`` (flying ``plan`` unless ``planning`` is off) to ``path``; with ``declare``,
    preflight it (``seeds`` runs, the initializer over ``initializer_seeds`` seeds) and, when it passes, rewrite it
    with the duration to declare in its header."""
    submission = build(scene, planning=planning, plan=plan)
    written = write(submission, path)
    if not declare:
        return WrittenSubmission(submission, written, None)
    report = check(written, seeds=seeds, initializer_seeds=initializer_seeds)
    result = WrittenSubmission(submission, written, report)
    if result.declaration is not None:
        write(build(scene, planning=planning, plan=plan, declaration=result.declaration), path)
    return result
