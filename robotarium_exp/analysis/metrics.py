"""What [`robotarium_exp.analysis.report.analyse`][robotarium_exp.analysis.report.analyse] measures of a recording, as
frozen types.

[`RecordingMetrics`][robotarium_exp.analysis.metrics.RecordingMetrics] holds the tube-free measures (coverage, gaps,
pair distances, collisions), the tube's ([`TubeMetrics`][robotarium_exp.analysis.metrics.TubeMetrics], None without a
scene) and what was read; ``to_json()`` gives the strict JSON of ``metrics.json`` (None for what is missing or not
finite). [`Analysis`][robotarium_exp.analysis.metrics.Analysis] holds them with what they were measured from: the
report and the figures (`robotarium_exp.analysis.plots`) read it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import asdict, dataclass
from typing import Any

from robotarium_exp.analysis.distances import PairDistances
from robotarium_exp.analysis.loaders import InputFile
from robotarium_exp.analysis.passage import INFERRED_START, AlongTube, Passage
from robotarium_exp.analysis.trajectory import Coverage, Gap, Trajectory
from robotarium_exp.verifier import wall_failure
from vtube_planning.swarm.map_contact import MapContact
from vtube_planning.swarm.metrics import strict_json


@dataclass(frozen=True)
class PairMeasure:
    """Two robots over their common frames: the smallest distance and when (None without common frames), and the
    frames at which they are closer than the collision distance (None when collisions are not counted)."""

    robots: tuple[str, str]
    common_frames: int
    min_distance_m: float | None
    time_s: float | None
    frames_closer: int | None


@dataclass(frozen=True)
class TrackingErrors:
    """|mean forward speed - v*(l_c)| and |density - rho*(l_c)| at the swarm centre, mean and max over the frames
    with every robot present and the centre inside the tube."""

    speed_tracking_mean_mps: float
    speed_tracking_max_mps: float
    density_tracking_mean_per_m2: float
    density_tracking_max_per_m2: float


@dataclass(frozen=True)
class TubeMetrics:
    """The recording seen from the tube.

    Attributes
    ----------
    passage
        The passage: timed from the start a flight recorded, else as observed (a passing time only for a passage
        observed whole).
    tube_violation_steps, robots_outside, max_outside_m
        Robot-frames outside the tube while 0 <= l <= L (the body of radius ``body_radius_m``; 0: the centre), the
        robots that ever were, how far out.
    narrowing_start_m
        Arc length where the tube first gets narrower than at its entrance.
    extent_start_m, extent_at_narrowing_m
        The swarm's length along the tube at the first complete frame and when its front reaches the narrowing
        (None without a complete frame, or when the front never reaches it).
    tracking
        Against the plan (None without a plan or a complete frame with the centre inside the tube).
    body_radius_m
        The Robotarium robot's for a flight that recorded its start (as the experiment counts), else 0.
    obstacle_clearance_m
        Per robot, the smallest distance from its body (``body_radius_m``; 0: its centre) to the scene's obstacles
        over the recording, 0 when it touched one; None for a scene without obstacles or a robot never seen.
    closest_in_passage, closest_after_passage
        The smallest distance between two robots and its time, up to the last robot's exit (the approach and the
        passage) and after it (parking); None without a last exit or a frame there.
    map_contact
        Robot-frames with a body (``body_radius_m``) on an obstacle or outside the scene's workspace, over the whole
        recording, those beyond the exit apart (`vtube_planning.swarm.map_contact`); None for a scene with neither.
    """

    passage: Passage
    tube_violation_steps: int
    robots_outside: int
    max_outside_m: float
    narrowing_start_m: float
    extent_start_m: float | None
    extent_at_narrowing_m: float | None
    tracking: TrackingErrors | None
    body_radius_m: float = 0.0
    obstacle_clearance_m: tuple[float | None, ...] | None = None
    closest_in_passage: tuple[float, float] | None = None
    closest_after_passage: tuple[float, float] | None = None
    map_contact: MapContact | None = None

    def to_json(self) -> dict[str, Any]:
        """The keys ``metrics.json`` holds for a recording analysed in a scene."""
        passage = self.passage
        out: dict[str, Any] = {
            'passing_time_s': passage.passing_time_s,
            'completed': passage.passing_time_s is not None,
            'passage': asdict(passage),
            'first_entry_s': passage.first_entry_s,
            'last_exit_s': passage.last_exit_s,
            'robots_passed': passage.robots_passed,
            'tube_violation_steps': self.tube_violation_steps,
            'robots_outside': self.robots_outside,
            'max_outside_m': self.max_outside_m,
            'tube_violation_body_radius_m': self.body_radius_m,
            'narrowing_start_m': self.narrowing_start_m,
            'extent_start_m': self.extent_start_m,
            'extent_at_narrowing_m': self.extent_at_narrowing_m,
            'obstacle_clearance_m': list(self.obstacle_clearance_m) if self.obstacle_clearance_m is not None else None,
        }
        if self.map_contact is not None:
            out['map_contact'] = asdict(self.map_contact)
        for key, closest in (('passage', self.closest_in_passage), ('after_passage', self.closest_after_passage)):
            out[f'min_distance_{key}_m'], out[f'min_distance_{key}_time_s'] = closest or (None, None)
        if self.tracking is not None:
            out.update(asdict(self.tracking))
        return out

    def violations_counted(self) -> str:
        """What a tube violation is here, in words."""
        if self.body_radius_m > 0.0:
            return f'the body (radius {self.body_radius_m:.3f} m)'
        return 'the centre'


@dataclass(frozen=True)
class RecordingMetrics:
    """The measures of one recording, and what they were made from.

    Attributes
    ----------
    robot_ids
        One name per robot.
    frames, complete_frames
        Frames, and frames at which every robot has a position.
    coverage, gaps
        Per robot: samples used and left out; holes never interpolated across.
    pairs, closest
        Every pair of robots; the pair that came closest (None when no two robots were seen at the same time).
    collision_distance_m, collision_frames
        The distance below which two robots collide, and the frames with a pair closer (None: not counted).
    tube
        The measures that need a tube (None without a scene).
    source, inputs, options
        Where the recording came from, the files read (sizes and hashes), the options of the analysis.
    scene, planned
        The scene's name (None without one); whether a plan was given.
    vtube_version, provenance
        The package version and the record of the run (`vtube_planning.provenance.provenance`).
    """

    robot_ids: tuple[str, ...]
    frames: int
    complete_frames: int
    coverage: tuple[Coverage, ...]
    gaps: tuple[Gap, ...]
    pairs: tuple[PairMeasure, ...]
    closest: PairMeasure | None
    collision_distance_m: float | None
    collision_frames: int | None
    tube: TubeMetrics | None
    source: Mapping[str, Any]
    inputs: tuple[InputFile, ...]
    options: Mapping[str, Any]
    scene: str | None
    planned: bool
    vtube_version: str
    provenance: Mapping[str, Any]

    @property
    def robots(self) -> int:
        return len(self.robot_ids)

    @property
    def colliding_pairs(self) -> tuple[tuple[str, str], ...] | None:
        """The pairs that came closer than the collision distance (None when collisions are not counted)."""
        if self.collision_distance_m is None:
            return None
        return tuple(p.robots for p in self.pairs if p.frames_closer)

    @property
    def collision_pairs(self) -> int | None:
        colliding = self.colliding_pairs
        return None if colliding is None else len(colliding)

    def failures(self) -> tuple[str, ...]:
        """What the recording shows failed: robots that collided, and, where the flight recorded its start, robots
        that never entered the tube or never left it, bodies outside the workspace at any time (beyond the exit too,
        but in a simulation of a Robotarium scene: `vtube_planning.swarm.map_contact.fails_beyond_exit`), and robot
        bodies on the tube walls (`robotarium_exp.verifier.wall_failure`, the rule of every verdict on a Robotarium
        run); a passage inferred from the data is not judged. Bodies on an obstacle fail it over the whole recording,
        whatever its start (``touched``)."""
        found = []
        colliding = self.colliding_pairs
        if colliding:
            found.append(f'{len(colliding)} robot pairs came closer than {self.collision_distance_m:.3f} m')
        passage = self.tube.passage if self.tube is not None else None
        if passage is not None and passage.start != INFERRED_START:
            if passage.never_inside:
                found.append(f'robots {", ".join(passage.never_inside)} never entered the tube')
            if passage.not_exited:
                found.append(f'robots {", ".join(passage.not_exited)} never passed the exit')
        judged = passage is not None and passage.start != INFERRED_START  # obstacles: `touched` below
        contact = self.tube.map_contact if judged and self.tube is not None else None
        found += [f for f in (contact.failures() if contact else ()) if 'outside the workspace' in f]
        if self.tube is not None and self.tube.body_radius_m > 0.0:
            tube = self.tube
            found += filter(None, [wall_failure(tube.tube_violation_steps, tube.robots_outside, tube.max_outside_m)])
        clearances = self.tube.obstacle_clearance_m if self.tube is not None else None
        touched = [r for r, c in zip(self.robot_ids, clearances or (), strict=False) if c is not None and c <= 0.0]
        if touched:
            found.append(f'robots {", ".join(touched)} touched an obstacle')
        return tuple(found)

    def to_json(self) -> dict[str, Any]:
        """``metrics.json``'s entry for this recording: strict JSON, the tube's keys only with a scene."""
        closest = self.closest
        out: dict[str, Any] = {
            'robots': self.robots,
            'robot_ids': list(self.robot_ids),
            'frames': self.frames,
            'complete_frames': self.complete_frames,
            'coverage': [asdict(c) for c in self.coverage],
            'gaps': [asdict(g) for g in self.gaps],
            'min_distance_m': closest.min_distance_m if closest else None,
            'min_distance_pair': closest.robots if closest else None,
            'min_distance_time_s': closest.time_s if closest else None,
            'pairs_without_common_frames': [p.robots for p in self.pairs if not p.common_frames],
            'collision_distance_m': self.collision_distance_m,
            'collision_pairs': self.collision_pairs,
            'colliding_pairs': self.colliding_pairs,
            'collision_frames': self.collision_frames,
            'pairs': [asdict(p) for p in self.pairs],
        }
        if self.tube is not None:
            out.update(self.tube.to_json())
        out.update(
            {
                'source': dict(self.source),
                'inputs': [f.to_json() for f in self.inputs],
                'options': dict(self.options),
                'scene': self.scene,
                'plan': self.planned,
                'vtube_version': self.vtube_version,
                'provenance': dict(self.provenance),
            }
        )
        json: dict[str, Any] = strict_json(out)
        return json


@dataclass(frozen=True)
class Analysis:
    """A trajectory, its distances, what the tube says of it (None without a scene), and its metrics."""

    trajectory: Trajectory
    distances: PairDistances
    along: AlongTube | None
    metrics: RecordingMetrics
