"""What a robot runs on board: one control period of the swarm, in small modules of numpy and scipy only.

The submission builder inlines these modules' sources, in the order of :data:`MODULES`, into the file the testbed
runs; they import nothing but numpy, scipy, the standard library and each other.
"""

from vtube_planning.onboard.delay import CommandPredictor, lag_response
from vtube_planning.onboard.density import swarm_area, swarm_density
from vtube_planning.onboard.law import Command, avoidance_velocity, interaction_gains, velocity_command
from vtube_planning.onboard.params import (
    DENSITY_PADDINGS,
    KDTREE_ABOVE,
    LAWS,
    PLAN_AT,
    SATURATIONS,
    DensityPadding,
    Law,
    PlanAt,
    Saturation,
    StepParams,
)
from vtube_planning.onboard.profile import PlanProfile
from vtube_planning.onboard.projection import Projection
from vtube_planning.onboard.sampled_tube import SampledTube
from vtube_planning.onboard.stepper import StepResult, SwarmStep
from vtube_planning.onboard.tube import StepTube

MODULES = (
    'vtube_planning.onboard.projection',
    'vtube_planning.onboard.tube',
    'vtube_planning.onboard.sampled_tube',
    'vtube_planning.onboard.scalar',
    'vtube_planning.onboard.params',
    'vtube_planning.onboard.profile',
    'vtube_planning.onboard.density',
    'vtube_planning.onboard.neighbours',
    'vtube_planning.onboard.law',
    'vtube_planning.onboard.radius',
    'vtube_planning.onboard.stretch',
    'vtube_planning.onboard.parking',
    'vtube_planning.onboard.delay',
    'vtube_planning.onboard.stepper',
)
"""The modules in dependency order (each imports only modules before it): the order the builder inlines them."""

__all__ = [
    'DENSITY_PADDINGS',
    'KDTREE_ABOVE',
    'LAWS',
    'MODULES',
    'PLAN_AT',
    'SATURATIONS',
    'Command',
    'CommandPredictor',
    'DensityPadding',
    'Law',
    'PlanAt',
    'PlanProfile',
    'Projection',
    'SampledTube',
    'Saturation',
    'StepParams',
    'StepResult',
    'StepTube',
    'SwarmStep',
    'avoidance_velocity',
    'interaction_gains',
    'lag_response',
    'swarm_area',
    'swarm_density',
    'velocity_command',
]
