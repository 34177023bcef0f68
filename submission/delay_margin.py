"""The delay margin a submission keeps: how far the real robots' delay and lag may exceed the fitted ones.

The compensation a file flies is tuned for the fitted delay and lag (`robotarium_exp.rps.testbed_model.FITTED`).
The margin is the largest multiple of ``LADDER`` (1x, 1.5x, 2x, ...: ``fitted:K``, delay and lag times K) at which
every run stays clean, it and every multiple below it, each over the same seeds (at least ``MIN_SEEDS``). The search
climbs the ladder and stops at the first multiple where a run fails: a file clean at 2x but not at 1.5x keeps 1x.

Clean runs are evidence, not proof: ``failure_bound`` is the exact (Clopper-Pearson) one-sided 95 % upper bound on
the failure rate that k failures in n runs allow ("0 of 10 runs failed: at most 26 % of runs may fail").
Distances are said as what they are: the closest two robots' centres came, and the gap between their bodies
(centres minus the robot's diameter; negative when the bodies overlap).
"""

from __future__ import annotations

import itertools
import math
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Protocol, TypeVar

from robotarium_exp.rps.testbed_model import FITTED_VERSION
from robotarium_exp.spec import ROBOTARIUM
from submission.errors import CheckError
from submission.robustness import gap_mm
from submission.schedule import Job

LADDER = (1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0)
"""The multiples of the fitted delay and lag tried, in order."""
MIN_SEEDS = 10
"""Fewer clean runs bound the failure rate too loosely to call a margin (0 of 10: at most 26 %)."""
CONFIDENCE = 0.95


def failure_bound(failed: int, runs: int, confidence: float = CONFIDENCE) -> float:
    """The exact (Clopper-Pearson) one-sided upper confidence bound on a failure rate, ``failed`` of ``runs``."""
    if runs < 1 or not 0 <= failed <= runs:
        msg = f'a failure bound needs 0 <= failed <= runs and runs >= 1 (got {failed} of {runs}).'
        raise ValueError(msg)
    if failed == runs:
        return 1.0
    from scipy.special import betaincinv

    return float(betaincinv(failed + 1, runs - failed, confidence))


def model_at(multiple: float) -> str:
    """The testbed model at ``multiple`` times the fitted delay and lag: ``fitted`` at 1x, else ``fitted:K``."""
    return 'fitted' if multiple == 1 else f'fitted:{multiple:g}'


@dataclass(frozen=True)
class Rung:
    """The runs at one multiple: how many, how many failed, how close two robots' centres came (NaN: no record)."""

    multiple: float
    runs: int
    failed: int
    closest_centres_m: float

    @property
    def clean(self) -> bool:
        return self.runs > 0 and self.failed == 0

    @property
    def bound(self) -> float:
        """The 95 % upper bound on the failure rate at this multiple."""
        return failure_bound(self.failed, self.runs)

    def line(self) -> str:
        """One line: the failures, their bound, and the closest centres with the gap between bodies."""
        closest = (
            f'closest centres {self.closest_centres_m:.3f} m, {gap_mm(self.closest_centres_m)}'
            if math.isfinite(self.closest_centres_m)
            else 'no distance recorded'
        )
        return (
            f'at {self.multiple:g}x: {self.failed} of {self.runs} runs failed: at most {100 * self.bound:.0f} % of '
            f'runs may fail; {closest}.'
        )

    def to_json(self) -> dict[str, object]:
        centres = self.closest_centres_m if math.isfinite(self.closest_centres_m) else None
        return {
            'multiple': self.multiple,
            'model': model_at(self.multiple),
            'runs': self.runs,
            'failed': self.failed,
            'failure_rate_upper_95': self.bound,
            'closest_centres_m': centres,
            'gap_between_bodies_m': None if centres is None else centres - ROBOTARIUM.robot_diameter_m,
        }


