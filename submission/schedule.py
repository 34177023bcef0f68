"""The preflight's runs of a file spread over the cores: which run goes when, and the order they are reported in.

Each run is a process of its own (`submission.check.run_file`), so ``workers`` of them run at once (default: one
per core). They go in two batches: the runs under the testbed models up to ``ideal`` and the PyPI simulator's run;
then, when every ideal run is fine, the runs under the models after it (a file that fails in the ideal simulator
gets no margins). The reports come back in the order a run after another would give them.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import Literal, Protocol, TypeVar

Job = tuple[Literal['bundled', 'pypi'], int | None, str]
"""One run: the simulator, the seed (None: unseeded), the testbed model."""


class Judged(Protocol):
    @property
    def ok(self) -> bool: ...


R = TypeVar('R', bound=Judged)


def flights(
    run: Callable[[Job], R],
    seeds: Sequence[int],
    models: Sequence[str],
    *,
    pypi: bool,
    starts: Callable[[Job], None] = lambda job: None,
    workers: int | None = None,
) -> tuple[dict[str, list[R]], list[R]]:
    """The runs per testbed model in ``models``' order (a model not flown is absent), and the PyPI simulator's run
    (``pypi``: it is installed); ``starts`` is told of each run as its batch starts."""
    cut = models.index('ideal') + 1 if 'ideal' in models else len(models)
    jobs: list[Job] = [('bundled', seed, model) for model in models for seed in seeds]
    n, ideal = cut * len(seeds), (cut - 1) * len(seeds) if 'ideal' in models else 0
    first = batch(run, jobs[:n] + ([('pypi', None, 'ideal')] if pypi else []), starts, workers)
    done = first[:n] + (batch(run, jobs[n:], starts, workers) if all(r.ok for r in first[ideal:n]) else [])
    flown = models[: len(done) // len(seeds)] if seeds else models
    return {model: done[k * len(seeds) : (k + 1) * len(seeds)] for k, model in enumerate(flown)}, first[n:]


def batch(run: Callable[[Job], R], jobs: list[Job], starts: Callable[[Job], None], workers: int | None) -> list[R]:
    """``run`` of each job, ``workers`` at a time (default: one per core); the results in the jobs' order."""
    for job in jobs:
        starts(job)
    if not jobs:
        return []
    with ThreadPoolExecutor(max(1, min(workers or os.cpu_count() or 1, len(jobs)))) as pool:
        return list(pool.map(run, jobs))
