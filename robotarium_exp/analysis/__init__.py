"""Analysis of recorded trajectories: the testbed's returned files, our logs, ROS1/ROS2 motion-capture bags.

:mod:`.trajectory` is the one type every source becomes, :mod:`.loaders`, :mod:`.bags` and :mod:`.matfiles` read
the sources, :mod:`.distances` measures pairs over their common coverage, :mod:`.passage` sees the trajectory from
a tube, and :mod:`.report` measures a trajectory (in a scene or without one) and writes metrics, report and
figures (:mod:`.plots`).
"""
