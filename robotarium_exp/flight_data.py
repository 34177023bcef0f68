"""What a Robotarium flight is made of, as data: :class:`FlightData`, the one thing a submission embeds.

The experiment (:func:`robotarium_exp.experiment.flight_data`) makes it from a scene and a plan; the submitted file
carries it as a plain literal (:meth:`FlightData.to_plain`: nested lists and numbers, six significant digits) and
rebuilds it with :meth:`FlightData.from_plain`, so both fly the same numbers with
:func:`robotarium_exp.flight.build_flight`. It needs numpy only: :mod:`submission.builder` inlines it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import asdict, dataclass, fields, is_dataclass
from typing import Any, TypeAlias

import numpy as np
from numpy.typing import NDArray

from vtube_planning.onboard import PlanProfile, StepParams

FloatArray = NDArray[np.float64]
PlainValue: TypeAlias = 'None | bool | int | float | str | list[PlainValue] | dict[str, PlainValue]'
"""A value of a plain literal: what ``ast.literal_eval`` gives back."""
SIGNIFICANT_DIGITS = 6


@dataclass(frozen=True)
class Wheels:
    """The robot's drive: axle length, wheel radius, wheel speed limit (from ``RobotariumSpec``)."""

    base_length_m: float
    wheel_radius_m: float
    max_wheel_speed_radps: float

    @property
    def rim_speed_mps(self) -> float:
        """The largest wheel rim speed r phi_max."""
        return self.wheel_radius_m * self.max_wheel_speed_radps


@dataclass(frozen=True, eq=False)
class TubeSamples:
    """The tube a flight projects onto: centre-line points, half-widths and cumulative areas at arc lengths (K,);
    ``xy_m`` is (2, K). :class:`~vtube_planning.onboard.SampledTube` takes these."""

    l_m: FloatArray
    xy_m: FloatArray
    half_width_m: FloatArray
    area_m2: FloatArray


@dataclass(frozen=True)
class SafetyData:
    """The barrier rows of the safety filter: distance between control points, gain gamma, arena (x0, x1, y0, y1)."""

    safety_radius_m: float
    barrier_gain: float
    arena_m: tuple[float, float, float, float]


