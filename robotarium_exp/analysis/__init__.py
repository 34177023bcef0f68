"""Analysis of recorded trajectories: the testbed's returned files, our logs, ROS1/ROS2 motion-capture bags.

:mod:`.trajectory` is the one type every source becomes, :mod:`.loaders` and :mod:`.bags` read the sources,
:mod:`.report` measures a trajectory in a scene and writes metrics, report and figures (:mod:`.plots`).
"""