@dataclass(frozen=True)
class DelayMargin:
    """The rungs climbed (the last one the first that failed, unless every rung was clean), over ``seeds`` each,
    under the fitted model of version ``model_version``."""

    rungs: tuple[Rung, ...]
    seeds: int
    model_version: int = FITTED_VERSION

    @property
    def multiple(self) -> float | None:
        """The largest multiple clean with every one below it (None: a run failed at 1x)."""
        clean = [rung.multiple for rung in self.rungs if rung.clean]
        return clean[-1] if clean else None

    @property
    def top(self) -> bool:
        """Whether every rung of the ladder was clean (the margin is at least its top)."""
        return len(self.rungs) == len(LADDER) and all(rung.clean for rung in self.rungs)

    def summary(self) -> str:
        """The margin in one sentence (the header's first line of it; `from_header` reads it back)."""
        m = self.multiple
        said = 'none: a run failed at 1x' if m is None else f'{m:g}x' + (' or more' if self.top else '')
        return (
            f'{HEADER_PREFIX} {said} the fitted delay and lag (testbed model fitted, version {self.model_version}; '
            f'{self.seeds} seeds at each multiple).'
        )

    def header_lines(self) -> list[str]:
        return [self.summary(), *(f'  {rung.line()}' for rung in self.rungs)]

    def to_json(self) -> dict[str, object]:
        top = self.top
        return {
            'multiple': self.multiple,
            'at_least': top,
            'seeds': self.seeds,
            'model_version': self.model_version,
            'rungs': [rung.to_json() for rung in self.rungs],
        }


HEADER_PREFIX = 'Delay margin:'
HEADER_SUMMARY = re.compile(
    rf'{HEADER_PREFIX} .*? the fitted delay and lag \(testbed model fitted, version (\d+); (\d+) seeds at each multiple\)'
)
HEADER_RUNG = re.compile(
    r'^  at ([\d.]+)x: (\d+) of (\d+) runs failed: at most \d+ % of runs may fail; '
    r'(?:closest centres ([\d.]+) m|no distance recorded)',
    re.MULTILINE,
)


def from_header(source: str) -> DelayMargin | None:
    """The delay margin a submission's header records (None when it records none)."""
    found = HEADER_SUMMARY.search(source)
    if found is None:
        return None
    following = source[found.end() :].splitlines()[1:]
    lines = [line for line in itertools.takewhile(lambda line: line.startswith('  at '), following)]
    rungs = tuple(
        Rung(float(multiple), int(runs), int(failed), float(centres) if centres else math.nan)
        for multiple, failed, runs, centres in HEADER_RUNG.findall('\n'.join(lines))
    )
    return DelayMargin(rungs, int(found.group(2)), int(found.group(1)))


def climb(
    runs_at: Callable[[float], Sequence[tuple[bool, float | None]]], ladder: Sequence[float] = LADDER
) -> tuple[Rung, ...]:
    """Climb ``ladder``: ``runs_at(multiple)`` gives each run's (clean, closest centres or None); stop after the
    first multiple with a failed run."""
    rungs = []
    for multiple in ladder:
        runs = runs_at(multiple)
        distances = [d for _, d in runs if d is not None]
        rungs.append(Rung(multiple, len(runs), sum(not ok for ok, _ in runs), min(distances, default=math.nan)))
        if not rungs[-1].clean:
            break
    return tuple(rungs)


class Flown(Protocol):
    @property
    def ok(self) -> bool: ...

    @property
    def seed(self) -> int | None: ...

    @property
    def min_center_distance_m(self) -> float | None: ...


R = TypeVar('R', bound=Flown)


def search(
    fly: Callable[[list[Job]], list[R]], seeds: Sequence[int], by_model: Mapping[str, Sequence[R]]
) -> tuple[DelayMargin, list[R]]:
    """The file's delay margin over ``seeds`` (at least `MIN_SEEDS`), flying with ``fly`` (a batch of jobs, their
    runs in order) the runs not already flown (``by_model``: the check's bundled runs per model, reused), and every
    run of the search."""
    if len(seeds) < MIN_SEEDS:
        msg = f'a delay margin rests on at least {MIN_SEEDS} seeds (got {len(seeds)}); give --margin-seeds {MIN_SEEDS}.'
        raise CheckError(msg)
    flown: dict[Job, R] = {('bundled', r.seed, model): r for model, runs in by_model.items() for r in runs}
    done: list[R] = []

    def runs_at(multiple: float) -> list[tuple[bool, float | None]]:
        jobs: list[Job] = [('bundled', seed, model_at(multiple)) for seed in seeds]
        new = iter(fly([job for job in jobs if job not in flown]))
        runs = [flown[job] if job in flown else next(new) for job in jobs]
        done.extend(runs)
        return [(run.ok, run.min_center_distance_m) for run in runs]

    return DelayMargin(climb(runs_at), len(seeds)), done
