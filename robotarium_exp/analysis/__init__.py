"""Analysis of recorded trajectories: the testbed's returned files, our logs, ROS1/ROS2 motion-capture bags.

:mod:`.trajectory` is the one type every source becomes, :mod:`.loaders`, :mod:`.bags` and :mod:`.matfiles` read
the sources, :mod:`.distances` measures pairs over their common coverage, :mod:`.passage` sees the trajectory from
a tube, :mod:`.report` measures a trajectory (in a scene or without one) into :mod:`.metrics` and writes
``metrics.json``, ``report.md`` and the figures (:mod:`.plots`).
"""

from robotarium_exp.analysis.loaders import load_trajectory
from robotarium_exp.analysis.metrics import PairMeasure, RecordingMetrics, TrackingErrors, TubeMetrics
from robotarium_exp.analysis.report import Analysis, analyse, write_report
from robotarium_exp.analysis.trajectory import DEFAULT_MAX_GAP, MaxGap, Trajectory

__all__ = [
    'DEFAULT_MAX_GAP',
    'Analysis',
    'MaxGap',
    'PairMeasure',
    'RecordingMetrics',
    'TrackingErrors',
    'Trajectory',
    'TubeMetrics',
    'analyse',
    'load_trajectory',
    'write_report',
]
