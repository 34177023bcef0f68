"""Running a campaign: every run not yet in its folder, on an executor, each row stored as it comes."""

from __future__ import annotations

import csv
import signal
import sys
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import asdict, dataclass
from pathlib import Path
from types import FrameType
from typing import Any

from tqdm import tqdm

from vtube_planning import __version__
from vtube_planning.geometry.scene import load_scene
from vtube_planning.provenance import provenance, sha256_of, source_commit
from vtube_planning.studies.campaign import Campaign, CampaignError, run_key
from vtube_planning.studies.campaign_store import RUNS_FILE, holding, prepare_folder, record_made, typed_row
from vtube_planning.studies.executors import map_unordered
from vtube_planning.studies.study import Point, RunSettings, run_point


@dataclass(frozen=True)
class Outcome:
    """What a campaign run did: ``rows`` (every run's row in the grid's order: done before, run now and failed),
    how many were skipped as already done, run now and failed, and the seconds it took."""

    rows: list[dict[str, Any]]
    skipped: int
    ran: int
    failed: int
    seconds: float


def run_campaign(
    campaign: Campaign,
    out: Path,
    *,
    workers: int = 1,
    client: Any = None,
    progress: bool | None = None,
) -> Outcome:
    """Run every run of ``campaign`` not yet in ``out/runs.csv`` (`map_unordered`:
    ``workers`` local processes, or the Dask ``client``), appending each row as it comes.

    The folder is held while the campaign runs (`holding`: a second run on it
    is refused) and checked before any run starts: writable, holding no other campaign, and no finished run made
    with another version of the package or another text of its scene file. ``progress`` draws a bar
    on stderr (runs done / total, failures, elapsed and remaining time); None: when stderr is a terminal. An
    interruption leaves every finished row in the table; the same call again runs only the missing ones. Ctrl-C
    stops it even when Python drops the KeyboardInterrupt (raised inside a finaliser, "Exception ignored"): the
    interruption is noted, and the loop stops after the row of the run it fell in.
    """
    started = time.perf_counter()
    points = campaign.points()
    keys = [run_key(p, campaign.settings) for p in points]
    scenes = {
        name: sha256_of(load_scene(campaign.scene_path(name)).text) for name in dict.fromkeys(p.scene for p in points)
    }
    expected = {k: {'version': __version__, 'scene_sha256': scenes[p.scene]} for p, k in zip(points, keys, strict=True)}
    with holding(out, 'campaign'):
        done = prepare_folder(campaign, out, expected)
        waiting = [p for p, k in zip(points, keys, strict=True) if k not in done]
        todo = [(campaign.runnable(p), campaign.settings, campaign.metrics) for p in waiting]
        if todo:
            record_made(out, provenance() | {'commit': source_commit(), 'done_before': len(done), 'to_run': len(todo)})
        rows, failed = dict(done), 0
        show = sys.stderr.isatty() if progress is None else progress
        bar = tqdm(total=len(points), initial=len(points) - len(todo), unit='run', disable=not show, file=sys.stderr)
        with (out / RUNS_FILE).open('a', newline='', encoding='utf-8') as handle, bar, _noting_interrupts() as noted:
            writer = csv.DictWriter(handle, fieldnames=campaign.columns)
            for i, row in map_unordered(run_row, todo, workers=workers, client=client):
                point = waiting[i]  # as recorded: its scene file named relative to the campaign file
                if row['version'] != __version__:
                    msg = (
                        f'a worker runs vtube {row["version"]}, this process {__version__}: their rows would mix. '
                        'Install the same version everywhere the campaign runs.'
                    )
                    raise CampaignError(msg)
                row = {'key': run_key(point, campaign.settings), **asdict(point), **row}
                row['scene_sha256'] = scenes[point.scene]
                writer.writerow(row)
                handle.flush()
                rows[row['key']] = row
                failed += bool(row['error'])
                bar.update()
                bar.set_postfix(failed=failed, refresh=False)
                if noted.is_set():
                    raise KeyboardInterrupt
    ordered = [typed_row(rows[k], campaign.columns) for k in keys]
    return Outcome(ordered, len(points) - len(todo), len(todo), failed, time.perf_counter() - started)


@contextmanager
def _noting_interrupts() -> Iterator[threading.Event]:
    """While inside, SIGINT (Ctrl-C) sets the event it yields before raising KeyboardInterrupt as Python does; off
    the main thread, where no handler can be installed, the event is never set."""
    noted = threading.Event()
    if threading.current_thread() is not threading.main_thread():
        yield noted
        return
    previous = signal.getsignal(signal.SIGINT)

    def note(signum: int, frame: FrameType | None) -> None:
        noted.set()
        signal.default_int_handler(signum, frame)

    signal.signal(signal.SIGINT, note)
    try:
        yield noted
    finally:
        signal.signal(signal.SIGINT, previous)


def run_row(job: tuple[Point, RunSettings, tuple[str, ...]]) -> dict[str, Any]:
    """One run (in a worker): its metrics, wall time and version; a run that raises gives its error instead."""
    point, settings, metrics = job
    started = time.perf_counter()
    try:
        measured = run_point(point, settings)
        row: dict[str, Any] = {m: measured[m] for m in metrics} | {'error': ''}
    except Exception as err:  # noqa: BLE001 - recorded in the table; the other runs go on
        row = dict.fromkeys(metrics, '') | {'error': f'{type(err).__name__}: {" ".join(str(err).split())}'}
    return row | {'wall_s': round(time.perf_counter() - started, 3), 'version': __version__}
