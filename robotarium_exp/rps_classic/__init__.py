"""The classic ``rps`` generation (PyPI ``robotarium_python_simulator`` 0.0.0), written here: names AND semantics.

``python -m robotarium_exp.rps_alias --classic script.py`` resolves ``import rps...`` to this tree. It differs from
V2 (`robotarium_exp.rps`) where the classic package differs (``docs/robotarium.md`` §3): robots start exactly
at the initial conditions, ``get_poses()`` hands out the internal array, ``set_velocities`` clips v and omega in the
caller's array (no per-wheel clipping), the counters are shared by every instance in the process, the report comes
from ``call_at_scripts_end()``. Where the two generations compute the same thing the utilities here import V2's.
"""
