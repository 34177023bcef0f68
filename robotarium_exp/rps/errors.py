"""What ``rps`` and ``rps_classic`` raise on misuse: the official's ``AssertionError``, or our `RobotariumError`.

Where the official simulators check a call (``assert condition, message``), ours raise exactly ``AssertionError``
with the official's message (`require`), so a script's traceback ends on the same line as on the official (and the
check holds under ``python -O`` too). Where ours refuse what the official does not check (a NaN command, more robots
than charger slots, an initialization that never finishes), they raise
[`RobotariumError`][robotarium_exp.rps.errors.RobotariumError], which vtube's own layers catch.
"""

from __future__ import annotations


class RobotariumError(AssertionError):
    """A refusal of ours that the official simulators do not make (NaN or misshapen commands, more robots than
    charger slots, an initialization that never finishes, an unknown QP solver).

    It subclasses ``AssertionError``, what the official raises for its own checks, so a script's
    ``except AssertionError`` catches both; the messages say what to do instead.
    """


def require(condition: bool, message: str) -> None:
    """The official's ``assert condition, message``: raise exactly ``AssertionError(message)`` unless it holds."""
    if not condition:
        raise AssertionError(message)
