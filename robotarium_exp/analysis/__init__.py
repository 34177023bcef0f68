"""Analysis of recorded trajectories: the testbed's returned files, our logs, ROS1/ROS2 motion-capture bags.

`trajectory` is the one type every source becomes, `loaders`, `bags` and `matfiles` read the sources,
`distances` measures pairs over their common coverage, `passage` sees the trajectory from a tube, `report`
measures a trajectory (in a scene or without one) into `metrics` and writes ``metrics.json``, ``report.md`` and the
figures (`plots`); `export` writes a trajectory as a bag or CSV, and `replay` as one offline HTML page that plays
it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from vtube_planning._lazy import lazy_exports

if TYPE_CHECKING:
    from robotarium_exp.analysis.bags import read_bag
    from robotarium_exp.analysis.loaders import load_npz_log, load_submission_folder, load_trajectory
    from robotarium_exp.analysis.matfiles import read_mat
    from robotarium_exp.analysis.metrics import Analysis, PairMeasure, RecordingMetrics, TrackingErrors, TubeMetrics
    from robotarium_exp.analysis.report import analyse, write_report
    from robotarium_exp.analysis.trajectory import DEFAULT_MAX_GAP, MaxGap, RobotSamples, Trajectory

__all__ = [
    'DEFAULT_MAX_GAP',
    'Analysis',
    'MaxGap',
    'PairMeasure',
    'RecordingMetrics',
    'RobotSamples',
    'TrackingErrors',
    'Trajectory',
    'TubeMetrics',
    'analyse',
    'load_npz_log',
    'load_submission_folder',
    'load_trajectory',
    'read_bag',
    'read_mat',
    'write_report',
]

__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        'robotarium_exp.analysis.bags': ('read_bag',),
        'robotarium_exp.analysis.loaders': ('load_npz_log', 'load_submission_folder', 'load_trajectory'),
        'robotarium_exp.analysis.matfiles': ('read_mat',),
        'robotarium_exp.analysis.metrics': (
            'Analysis',
            'PairMeasure',
            'RecordingMetrics',
            'TrackingErrors',
            'TubeMetrics',
        ),
        'robotarium_exp.analysis.report': ('analyse', 'write_report'),
        'robotarium_exp.analysis.trajectory': ('DEFAULT_MAX_GAP', 'MaxGap', 'RobotSamples', 'Trajectory'),
    },
)
