"""The duration to declare on the testbed's web form, and how a submission's header records it.

The testbed's initializer runs first and counts, and it varies a lot from run to run, so V2's initializer is run
alone for the file's initial conditions over many seeds (`robotarium_exp.initializer`). The declaration is its
``DECLARE_QUANTILE`` quantile plus the longest experiment, rounded up to 10 s; the verifier stops a run only beyond
``RobotariumSpec.duration_factor`` times that. A declaration from fewer initializer seeds than a full build runs is a
preview: the header marks the file not for upload and gives the command that builds the one to upload.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from robotarium_exp.initializer import InitializerSample
from robotarium_exp.spec import ROBOTARIUM
from submission import delay_margin, robustness
from submission.errors import CheckError

DECLARE_QUANTILE = 0.995
"""Quantile of the initializer's durations that the declared duration covers without the verifier's margin (with
the default 200 seeds, the longest). The tail is heavy: on the trapezoid's initial conditions the longest of seeds
0-49 is 148 s, of seeds 0-199 319 s, so the longest of 50 seeds left a run beyond 1.5 times the declaration."""
FULL_BUILD_INITIALIZER_SEEDS = 200
"""The initializer seeds of a full build (``vtube submission build``); a declaration from fewer is not for upload."""


@dataclass(frozen=True)
class Declaration:
    """The duration to declare and what it rests on: the initializer's quantile, the experiment, the risks."""

    duration_s: int
    quantile_s: float
    experiment_s: float
    runs: int
    overrun_share: float
    stuck_share: float
    margins: tuple[robustness.Margins, ...] = ()
    """The runs' margins under each testbed model (`submission.robustness`), recorded in the header."""
    delay_margin: delay_margin.DelayMargin | None = None
    """The delay margin (`submission.delay_margin`) when the check searched it, recorded in the header."""

    def basis(self) -> str:
        """What the duration rests on, in one line."""
        return (
            f'initializer {DECLARE_QUANTILE:.1%} over {self.runs} seeds {self.quantile_s:.1f} s + experiment '
            f'{self.experiment_s:.1f} s; overruns {self.overrun_share:.1%}, stuck {self.stuck_share:.1%}'
        )

    @property
    def for_upload(self) -> bool:
        """Derived from as many initializer seeds as a full build: fewer may miss the heavy tail."""
        return self.runs >= FULL_BUILD_INITIALIZER_SEEDS

    def not_for_upload(self) -> list[str]:
        """Why a preview's file is not for upload, in the header's lines ([] when it is for upload)."""
        if self.for_upload:
            return []
        full = FULL_BUILD_INITIALIZER_SEEDS
        return [
            f'NOT FOR UPLOAD: this duration rests on {self.runs} initializer seeds, not the {full} of a full build',
            '(the initializer\'s tail is heavy); the command under "Rebuild with" below builds the file to upload.',
        ]

    def header_lines(self, robots: int) -> list[str]:
        """The declaration as the submission's header records it
        ([`from_header`][submission.declaration.Declaration.from_header] reads it back), after the preview's mark
        ([`not_for_upload`][submission.declaration.Declaration.not_for_upload])."""
        return [
            *self.not_for_upload(),
            f'Declare on the web form: {robots} robots and {self.duration_s} s, derived by `vtube submission check`',
            f'from {self.basis()}.',
            *(margin.line() for margin in self.margins),
            *([] if self.delay_margin is None else self.delay_margin.header_lines()),
        ]

    @classmethod
    def from_header(cls, source: str) -> Declaration | None:
        """The declaration a submission's header records, or None when it records none."""
        found = HEADER_DECLARATION.search(source)
        if found is None:
            return None
        duration, runs, quantile, experiment, overruns, stuck = found.groups()
        return cls(
            int(duration),
            float(quantile),
            float(experiment),
            int(runs),
            float(overruns) / 100,
            float(stuck) / 100,
            robustness.from_header(source),
            delay_margin.from_header(source),
        )


HEADER_DECLARATION = re.compile(
    r'Declare on the web form: \d+ robots and (\d+) s, derived by `vtube submission check`\s+from initializer '
    r'[\d.]+% over (\d+) seeds ([\d.]+) s \+ experiment ([\d.]+) s; overruns ([\d.]+)%, stuck ([\d.]+)%'
)


def declare(initializer: InitializerSample, experiment_s: float) -> Declaration:
    """The duration to declare for an initializer sample and an experiment's duration, and the measured risks.

    Stuck runs count as infinitely long: they raise the quantile when they are more than 1 - DECLARE_QUANTILE of
    the sample, and they always count as overruns.
    """
    if initializer.runs == 0:
        raise CheckError('the initializer sample is empty; run it for at least one seed.')
    durations = np.array(initializer.durations_s + (np.inf,) * len(initializer.stuck_seeds))
    quantile = float(np.quantile(durations, DECLARE_QUANTILE, method='higher'))
    if not math.isfinite(quantile):
        msg = (
            f'{len(initializer.stuck_seeds)} of {initializer.runs} initializations did not finish (seeds '
            f'{list(initializer.stuck_seeds)}): no duration covers them; change the initial conditions.'
        )
        raise CheckError(msg)
    duration = int(math.ceil((quantile + experiment_s) / 10.0) * 10)
    overruns = float(np.mean(durations + experiment_s > ROBOTARIUM.duration_factor * duration))
    return Declaration(
        duration, quantile, experiment_s, initializer.runs, overruns, len(initializer.stuck_seeds) / initializer.runs
    )
