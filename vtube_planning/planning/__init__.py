"""Speed and density planning: the density model of (p7), the convex and polynomial planners, the Plan."""

from __future__ import annotations

from typing import TYPE_CHECKING

from vtube_planning._lazy import lazy_exports

if TYPE_CHECKING:
    from vtube_planning.planning.density import footprint, predicted_density
    from vtube_planning.planning.plan import Plan, SwarmState
    from vtube_planning.planning.planner import plan_convex, replan
    from vtube_planning.planning.polynomial import plan_polynomial

__all__ = [
    'Plan',
    'SwarmState',
    'footprint',
    'plan_convex',
    'plan_polynomial',
    'predicted_density',
    'replan',
]

__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        'vtube_planning.planning.density': ('footprint', 'predicted_density'),
        'vtube_planning.planning.plan': ('Plan', 'SwarmState'),
        'vtube_planning.planning.planner': ('plan_convex', 'replan'),
        'vtube_planning.planning.polynomial': ('plan_polynomial',),
    },
)
