"""The swarm: one control step (numpy and scipy only), the simulator, its metrics.

The simulator itself is [`vtube_planning.simulate`][vtube_planning.swarm.simulate.simulate] (also
``vtube_planning.swarm.simulate.simulate``): here ``simulate`` names its module, which importing it binds on this
package, so the function is not exported under that name.
[`passage_failures`][vtube_planning.swarm.metrics.passage_failures] turns a passage's
[`PassageMetrics`][vtube_planning.swarm.metrics.PassageMetrics] into the reasons it failed.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from vtube_planning._lazy import lazy_exports

if TYPE_CHECKING:
    from vtube_planning.onboard import PlanProfile, StepParams, SwarmStep
    from vtube_planning.swarm.faults import RobotFailure
    from vtube_planning.swarm.metrics import PassageMetrics, passage_failures, passage_metrics, tracking_errors
    from vtube_planning.swarm.simulate import SimConfig, SimResult

__all__ = [
    'PassageMetrics',
    'PlanProfile',
    'RobotFailure',
    'SimConfig',
    'SimResult',
    'StepParams',
    'SwarmStep',
    'passage_failures',
    'passage_metrics',
    'tracking_errors',
]

__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        'vtube_planning.swarm.metrics': ('PassageMetrics', 'passage_failures', 'passage_metrics', 'tracking_errors'),
        'vtube_planning.swarm.faults': ('RobotFailure',),
        'vtube_planning.swarm.simulate': ('SimConfig', 'SimResult'),
        'vtube_planning.onboard': ('PlanProfile', 'StepParams', 'SwarmStep'),
    },
)
