"""The preflight's runs over the cores: two batches, ideal (and PyPI) first, the reports in the order of the jobs."""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass

from submission.schedule import Job, batch, flights


@dataclass(frozen=True)
class Ran:
    job: Job
    ok: bool


def runner(failing: set[str], log: list[Job], delay_s: float = 0.0):
    def run(job: Job) -> Ran:
        log.append(job)
        time.sleep(delay_s * (job[1] or 0))  # a later seed ends later: completion order is not the jobs' order
        return Ran(job, job[2] not in failing)

    return run


def test_ideal_and_pypi_first_then_the_other_models_reported_by_model() -> None:
    log: list[Job] = []
    started: list[Job] = []
    by_model, pypi = flights(
        runner(set(), log), (0, 1), ('ideal', 'fitted', 'fitted:2'), pypi=True, starts=started.append, workers=1
    )
    ideal = [('bundled', 0, 'ideal'), ('bundled', 1, 'ideal'), ('pypi', None, 'ideal')]
    assert log == started == [*ideal, *[('bundled', s, m) for m in ('fitted', 'fitted:2') for s in (0, 1)]]
    assert list(by_model) == ['ideal', 'fitted', 'fitted:2']
    assert [[r.job for r in runs] for runs in by_model.values()] == [
        [('bundled', s, m) for s in (0, 1)] for m in ('ideal', 'fitted', 'fitted:2')
    ]
    assert [r.job for r in pypi] == [('pypi', None, 'ideal')]


def test_a_file_that_fails_in_the_ideal_simulator_flies_no_other_model() -> None:
    log: list[Job] = []
    by_model, pypi = flights(runner({'ideal'}, log), (0,), ('ideal', 'fitted'), pypi=False)
    assert list(by_model) == ['ideal'] and pypi == [] and log == [('bundled', 0, 'ideal')]
    log.clear()
    by_model, _ = flights(runner({'fitted'}, log), (0,), ('fitted', 'fitted:2'), pypi=False)  # no ideal: one batch
    assert list(by_model) == ['fitted', 'fitted:2'] and len(log) == 2


def test_a_batch_runs_its_jobs_at_once_and_reports_them_in_order() -> None:
    jobs: list[Job] = [('bundled', seed, 'ideal') for seed in (3, 2, 1, 0)]
    threads: set[int] = set()

    def run(job: Job) -> Ran:
        threads.add(threading.get_ident())
        time.sleep(0.02 * (job[1] or 0))
        return Ran(job, True)

    assert [r.job for r in batch(run, jobs, lambda job: None, 4)] == jobs
    assert len(threads) > 1 and batch(run, [], lambda job: None, None) == []
