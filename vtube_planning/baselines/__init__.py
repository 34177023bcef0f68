"""The paper's baselines: optimized flocking and distributed NMPC.

Each flies through [`vtube_planning.simulate`][vtube_planning.swarm.simulate.simulate] as its ``baseline``; every name
below is imported from its module on first use (the NMPC's CasADi only when a problem is built).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from vtube_planning._lazy import lazy_exports

if TYPE_CHECKING:
    from vtube_planning.baselines.flocking import FlockingParams, flocking_command
    from vtube_planning.baselines.nmpc import NmpcParams, NmpcSwarm

__all__ = ['FlockingParams', 'NmpcParams', 'NmpcSwarm', 'flocking_command']

__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        'vtube_planning.baselines.flocking': ('FlockingParams', 'flocking_command'),
        'vtube_planning.baselines.nmpc': ('NmpcParams', 'NmpcSwarm'),
    },
)
