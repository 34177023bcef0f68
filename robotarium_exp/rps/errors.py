"""What ``rps`` raises on misuse: [`RobotariumError`][robotarium_exp.rps.errors.RobotariumError]."""

from __future__ import annotations


class RobotariumError(AssertionError):
    """Misuse of the Robotarium API (call order, shapes, robot counts).

    It subclasses ``AssertionError`` because that is what ``rps`` raises for the same mistakes (through ``assert``),
    so scripts that run on the testbed behave the same here; the messages say what to do instead.
    """
