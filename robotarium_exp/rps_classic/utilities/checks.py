"""Classic's argument checks, as data: what each classic utility asserts of its inputs, in classic's order.

Classic asserts every input of its utilities (types, then ranges, then array shapes) and a script that breaks one
stops with an ``AssertionError`` whose text names the function and the argument. Scripts and users know those
texts, so the checks here raise ``AssertionError`` itself with the same texts, in the same order, typos included
("Recieved"). A utility lists its checks with the constructors below and calls `enforce`; `Checked` runs the checks
of a created function (a certificate, a map) before each call.

A check reads its argument as classic does (``x.shape[0]``, ``v > 0``), so what classic cannot even test (a string
compared with 0, a list's ``shape``) fails here with the same Python error.
"""

from __future__ import annotations

import operator
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

Values = Mapping[str, Any]


@dataclass(frozen=True)
class Check:
    """One classic assertion: ``test(values)`` must hold, else ``message % shown(values)``."""

    test: Callable[[Values], Any]
    message: str
    shown: Callable[[Values], tuple[Any, ...]]


@dataclass(frozen=True)
class Kind:
    """A type classic asserts, with the words its messages use for it."""

    types: tuple[type, ...]
    words: str


NUMBER = Kind((int, float), 'an integer or float')
INTEGER = Kind((int,), 'an integer')
ARRAY = Kind((np.ndarray,), 'a numpy array')
NDARRAY = Kind((np.ndarray,), 'a numpy ndarray')

Rule = tuple[Callable[[Any, Any], Any], float, str]
"""A range classic asserts: the comparison, the limit, the words after 'must' (``(operator.gt, 0, 'be positive')``)."""

POSITIVE: Rule = (operator.gt, 0, 'be positive')
AT_LEAST_ZERO: Rule = (operator.ge, 0, 'be greater than or equal to zero')
NOT_NEGATIVE: Rule = (operator.ge, 0, 'not be negative')


def enforce(place: str, checks: Sequence[Check], values: Values) -> None:
    """Run ``checks`` in order on the named ``values``; the first that fails raises ``place, message``."""
    for check in checks:
        if not check.test(values):
            raise AssertionError(f'{place}, {check.message % check.shown(values)}')


def typed(name: str, what: str, kind: Kind = NUMBER, shown: str | None = None) -> Check:
    """``name`` must be of ``kind``; the message shows the type of ``shown`` (classic sometimes names another)."""
    return Check(
        lambda v: isinstance(v[name], kind.types),
        f'{what} must be {kind.words}. Recieved type %r.',
        lambda v: (type(v[shown or name]).__name__,),
    )


def bound(name: str, what: str, rule: Rule) -> Check:
    """``name`` compared with a limit, e.g. ``POSITIVE`` or ``(operator.le, 0.2, 'be less than ...')``."""
    compare, limit, words = rule
    return Check(lambda v: compare(v[name], limit), f'{what} must {words}. Recieved %r.', lambda v: (v[name],))


def rows(name: str, count: int, what: str, received: str = 'Recieved dimension %r.') -> Check:
    """``name.shape[0] == count``: ``what`` says it (``... must be 2 ([x;y])``), then the rows received."""
    return Check(lambda v: v[name].shape[0] == count, f'{what}. {received}', lambda v: (v[name].shape[0],))


def columns(first: str, second: str, message: str) -> Check:
    """As many columns in ``first`` as in ``second``; the message shows both shapes (rows x columns, each)."""
    return Check(
        lambda v: v[first].shape[1] == v[second].shape[1],
        message,
        lambda v: (v[first].shape[0], v[first].shape[1], v[second].shape[0], v[second].shape[1]),
    )


def pair(place: str, checks: Sequence[Check], first: str, second: str) -> Callable[[Any, Any], None]:
    """The checks of a created function of two arguments, named ``first`` and ``second`` in the checks."""
    return lambda a, b: enforce(place, checks, {first: a, second: b})


class Checked:
    """A created function (a map, a certificate) that first runs classic's checks on its two arguments; its other
    attributes (a certificate's ``stats``) are the function's."""

    def __init__(self, function: Callable[..., Any], check: Callable[[Any, Any], None]) -> None:
        self.function = function
        self.check = check

    def __call__(self, first: Any, second: Any, *rest: Any) -> Any:
        self.check(first, second)
        return self.function(first, second, *rest)

    def __getattr__(self, name: str) -> Any:
        if name == 'function':  # not yet set (a copy being built): no attribute to forward to
            raise AttributeError(name)
        return getattr(self.function, name)
