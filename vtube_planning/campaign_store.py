"""A campaign's folder: ``campaign.json`` (the campaign) and ``runs.csv`` (one row per run, appended as it comes).

A row holds the run's key, its point, the metrics kept, its wall time, the package version and, for a run that
raised, its error. Reading keeps only whole rows of finished runs, each column typed back.
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from vtube_planning.campaign import AXES, LATER_AXES, METRICS, Campaign, CampaignError, run_key
from vtube_planning.files import write_atomically

RUNS_FILE, CAMPAIGN_FILE = 'runs.csv', 'campaign.json'


def prepare_folder(campaign: Campaign, out: Path, keys: set[str]) -> dict[str, dict[str, Any]]:
    """Check ``out`` before any run (writable, no other campaign in it), record the campaign there, and keep the
    rows of runs already done (each rewritten whole: a line cut by an interruption, or a failed run, is dropped
    and its run done again). Returns the done rows by key."""
    return prepare_table(out, CAMPAIGN_FILE, campaign.to_json(), campaign.columns, keys, what='campaign')


def prepare_table(
    out: Path, record_file: str, record: Mapping[str, Any], columns: list[str], keys: set[str], *, what: str
) -> dict[str, dict[str, Any]]:
    """:func:`prepare_folder` for any table of runs (``runs.csv`` with ``columns``, among them ``key``, ``error``
    and ``version``) recorded with its settings ``record`` in ``out/record_file``; ``what`` names it in errors."""
    recorded = out / record_file
    try:
        out.mkdir(parents=True, exist_ok=True)
        if recorded.is_file():
            previous = json.loads(recorded.read_text(encoding='utf-8'))
            if previous != record:
                msg = (
                    f'{out} holds the results of another {what} ({recorded} differs from this one); '
                    'give another --out, or delete the folder to start again.'
                )
                raise CampaignError(msg)
        done = {}
        table = out / RUNS_FILE
        if table.is_file():
            with table.open(newline='', encoding='utf-8') as handle:
                reader = csv.DictReader(handle)
                later = [c for c in columns if c in LATER_AXES and c not in (reader.fieldnames or columns)]
                if reader.fieldnames is not None and reader.fieldnames != [c for c in columns if c not in later]:
                    msg = f'{table} has other columns than this {what}; give another --out.'
                    raise CampaignError(msg)
                for row in reader:
                    whole = None not in row.values() and None not in row
                    if whole and row['key'] in keys and not row['error'] and row['version']:
                        done[row['key']] = {**{c: LATER_AXES[c] for c in later}, **row}  # a table from before
        write_atomically(recorded, json.dumps(record, indent=1) + '\n')
        write_atomically(table, _csv_text(columns, done.values()))
    except OSError as err:
        msg = f'cannot write to {out} ({err.strerror or err}); choose another --out before any run starts.'
        raise OSError(msg) from err
    return done


def _csv_text(columns: list[str], rows: Iterable[dict[str, Any]]) -> str:
    text = io.StringIO(newline='')
    writer = csv.DictWriter(text, fieldnames=columns)
    writer.writeheader()
    writer.writerows(rows)
    return text.getvalue()


def read_results(out: Path) -> tuple[Campaign, list[dict[str, Any]], int]:
    """A campaign folder's campaign, its finished rows (typed, in the grid's order) and how many runs of the grid
    are not among them (not done yet, or failed)."""
    recorded, table = out / CAMPAIGN_FILE, out / RUNS_FILE
    if not recorded.is_file() or not table.is_file():
        msg = f'{out} holds no campaign ({CAMPAIGN_FILE} and {RUNS_FILE}); run `vtube campaign run FILE --out {out}`.'
        raise CampaignError(msg)
    campaign = Campaign.from_dict(json.loads(recorded.read_text(encoding='utf-8')))
    with table.open(newline='', encoding='utf-8') as handle:
        found = {
            row['key']: row
            for row in csv.DictReader(handle)
            if None not in row.values() and None not in row and not row['error']
        }
    keys = [run_key(p, campaign.settings) for p in campaign.points()]
    rows = [typed_row(found[k], campaign.columns) for k in keys if k in found]
    return campaign, rows, len(keys) - len(rows)


def typed_row(row: Mapping[str, Any], columns: list[str]) -> dict[str, Any]:
    """A table row with each column of its known type again (numbers, booleans; an empty metric is NaN)."""
    kinds: dict[str, type] = AXES | METRICS | {'wall_s': float}
    return {c: _typed(row[c] if c in row or c not in LATER_AXES else LATER_AXES[c], kinds.get(c, str)) for c in columns}


def _typed(value: Any, kind: type) -> Any:
    if not isinstance(value, str):
        return value
    if kind is bool:
        return value == 'True'
    if kind in (int, float) and value == '':
        return math.nan
    return kind(value)
