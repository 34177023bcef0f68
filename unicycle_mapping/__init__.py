"""Single-integrator velocities mapped to unicycle speeds through a near-identity diffeomorphism.

Pure numpy, vectorised over robots, in the Robotarium's layout: poses (3, N) as [x; y; theta], unicycle commands
(2, N) as [v; omega], single-integrator points and velocities (2, N). One robot per column.
"""

from unicycle_mapping.errors import MappingError
from unicycle_mapping.mapping import (
    si_to_uni,
    si_to_uni_constrained,
    si_to_uni_states,
    uni_to_si,
    uni_to_si_states,
)
from unicycle_mapping.unicycle import unicycle_step
from unicycle_mapping.wheels import max_realisable_si_speed, scale_to_wheel_limits, wheel_speeds

__all__ = [
    'MappingError',
    'max_realisable_si_speed',
    'scale_to_wheel_limits',
    'si_to_uni',
    'si_to_uni_constrained',
    'si_to_uni_states',
    'uni_to_si',
    'uni_to_si_states',
    'unicycle_step',
    'wheel_speeds',
]
