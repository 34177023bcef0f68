"""The tube experiment on the Robotarium: a compatible simulator, the experiment loop, trajectory analysis.

[`run_experiment`][robotarium_exp.experiment.run_experiment] flies a scene's plan on any Robotarium class (`rps`,
`rps_classic`, the PyPI simulator); [`analysis`][robotarium_exp.analysis] measures what comes back.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from vtube_planning._lazy import lazy_exports

if TYPE_CHECKING:
    from robotarium_exp.errors import AnalysisError, ExperimentError, RobotariumExpError
    from robotarium_exp.experiment import ExperimentConfig, ExperimentResult, run_experiment
    from robotarium_exp.rps.errors import RobotariumError
    from robotarium_exp.spec import ROBOTARIUM, RobotariumSpec

__all__ = [
    'ROBOTARIUM',
    'AnalysisError',
    'ExperimentConfig',
    'ExperimentError',
    'ExperimentResult',
    'RobotariumError',
    'RobotariumExpError',
    'RobotariumSpec',
    'run_experiment',
]

__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        'robotarium_exp.errors': ('AnalysisError', 'ExperimentError', 'RobotariumExpError'),
        'robotarium_exp.rps.errors': ('RobotariumError',),
        'robotarium_exp.experiment': ('ExperimentConfig', 'ExperimentResult', 'run_experiment'),
        'robotarium_exp.spec': ('ROBOTARIUM', 'RobotariumSpec'),
    },
)
