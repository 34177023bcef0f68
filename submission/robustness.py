"""How a submission's flight holds up under the real robots: its margins per testbed model.

The preflight flies the file on the bundled simulator under the testbed models of `CHECKED_MODELS`
(`robotarium_exp.rps.testbed_model`): ``ideal`` (V2's simulator) and ``fitted`` (the delay, lag, gains and
noise fitted to real runs) decide the verdict, and the declared duration covers both; ``fitted:2`` (twice the delay
and lag) is a stress test whose margins are reported and recorded in the header, not a condition of the verdict.
A model's margins: how many of its runs were clean and completed, the smallest distance between two robots' centres
(and the gap it leaves between their bodies), the robot-steps with a body over a wall, and the longest passing time and run.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.flight_data import FlightData
from robotarium_exp.spec import ROBOTARIUM
from submission.recording import SimulatorRecord
from vtube_planning.onboard import SampledTube, StepTube
from vtube_planning.swarm.metrics import PassageMetrics, passage_metrics

FloatArray = NDArray[np.float64]

CHECKED_MODELS = ('ideal', 'fitted', 'fitted:2')
"""The testbed models a preflight flies, in order."""
VERDICT_MODELS = ('ideal', 'fitted')
"""The models whose runs decide the verdict and the declared duration (the others are stress tests)."""
HEADER_PREFIX = 'Under testbed model'


def gap_mm(centres_m: float) -> str:
    """The gap between two robots' bodies whose centres are ``centres_m`` apart, in words."""
    gap = 1000 * (centres_m - ROBOTARIUM.robot_diameter_m)
    if not math.isfinite(gap):
        return 'no gap recorded'
    return f'a {gap:.0f} mm gap between bodies' if gap >= 0 else f'bodies overlapping by {-gap:.0f} mm'


@dataclass(frozen=True)
class Margins:
    """One testbed model's runs, summed up (NaN where no run left a record)."""

    model: str
    runs: int
    clean: int
    min_distance_m: float
    wall_steps: int
    passing_time_s: float
    duration_s: float

    def line(self) -> str:
        """The margins in one line (the header records it; `from_header` reads it back)."""
        return (
            f'{HEADER_PREFIX} {self.model}: {self.clean} of {self.runs} runs clean, closest centres '
            f'{self.min_distance_m:.3f} m ({gap_mm(self.min_distance_m)}), body on a wall {self.wall_steps} robot-steps, passing at most '
            f'{self.passing_time_s:.1f} s, run at most {self.duration_s:.1f} s.'
        )

    def to_json(self) -> dict[str, object]:
        """The margins for ``--json`` (None where no run left a record)."""
        centres = _finite(self.min_distance_m)
        return {
            'model': self.model,
            'runs': self.runs,
            'clean': self.clean,
            'closest_centres_m': centres,
            'gap_between_bodies_m': None if centres is None else centres - ROBOTARIUM.robot_diameter_m,
            'body_on_wall_robot_steps': self.wall_steps,
            'passing_time_max_s': _finite(self.passing_time_s),
            'duration_max_s': _finite(self.duration_s),
        }


def _finite(x: float) -> float | None:
    return x if math.isfinite(x) else None


HEADER_MARGINS = re.compile(
    rf'{HEADER_PREFIX} (\S+): (\d+) of (\d+) runs clean, (?:min distance|closest centres) (\S+) m(?: \([^)]*\))?, '
    r'body on a wall (\d+) robot-steps, '
    r'passing at most (\S+) s, run at most (\S+) s\.'
)


def from_header(source: str) -> tuple[Margins, ...]:
    """The margins a submission's header records (none in a file built before they were)."""
    found = []
    for model, clean, runs, distance, wall, passing, duration in HEADER_MARGINS.findall(source):
        found.append(Margins(model, int(runs), int(clean), float(distance), int(wall), float(passing), float(duration)))
    return tuple(found)


def record_passage(
    record: SimulatorRecord, tube: StepTube, collision_distance_m: float
) -> tuple[PassageMetrics, FloatArray, FloatArray]:
    """A recorded run's passage through ``tube``, from the poses the simulator validated (its true poses), with
    bodies of the testbed's robots: the metrics, the times (T,) and every robot's arc length (T, N)."""
    poses = record.poses
    steps, _, n = poses.shape
    t_s = record.dt_s * np.arange(steps, dtype=float)
    projection = tube.project(poses[:, :2].transpose(1, 0, 2).reshape(2, -1))
    l_m = projection.l_m.reshape(steps, n)
    metrics = passage_metrics(
        t_s,
        poses[:, :2],
        l_m,
        projection.clearance_m.reshape(steps, n),
        tube.length_m,
        collision_distance_m=collision_distance_m,
        body_radius_m=0.5 * ROBOTARIUM.robot_diameter_m,
    )
    return metrics, t_s, l_m


def record_metrics(record: SimulatorRecord, data: FlightData) -> tuple[float, float, int]:
    """A run's passing time, smallest centre distance and body-on-wall robot-steps on the file's tube."""
    if record.poses.shape[0] == 0:
        return math.nan, math.nan, 0
    tube = SampledTube(data.tube.l_m, data.tube.xy_m, data.tube.half_width_m, data.tube.area_m2)
    metrics, _, _ = record_passage(record, tube, ROBOTARIUM.collision_diameter_m)
    return metrics.passing_time_s, metrics.min_distance_m, metrics.tube_violation_steps


def margins(model: str, runs: Sequence[tuple[bool, SimulatorRecord | None, float | None]], data: FlightData) -> Margins:
    """A model's margins from its runs, each (clean: no problem found, its record, its duration by the simulator's
    count)."""
    measured = [record_metrics(record, data) for _, record, _ in runs if record is not None]
    durations = [d for _, _, d in runs if d is not None]
    return Margins(
        model,
        len(runs),
        sum(ok for ok, _, _ in runs),
        min((m[1] for m in measured), default=math.nan),
        sum(m[2] for m in measured),
        max((m[0] for m in measured), default=math.nan),
        max(durations, default=math.nan),
    )
