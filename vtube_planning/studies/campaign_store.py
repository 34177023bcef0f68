"""A campaign's folder: ``campaign.json`` (the campaign), ``runs.csv`` (one row per run, appended as it comes) and
``provenance.json`` (what made the runs: each sitting's command, version, git commit and time).

A row holds the run's key, its point, the metrics kept, its wall time, the package version and, for a run that
raised, its error. Reading keeps only whole rows of finished runs, each column typed back.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import socket
import time
from collections.abc import Collection, Iterable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path
from typing import Any

from vtube_planning.files import write_atomically
from vtube_planning.studies.campaign import AXES, LATER_COLUMNS, METRICS, REPORT_KEYS, Campaign, CampaignError, run_key
from vtube_planning.studies.study import Point

RUNS_FILE, CAMPAIGN_FILE, LOCK_FILE, MADE_FILE = 'runs.csv', 'campaign.json', '.lock', 'provenance.json'


@contextmanager
def holding(out: Path, what: str) -> Iterator[None]:
    """Hold ``out`` for one run of a table while inside: ``out/.lock``, created exclusively, names this process; a
    second run on the folder is refused (`CampaignError`, naming who holds it) instead of writing the same
    table, so no finished row can be lost or written twice. A lock left by a process of this machine that is gone
    (killed) is taken over; the lock is removed on leaving."""
    out.mkdir(parents=True, exist_ok=True)
    lock = out / LOCK_FILE
    me = {'pid': os.getpid(), 'host': socket.gethostname(), 'since': time.strftime('%Y-%m-%dT%H:%M:%S')}
    for _ in range(2):
        try:
            descriptor = os.open(lock, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
        except FileExistsError:
            holder = _holder(lock)
            if holder.get('host') == me['host'] and not _alive(holder.get('pid')):
                lock.unlink(missing_ok=True)  # left by a run that was killed: take it over
                continue
            msg = (
                f'{out} is being written by another {what} run (process {holder.get("pid", "?")} on '
                f'{holder.get("host", "?")}, since {holder.get("since", "?")}); wait for it to finish, or, if that '
                f'run is dead, delete {lock}.'
            )
            raise CampaignError(msg) from None
        with os.fdopen(descriptor, 'w', encoding='utf-8') as handle:
            json.dump(me, handle)
        break
    else:
        msg = f'{out}: could not take {lock} (another run took it meanwhile); run again.'
        raise CampaignError(msg)
    try:
        yield
    finally:
        if _holder(lock) == me:
            lock.unlink(missing_ok=True)


def _holder(lock: Path) -> dict[str, Any]:
    try:
        holder = json.loads(lock.read_text(encoding='utf-8'))
    except (OSError, ValueError):
        return {}
    return holder if isinstance(holder, dict) else {}


def _recorded(path: Path) -> dict[str, Any]:
    """The campaign (or sweep) a folder records, as the JSON object written there."""
    try:
        recorded = json.loads(path.read_text(encoding='utf-8'))
    except (UnicodeDecodeError, ValueError) as err:
        msg = (
            f'{path} is not the JSON vtube wrote there ({err}); delete the folder to start again, or restore the file.'
        )
        raise CampaignError(msg) from err
    if not isinstance(recorded, dict):
        msg = f'{path} holds a JSON {type(recorded).__name__}, not the object vtube wrote there; restore the file.'
        raise CampaignError(msg)
    return recorded


def _alive(pid: object) -> bool:
    """Whether a process of this machine with this id exists (True when it cannot be told)."""
    if not isinstance(pid, int) or pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True
    return True


def prepare_folder(
    campaign: Campaign, out: Path, expected: Mapping[str, Mapping[str, str]]
) -> dict[str, dict[str, Any]]:
    """Check ``out`` before any run (writable, no other campaign in it), record the campaign there, and keep the
    rows of runs already done (each rewritten whole: a line cut by an interruption, or a failed run, is dropped
    and its run done again). ``expected``: per run's key, what its row must record (`prepare_table`).
    A recorded campaign that differs only in how its report judges (REPORT_KEYS) is the same; the new one is
    recorded. Returns the done rows by key."""
    record = campaign.to_json()
    if campaign.base is not None and _named_files(campaign):
        record[SCENE_FOLDER] = str(campaign.base.resolve())
    apart = (*REPORT_KEYS, SCENE_FOLDER)
    if (out / CAMPAIGN_FILE).is_file():
        _rename_scenes(campaign, out, record, apart)
    return prepare_table(out, CAMPAIGN_FILE, record, campaign.columns, expected, what='campaign', apart=apart)


SCENE_FOLDER = 'scene_folder'
"""The key of ``campaign.json`` that records where the campaign file was (absolute), whose folder its relative
scene files are named from: not part of what the campaign is (the same file run from another working directory,
or moved with its scenes, is the same campaign); `read_results` finds the scenes there."""


def _named_files(campaign: Campaign) -> bool:
    """Whether a grid names a scene file relative to the campaign file."""
    return any(campaign.scene_path(s) != s for grid in campaign.grids for s in grid['scene'])


def _rename_scenes(campaign: Campaign, out: Path, record: Mapping[str, Any], apart: Collection[str]) -> None:
    """Rewrite a folder of ``campaign`` made before scene files were recorded relative to the campaign file (issue
    49, item 16: relative to the working directory) in today's form, when its record names the same files: each
    scene file it names, found relative to the campaign file or, failing that, to the working directory, is the
    file ``campaign`` names (the same resolved path; the scene's hash in each row is checked when resuming). The
    whole rows are keyed again for the names of today (runs.csv first, then campaign.json: a folder left between the
    two is rewritten again). Nothing changes in a folder of another campaign, or one in today's form."""
    previous = _recorded(out / CAMPAIGN_FILE)
    renamed = _old_names(campaign, previous)
    if not renamed:
        return
    grids = [{**grid, 'scene': [renamed.get(s, s) for s in grid['scene']]} for grid in previous['grids']]
    if _without({**previous, 'grids': grids}, apart) != _without(record, apart):
        return  # another campaign: `prepare_table` says so
    table = out / RUNS_FILE
    if table.is_file():
        with table.open(newline='', encoding='utf-8') as handle:
            reader = csv.DictReader(handle)
            rows = [row for row in reader if None not in row.values() and None not in row]  # whole, as resumed
        columns = list(reader.fieldnames or ())
        write_atomically(table, _csv_text(columns, [_keyed_again(row, renamed, campaign) for row in rows]))
    write_atomically(out / CAMPAIGN_FILE, json.dumps({**previous, 'grids': grids}, indent=1) + '\n')


def _old_names(campaign: Campaign, previous: Mapping[str, Any]) -> dict[str, str]:
    """The scene files a recorded campaign names otherwise than ``campaign`` does, each by ``campaign``'s name for
    the same file (`_rename_scenes`)."""
    named = {
        Path(campaign.scene_path(s)).resolve(): s for g in campaign.grids for s in g['scene'] if s.endswith('.toml')
    }
    ours = set(named.values())
    renamed: dict[str, str] = {}
    grids = previous.get('grids')
    if not isinstance(grids, list) or not all(isinstance(g, dict) and isinstance(g.get('scene'), list) for g in grids):
        return renamed  # not a record vtube wrote: `prepare_table` refuses it
    for grid in grids:
        for scene in grid['scene']:
            if not isinstance(scene, str) or not scene.endswith('.toml') or scene in ours:
                continue
            found = [Path(p) for p in (campaign.scene_path(scene), scene) if Path(p).is_file()]
            if found and found[0].resolve() in named:
                renamed[scene] = named[found[0].resolve()]
    return renamed


def _keyed_again(row: dict[str, Any], renamed: Mapping[str, str], campaign: Campaign) -> dict[str, Any]:
    """A runs.csv row of a renamed scene (`_rename_scenes`) with today's name and key; any other row as it is (a
    row whose key is not its point's, edited or cut, too: resuming runs it again)."""
    if row.get('scene') not in renamed:
        return row
    try:
        point = Point(**{axis: value for axis, value in typed_row(row, campaign.columns).items() if axis in AXES})
    except (CampaignError, TypeError, ValueError):
        return row
    if run_key(point, campaign.settings) != row['key']:
        return row
    point = replace(point, scene=renamed[point.scene])
    return {**row, 'scene': point.scene, 'key': run_key(point, campaign.settings)}


def prepare_table(
    out: Path,
    record_file: str,
    record: Mapping[str, Any],
    columns: list[str],
    expected: Mapping[str, Mapping[str, str]],
    *,
    what: str,
    apart: Collection[str] = (),
) -> dict[str, dict[str, Any]]:
    """`prepare_folder` for any table of runs (``runs.csv`` with ``columns``, among them ``key``, ``error``
    and ``version``) recorded with its settings ``record`` in ``out/record_file``; ``what`` names it in errors.
    ``expected`` holds the keys of the runs and, per key, the columns a finished row must hold as they are now
    (the package's version, the scene file's hash): a finished row that records another value is refused, not
    resumed (an empty value, from a table written before the column existed, is accepted). The keys ``apart``
    of ``record`` are not compared."""
    recorded = out / record_file
    try:
        out.mkdir(parents=True, exist_ok=True)
        if recorded.is_file():
            previous = _recorded(recorded)
            if _without(previous, apart) != _without(record, apart):
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
                later = [c for c in columns if c in LATER_COLUMNS and c not in (reader.fieldnames or columns)]
                if reader.fieldnames is not None and reader.fieldnames != [c for c in columns if c not in later]:
                    msg = f'{table} has other columns than this {what}; give another --out.'
                    raise CampaignError(msg)
                for row in reader:
                    whole = None not in row.values() and None not in row
                    if whole and row['key'] in expected and not row['error'] and row['version']:
                        done[row['key']] = {**{c: LATER_COLUMNS[c] for c in later}, **row}  # a table from before
        changed = {
            (c, done[k][c], v) for k in done for c, v in expected[k].items() if done[k].get(c, '') not in ('', v)
        }
        if changed:
            found = '; '.join(f'{c} {old!r} where this run has {new!r}' for c, old, new in sorted(changed)[:3])
            msg = (
                f'{table} holds finished runs made otherwise ({found}): resuming would mix their results with new '
                'ones. Give another --out, or delete the folder to run them all again.'
            )
            raise CampaignError(msg)
        write_atomically(recorded, json.dumps(record, indent=1) + '\n')
        write_atomically(table, _csv_text(columns, done.values()))
    except OSError as err:
        msg = f'cannot write to {out} ({err.strerror or err}); choose another --out before any run starts.'
        raise OSError(msg) from err
    return done


def _without(record: Mapping[str, Any], keys: Collection[str]) -> dict[str, Any]:
    return {k: v for k, v in record.items() if k not in keys}


def _csv_text(columns: list[str], rows: Iterable[dict[str, Any]]) -> str:
    text = io.StringIO(newline='')
    writer = csv.DictWriter(text, fieldnames=columns)
    writer.writeheader()
    writer.writerows(rows)
    return text.getvalue()


def record_made(out: Path, entry: Mapping[str, Any]) -> None:
    """Add ``entry`` (what made the runs of one sitting: command, version, commit, time, how many) to the folder's
    MADE_FILE, a JSON list, one entry per sitting that ran something."""
    write_atomically(out / MADE_FILE, json.dumps([*made_by(out), dict(entry)], indent=1) + '\n')


def made_by(out: Path) -> list[dict[str, Any]]:
    """The entries of `record_made` (none for a folder from before it)."""
    path = out / MADE_FILE
    if not path.is_file():
        return []
    try:
        entries = json.loads(path.read_text(encoding='utf-8'))
    except (UnicodeDecodeError, ValueError) as err:
        msg = f'{path} is not the JSON vtube wrote there ({err}); restore it, or delete it to start the record again.'
        raise CampaignError(msg) from err
    if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
        msg = f'{path} must hold a list of JSON objects, as vtube writes it; restore it, or delete it.'
        raise CampaignError(msg)
    return entries


def read_results(out: Path) -> tuple[Campaign, list[dict[str, Any]], int]:
    """A campaign folder's campaign, its finished rows (typed, in the grid's order) and how many runs of the grid
    are not among them (not done yet, or failed)."""
    recorded, table = out / CAMPAIGN_FILE, out / RUNS_FILE
    if not recorded.is_file() or not table.is_file():
        msg = f'{out} holds no campaign ({CAMPAIGN_FILE} and {RUNS_FILE}); run `vtube campaign run FILE --out {out}`.'
        raise CampaignError(msg)
    data = _recorded(recorded)
    folder = data.pop(SCENE_FOLDER, None)
    campaign = Campaign.from_dict(data, base=Path(folder) if isinstance(folder, str) else None)
    with table.open(newline='', encoding='utf-8') as handle:
        found = {
            row['key']: row
            for row in csv.DictReader(handle)
            if None not in row.values() and None not in row and not row['error']
        }
    keys = [run_key(p, campaign.settings) for p in campaign.points()]
    rows = []
    for key in (k for k in keys if k in found):
        try:
            rows.append(typed_row(found[key], campaign.columns))
        except CampaignError as err:
            msg = (
                f'{table}, the run {key}: {err} (the table was edited): restore the file, or delete the row and '
                'rerun the campaign to run it again.'
            )
            raise CampaignError(msg) from err
    return campaign, rows, len(keys) - len(rows)


def typed_row(row: Mapping[str, Any], columns: list[str]) -> dict[str, Any]:
    """A table row with each column of its known type again (numbers, booleans; an empty metric is NaN); a value
    that is not of its column's type (a table edited by hand) raises `CampaignError` naming it."""
    kinds: dict[str, type] = AXES | METRICS | {'wall_s': float}
    return {
        c: _typed(row[c] if c in row or c not in LATER_COLUMNS else LATER_COLUMNS[c], kinds.get(c, str), c)
        for c in columns
    }


def _typed(value: Any, kind: type, column: str) -> Any:
    if not isinstance(value, str):
        return value
    if kind in (int, float) and value == '':
        return math.nan
    try:
        return {'True': True, 'False': False, '': False}[value] if kind is bool else kind(value)  # '': a failed run
    except (KeyError, ValueError):
        words = {int: 'a whole number', float: 'a number', bool: 'True or False'}.get(kind, kind.__name__)
        msg = f'{column} = {value!r} is not {words}'
        raise CampaignError(msg) from None