@dataclass(frozen=True, eq=False)
class FlightData:
    """Everything a flight needs, rounded as a submission embeds it.

    Attributes
    ----------
    scene, tube_hash
        The scene's name and its tube's fingerprint (provenance of the flight and of its log).
    n_robots, time_step_s, max_steps
        Robots, the testbed's control period, the step limit.
    step
        The swarm step's parameters.
    constant_speed_mps
        The forward speed without a plan.
    plan
        The plan's profile, or None: an unplanned flight (constant speed, constant r_a).
    tube
        The sampled tube; ``tube_edges_m`` (2, 2, K) its left and right boundary, for drawing.
    obstacle_outlines_m
        The scene's obstacles, each a closed outline (2, K), for drawing (the arena holds none: they are virtual).
    initial_conditions
        Poses (3, N) the testbed initializes the robots to.
    parking_slots
        Slots (2, N) beyond the exit.
    projection_distance_m
        d of the near-identity map.
    safety
        The barrier rows of the safety filter, or None: no filter.
    wheels
        The drive's limits.
    """

    scene: str
    tube_hash: str
    n_robots: int
    time_step_s: float
    max_steps: int
    step: StepParams
    constant_speed_mps: float
    plan: PlanProfile | None
    tube: TubeSamples
    tube_edges_m: FloatArray
    obstacle_outlines_m: tuple[FloatArray, ...]
    initial_conditions: FloatArray
    parking_slots: FloatArray
    projection_distance_m: float
    safety: SafetyData | None
    wheels: Wheels

    @property
    def planned(self) -> bool:
        """Whether the flight tracks a plan."""
        return self.plan is not None

    def to_plain(self) -> dict[str, PlainValue]:
        """The data as a plain literal: dicts, lists of floats rounded to six significant digits, ints, strings."""
        plain: dict[str, PlainValue] = {}
        for item in fields(self):
            value = getattr(self, item.name)
            plain[item.name] = plain_value(
                asdict(value) if is_dataclass(value) and not isinstance(value, type) else value
            )
        return plain

    @classmethod
    def from_plain(cls, plain: Mapping[str, Any]) -> FlightData:
        """The data of a plain literal (:meth:`to_plain`); raises ValueError naming a missing or extra key."""
        _same_keys(plain, cls, 'flight data')
        profile, safety = plain['plan'], plain['safety']
        if safety is not None:
            safety = _same_keys(safety, SafetyData, "flight data's safety")
        return cls(
            scene=str(plain['scene']),
            tube_hash=str(plain['tube_hash']),
            n_robots=int(plain['n_robots']),
            time_step_s=float(plain['time_step_s']),
            max_steps=int(plain['max_steps']),
            step=StepParams(**_same_keys(plain['step'], StepParams, "flight data's step")),
            constant_speed_mps=float(plain['constant_speed_mps']),
            plan=None if profile is None else PlanProfile(**_arrays(profile, PlanProfile)),
            tube=TubeSamples(**_arrays(plain['tube'], TubeSamples)),
            tube_edges_m=_array(plain['tube_edges_m']),
            obstacle_outlines_m=tuple(_array(outline) for outline in plain['obstacle_outlines_m']),
            initial_conditions=_array(plain['initial_conditions']),
            parking_slots=_array(plain['parking_slots']),
            projection_distance_m=float(plain['projection_distance_m']),
            safety=None
            if safety is None
            else SafetyData(
                float(safety['safety_radius_m']),
                float(safety['barrier_gain']),
                _bounds(safety['arena_m']),
            ),
            wheels=Wheels(
                **{key: float(value) for key, value in _same_keys(plain['wheels'], Wheels, 'wheels').items()}
            ),
        )

    def rounded(self) -> FlightData:
        """The data as a submission carries it (:meth:`to_plain` read back)."""
        return FlightData.from_plain(self.to_plain())


def plain_value(value: object) -> PlainValue:
    """Arrays as nested lists of floats rounded to six significant digits; dicts, lists and scalars likewise."""
    if isinstance(value, dict):
        return {str(k): plain_value(v) for k, v in value.items()}
    if isinstance(value, np.ndarray):
        return plain_value(value.tolist())
    if isinstance(value, (list, tuple)):
        return [plain_value(v) for v in value]
    if isinstance(value, float):
        return float(f'{value:.{SIGNIFICANT_DIGITS}g}')
    if value is None or isinstance(value, (bool, int, str)):
        return value
    msg = f'{value!r} ({type(value).__name__}) has no plain form; give numbers, strings, lists or arrays.'
    raise ValueError(msg)


def _same_keys(plain: Mapping[str, Any], cls: type, what: str) -> dict[str, Any]:
    """``plain`` as a dict, when its keys are the fields of the dataclass ``cls``."""
    expected = [item.name for item in fields(cls)]
    missing, extra = sorted(set(expected) - set(plain)), sorted(set(plain) - set(expected))
    if missing or extra:
        msg = f'{what}: missing {missing}, unexpected {extra}; rebuild the file with `vtube submission build`.'
        raise ValueError(msg)
    return dict(plain)


def _arrays(plain: Mapping[str, Any], cls: type) -> dict[str, FloatArray]:
    return {key: _array(value) for key, value in _same_keys(plain, cls, cls.__name__).items()}


def _array(value: object) -> FloatArray:
    return np.asarray(value, dtype=float)


def _bounds(value: object) -> tuple[float, float, float, float]:
    x0, x1, y0, y1 = (float(v) for v in np.asarray(value, dtype=float))
    return (x0, x1, y0, y1)
