"""Which claims a report judges together, and on which seeds: the families of Holm's adjustment, pooled or held-out
confirmation seeds.

A report's paired tests (`vtube_planning.studies.study_report`, `robotarium_exp.compare`) are claims "a beats b on a
metric" in a cell (scene, N, setting) or over a population of maps. Holm's adjustment holds the chance of any false
claim at ALPHA within a *family*; the smaller the family, the smaller the effects its seeds can find. A campaign
declares its families, one per claim its readers quote (the README's), in a ``[families]`` table::

    [families.faster]                         # the family's name, as the report prints it
    comparisons = ["planning - no planning"]  # a - b, modes of the campaign (missing: every comparison)
    metrics = ["passing_time_s"]              # missing: every metric compared
    model = ["paper"]                         # any axis but mode and seed: the cells it takes (missing: all)
    saturation = ["radial"]

A test belongs to the first family that takes it; the tests no family takes make one family per comparison and
metric (`default_family`), as every report did before families were declared. Every report states its families.

The seeds of a campaign are pooled by default (the confirmation seeds are seeds like the others: the more seeds,
the smaller the effect found). Held out (``held_out = true``), the confirmation seeds test only the claims the
other seeds found, each family then made of those claims alone (`confirmed`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Hashable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from vtube_planning.errors import VtubeError
from vtube_planning.studies.stats import (
    NO_VERDICT,
    detectable_shift,
    family_adjusted,
    family_level,
    replicated,
    verdict,
)

SELECTORS = ('comparisons', 'metrics')
"""The keys of a family besides the axes it selects cells by."""


class FamilyError(VtubeError, ValueError):
    """A ``[families]`` table that cannot be read: a family that is not a table, an unknown key, a value that is
    not a list."""


@dataclass(frozen=True)
class Family:
    """A family of claims: its name, the comparisons ("a - b") and metrics it takes (empty: all) and, per axis, the
    values of the cells it takes (an axis missing: every value)."""

    name: str
    comparisons: tuple[str, ...] = ()
    metrics: tuple[str, ...] = ()
    cells: tuple[tuple[str, tuple[Any, ...]], ...] = ()

    def takes(self, test: Mapping[str, Any]) -> bool:
        """Whether a test (a dict with a, b, metric and its cell's axes) is a member."""
        return (
            (not self.comparisons or f'{test["a"]} - {test["b"]}' in self.comparisons)
            and (not self.metrics or test['metric'] in self.metrics)
            and all(test.get(axis) in values for axis, values in self.cells)
        )

    def to_json(self) -> dict[str, Any]:
        """The family as its ``[families.NAME]`` table."""
        keys = {'comparisons': list(self.comparisons), 'metrics': list(self.metrics)}
        return {k: v for k, v in keys.items() if v} | {axis: list(values) for axis, values in self.cells}


def families_from_toml(table: Any) -> tuple[Family, ...]:
    """The families of a ``[families]`` table (module doc), in their order; the axes' values are not checked here
    (the campaign checks them against its axes)."""
    if not isinstance(table, Mapping):
        msg = 'families must be a table of tables, like [families.faster] then metrics = ["passing_time_s"].'
        raise FamilyError(msg)
    out = []
    for name, spec in table.items():
        if not isinstance(spec, Mapping) or not spec:
            msg = f'families.{name} must be a table naming what it takes, like metrics = ["passing_time_s"].'
            raise FamilyError(msg)
        for key, values in spec.items():
            if not isinstance(values, list) or not values:
                msg = f'families.{name}.{key} must be a list of values, like {key} = [...]; got {values!r}.'
                raise FamilyError(msg)
        cells = tuple((axis, tuple(v)) for axis, v in spec.items() if axis not in SELECTORS)
        comparisons, metrics = (tuple(str(v) for v in spec.get(key, ())) for key in SELECTORS)
        out.append(Family(str(name), comparisons, metrics, cells))
    return tuple(out)


@dataclass(frozen=True)
class Judging:
    """How a report judges its claims: its ``families`` and the seeds held out to confirm the claims found (empty:
    every seed pooled)."""

    families: tuple[Family, ...] = ()
    held_out: tuple[int, ...] = ()


POOLED = Judging()
"""Every seed pooled, no family declared: one family per comparison and metric."""


def default_family(test: Mapping[str, Any]) -> str:
    """The family of a test no declared family takes: its comparison and metric."""
    return f'{test["a"]} - {test["b"]}, {test["metric"]}'


def family_of(test: Mapping[str, Any], families: Sequence[Family]) -> str:
    """The name of the first of ``families`` that takes ``test``, else `default_family`."""
    return next((f.name for f in families if f.takes(test)), default_family(test))


def judge(tests: list[dict[str, Any]], families: Sequence[Family]) -> list[dict[str, Any]]:
    """``tests`` (dicts with a, b, metric, better, estimate (an `Estimate` of the differences), p, nonzero (the
    non-zero differences), sd (their standard deviation) and the cell's axes), each given ``family`` (and whether
    it was ``declared``), ``size`` (its family's), ``p_holm`` (`family_adjusted` over its family), ``verdict``
    and ``detectable``: the smallest shift, in SDs of the differences, its seeds find at 80 % power at the
    family's level (`detectable_shift`)."""
    for name in dict.fromkeys(family_of(t, families) for t in tests):
        members = [t for t in tests if family_of(t, families) == name]
        estimates, p_values = [t['estimate'] for t in members], [t['p'] for t in members]
        adjusted = family_adjusted(estimates, p_values, [t['nonzero'] for t in members])
        for t, p in zip(members, adjusted, strict=True):
            t |= {'family': name, 'declared': name != default_family(t), 'size': len(members), 'p_holm': p}
            t['verdict'] = verdict(t['estimate'], t['better'], p)
            t['detectable'] = detectable_shift(t['estimate'].n, family_level(len(members)))
    return tests


def confirmed(
    found: list[dict[str, Any]],
    again: list[dict[str, Any]],
    families: Sequence[Family],
    key: Callable[[Mapping[str, Any]], Hashable],
) -> list[dict[str, Any]]:
    """``found`` (judged on the seeds found on) with the held-out seeds' tests ``again`` (not yet judged; two tests
    are the same claim where their ``key`` is the same): the claims found (holds, reversed) are judged again on the
    held-out seeds alone, each family made of its claims found; each test gets ``discovery_verdict``,
    ``confirmation`` (its test on the held-out seeds; None for a claim not found, which is not tested again) and
    ``verdict``, both's (`replicated`)."""
    claims = {key(t) for t in found if t['verdict'] in ('holds', 'reversed')}
    fresh = {key(t): t for t in judge([t for t in again if key(t) in claims], families)}
    out = []
    for t in found:
        if key(t) not in claims:
            out.append(t | {'discovery_verdict': t['verdict'], 'confirmation': None})
            continue
        again_t = fresh.get(key(t))
        final = replicated(t['verdict'], again_t['verdict']) if again_t else NO_VERDICT
        out.append(t | {'discovery_verdict': t['verdict'], 'confirmation': again_t, 'verdict': final})
    return out


def families_text(tests: Sequence[Mapping[str, Any]]) -> str:
    """The families of judged ``tests`` in words, those declared first: each with its size, its seeds and the shift
    it finds at 80 % power (a line per family, for a report's legend)."""
    lines = []
    declared = {t['family']: t['declared'] for t in tests}
    for name in sorted(declared, key=lambda name: not declared[name]):
        members = [t for t in tests if t['family'] == name]
        seeds = sorted({t['estimate'].n for t in members})
        shifts = sorted({t['detectable'] for t in members})
        n_text = str(seeds[0]) if len(seeds) == 1 else f'{seeds[0]}-{seeds[-1]}'
        shift = ' to '.join(dict.fromkeys(_sd_text(s) for s in (shifts[0], shifts[-1])))
        claims = f'{len(members)} claim' + ('s' if len(members) > 1 else '')
        lines.append(f'- {name}: {claims}, {n_text} pairs each, 80 % power at {shift}')
    return '\n'.join(lines) + '\n'


def _sd_text(shift: float) -> str:
    return 'no shift (too few pairs)' if math.isinf(shift) else f'{shift:.2f} SD'


def detectable_text(test: Mapping[str, Any]) -> str:
    """The effect a "not shown" test's seeds would have found at 80 % power: in SDs of its paired differences and
    in the metric's units (where the differences vary)."""
    shift = test['detectable']
    if math.isinf(shift):
        return 'too few pairs to find any shift'
    units = '' if not np.isfinite(test['sd']) or test['sd'] == 0.0 else f' = {shift * test["sd"]:.3g}'
    return f'80 % power at {shift:.2f} SD{units}'


_PAPER = (('model', ('paper',)), ('saturation', ('radial',)))
_VMAX = 'planning - no planning at v_max'
ABLATION_FAMILIES = (
    Family(
        'faster than no planning (paper model, radial sat)', ('planning - no planning',), ('passing_time_s',), _PAPER
    ),
    Family('faster than no planning at v_max (paper model, radial sat)', (_VMAX,), ('passing_time_s',), _PAPER),
    Family(
        'a larger minimum distance than no planning, at 3.5 m/s or v_max (paper model, radial sat)',
        ('planning - no planning', _VMAX),
        ('min_distance_m',),
        _PAPER,
    ),
    Family('what (p7) buys (paper model, radial sat)', ('planning - planning without (p7)',), (), _PAPER),
)
"""The families of ``vtube ablation``: one per claim the README quotes from it (the paper's model, radial
saturation); its other cells make one family per comparison and metric."""
