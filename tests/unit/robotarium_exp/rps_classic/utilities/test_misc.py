"""Classic misc: plt for star imports."""

from __future__ import annotations


def test_misc_hands_plt_to_star_imports() -> None:
    namespace: dict = {}
    exec('from robotarium_exp.rps_classic.utilities.misc import *', namespace)  # noqa: S102 - the point of the test
    assert namespace['plt'].__name__ == 'matplotlib.pyplot' and callable(namespace['at_pose'])
