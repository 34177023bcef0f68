"""A Robotarium-compatible simulator: the ``rps`` API of both generations (classic and V2), written here.

Module layout mirrors ``rps`` so that imports read like the original:

    from robotarium_exp.rps.robotarium import Robotarium
    from robotarium_exp.rps.utilities.barrier_certificates import create_si_barrier_certificate_with_boundary
"""
