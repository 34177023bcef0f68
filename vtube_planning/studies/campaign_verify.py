"""Whether a campaign folder holds what the code as it is produces: runs made again and compared, the report too.

Results committed beside the code (``docs/*/runs.csv`` and their ``report.md``) go stale when the code changes.
`verify` takes the folder's finished runs (all, or ``runs`` of them spread evenly over the table), makes each
again with this code (the same point and settings, through the runner's own `run_row`) and compares every
metric the table keeps: counts and flags exactly, numbers to a relative 1e-9 (the table holds them as Python
writes floats, exactly); and it writes the report again from the table (`campaign_report_text`) and compares it with
the folder's ``report.md``, word for word. Figures are not compared (they are drawn from the same rows). The
folder's ``provenance.json`` says which commit and command made the runs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from vtube_planning.studies.campaign import AXES, METRICS
from vtube_planning.studies.campaign_runner import run_row
from vtube_planning.studies.campaign_store import made_by, read_results
from vtube_planning.studies.crossover import campaign_report_text
from vtube_planning.studies.executors import map_unordered
from vtube_planning.studies.study import Point

REPORT_FILE = 'report.md'
RELATIVE = 1e-9


@dataclass(frozen=True)
class Difference:
    """A metric of one run that the code gives otherwise now: the run's key, the column, the two values."""

    key: str
    column: str
    recorded: Any
    now: Any


@dataclass(frozen=True)
class Verification:
    """What `verify` found: runs made again of the finished ones, their differences, and whether the report
    is the one the table gives now (None: the folder has no report)."""

    checked: int
    finished: int
    differences: tuple[Difference, ...]
    report_matches: bool | None
    made: tuple[dict[str, Any], ...]

    @property
    def ok(self) -> bool:
        return not self.differences and self.report_matches is not False


def verify(out: Path, *, runs: int | None = None, workers: int = 1, client: Any = None) -> Verification:
    """Make ``runs`` of the folder's finished runs again (None: all), spread evenly over the table, and compare
    them and its report with what this code gives (module doc)."""
    campaign, rows, missing = read_results(out)
    made = made_by(out)
    chosen = rows if runs is None or runs >= len(rows) else [rows[int(k)] for k in _spread(len(rows), runs)]
    points = [campaign.runnable(Point(**{axis: row[axis] for axis in AXES})) for row in chosen]
    jobs = [(point, campaign.settings, campaign.metrics) for point in points]
    differences = []
    for i, again in sorted(map_unordered(run_row, jobs, workers=workers, client=client), key=lambda found: found[0]):
        row = chosen[i]
        for column in (*campaign.metrics, 'error'):
            if not _same(row[column], again[column], METRICS.get(column, str)):
                differences.append(Difference(row['key'], column, row[column], again[column]))
    report = out / REPORT_FILE
    matches = None
    if report.is_file():
        text = campaign_report_text(campaign, rows, missing, made)
        matches = report.read_text(encoding='utf-8') == text
    return Verification(len(chosen), len(rows), tuple(differences), matches, tuple(made))


def _spread(total: int, count: int) -> list[int]:
    """``count`` indices of ``range(total)`` spread evenly, first and last included."""
    return sorted({round(k) for k in np.linspace(0, total - 1, max(count, 1))})


def _same(recorded: Any, now: Any, kind: type) -> bool:
    """Whether a recorded value and a new one agree: floats to RELATIVE (NaN with NaN), anything else exactly."""
    if kind is float and recorded != '' and now != '':
        a, b = float(recorded), float(now)
        return (math.isnan(a) and math.isnan(b)) or math.isclose(a, b, rel_tol=RELATIVE, abs_tol=1e-12)
    if kind in (int, bool) and recorded != '' and now != '':
        return kind(recorded) == kind(now)
    return str(recorded) == str(now)
