"""Short flights that collide under the law alone and not with the foresight (whole simulated flights: the
foresight's parts are unit-tested in ``tests/unit/vtube_planning/swarm/test_foresight.py``)."""

from __future__ import annotations

from dataclasses import replace

from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile
from vtube_planning.params import ControlParams, SwarmParams
from vtube_planning.swarm.dynamics import dynamics_violations
from vtube_planning.swarm.simulate import SimConfig, simulate


def _flight(control: ControlParams, tube: VirtualTube, n: int, seed: int):
    swarm = replace(SwarmParams(), n_robots=n)
    config = SimConfig(seed=seed, acceleration_limits=True, time_limit_s=40.0)
    return simulate(tube, swarm, control, plan=None, config=config, constant_speed_mps=4.0)


NARROWING = VirtualTube(
    ArcPath((ArcPiece(30.0),)),
    WidthProfile(
        3.0,
        (WidthPart('constant', 10.0), WidthPart('linear', 2.0, to_m=1.2, corner_m=0.3), WidthPart('constant', 18.0)),
    ),
)


def test_short_flights_that_fail_under_the_law_alone_pass_with_foresight() -> None:
    law = _flight(ControlParams(), NARROWING, 6, 0)
    assert law.metrics.collision_pairs > 0 or law.metrics.tube_violation_steps > 0  # a case the law alone fails
    assert dynamics_violations(law.velocities_mps, law.commands_mps, SwarmParams(), 0.02) > 0
    foreseen = _flight(ControlParams(foresight_s=3.0), NARROWING, 6, 0)
    m = foreseen.metrics
    assert (m.collision_pairs, m.tube_violation_steps, m.completed) == (0, 0, True)
    assert foreseen.dynamics_violations == 0 < law.dynamics_violations
