"""Exceptions of :mod:`robotarium_exp`."""

from __future__ import annotations


class RobotariumError(AssertionError):
    """Misuse of the Robotarium API (call order, shapes, robot counts).

    It subclasses ``AssertionError`` because that is what ``rps`` raises for the same mistakes (through ``assert``),
    so scripts that run on the testbed behave the same here; the messages say what to do instead.
    """


class ExperimentError(ValueError):
    """An experiment that cannot be set up: initial conditions, scene, plan."""


class AnalysisError(ValueError):
    """Trajectory data that cannot be read or analysed: missing topic, wrong format, truncated file, NaN poses."""
