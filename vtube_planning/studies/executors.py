"""Where a study's independent runs execute: in this process, in local processes, or on a Dask cluster.

`map_unordered` hands each item to ``fn`` and yields ``(index, result)`` as the results come, in whatever
order they finish; the caller stores each at once. One worker runs in this process (what tests patch and
debuggers step into); more start fresh processes (``spawn``: nothing of the parent's state leaks into a run); a
``dask.distributed.Client`` sends the items to its cluster, whose workers must have vtube installed. Stopping the
iteration (an interrupt, an error in the caller) cancels what has not started; a local worker whose parent is gone
(killed, even by ``kill -9``) ends itself within `WATCH_PARENT_S` (`die_with_parent`).

Dask is an optional extra (``pip install 'vtube[cluster]'``); `connect` names it when it is missing.
"""

from __future__ import annotations

import contextlib
import logging
import multiprocessing
import os
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from typing import Any

from vtube_planning.errors import VtubeError


class ExecutorError(VtubeError, RuntimeError):
    """An executor that cannot be reached or set up (a Dask scheduler that does not answer, Dask not installed)."""


def map_unordered(
    fn: Callable[[Any], Any], items: Sequence[Any], *, workers: int = 1, client: Any = None
) -> Iterator[tuple[int, Any]]:
    """``(i, fn(items[i]))`` for every item, as each finishes: in this process (``workers`` 1), in ``workers``
    local processes, or on the cluster of the Dask ``client``. An exception raised by ``fn`` propagates."""
    if client is not None:
        yield from _dask(fn, items, client)
    elif workers <= 1 or len(items) <= 1:
        for i, item in enumerate(items):
            yield i, fn(item)
    else:
        yield from _processes(fn, items, workers)


WATCH_PARENT_S = 0.5
"""How often a local worker looks whether the process that started it is still there."""


def die_with_parent(parent_pid: int) -> None:
    """Initializer of every local worker: a daemon thread ends the worker as soon as ``parent_pid`` is no longer
    its parent (the campaign was killed, ``kill -9`` included: nobody would store what it computes). The worker
    computes on one thread (numba's, for the foresight of a large swarm): the workers already share the cores."""
    os.environ['NUMBA_NUM_THREADS'] = '1'

    def watch() -> None:
        while True:
            time.sleep(WATCH_PARENT_S)
            if os.getppid() != parent_pid:
                os._exit(1)

    threading.Thread(target=watch, name='vtube-watch-parent', daemon=True).start()


def _processes(fn: Callable[[Any], Any], items: Sequence[Any], workers: int) -> Iterator[tuple[int, Any]]:
    pool = ProcessPoolExecutor(
        min(workers, len(items)),
        mp_context=multiprocessing.get_context('spawn'),
        initializer=die_with_parent,
        initargs=(os.getpid(),),
    )
    futures: dict[Future[Any], int] = {pool.submit(fn, item): i for i, item in enumerate(items)}
    try:
        pending = set(futures)
        while pending:
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            for future in sorted(done, key=futures.__getitem__):
                yield futures[future], future.result()
    finally:
        pool.shutdown(wait=False, cancel_futures=True)


def _dask(fn: Callable[[Any], Any], items: Sequence[Any], client: Any) -> Iterator[tuple[int, Any]]:
    from concurrent.futures import CancelledError

    from distributed import KilledWorker, as_completed
    from distributed.comm.core import CommClosedError

    lost = (KilledWorker, CommClosedError, CancelledError, TimeoutError)  # the cluster's failures, not fn's errors

    futures = client.map(fn, list(items), pure=False)
    index = {future.key: i for i, future in enumerate(futures)}
    try:
        with _client_quiet():
            for future in as_completed(futures):
                yield index[future.key], future.result()
    except lost as err:
        for name in ('distributed', 'distributed.client'):  # its reconnection tracebacks, then: said here, once
            logging.getLogger(name).setLevel(logging.CRITICAL)
        where = getattr(getattr(client, 'scheduler', None), 'address', None)
        msg = (
            f'the Dask cluster{f" of the scheduler at {where}" if where else ""} failed during the runs '
            f'({type(err).__name__}: {" ".join(str(err).split())}); every run finished before it is kept: start the '
            'cluster again and rerun the same command.'
        )
        raise ExecutorError(msg) from err
    finally:
        with contextlib.suppress(Exception):  # a scheduler that is gone takes no cancellation
            client.cancel(futures)


@contextlib.contextmanager
def _client_quiet() -> Iterator[None]:
    """While the runs go, distributed's client logs nothing below CRITICAL: a lost scheduler is logged there
    ("Failed to reconnect to scheduler ..., closing client") before its futures fail, and the one error line of
    `_dask` says it, with the scheduler's address."""
    logger = logging.getLogger('distributed.client')
    level = logger.level
    logger.setLevel(logging.CRITICAL)
    try:
        yield
    finally:
        logger.setLevel(level)


def connect(address: str, timeout_s: float = 10.0) -> Any:
    """A ``dask.distributed.Client`` of the scheduler at ``address`` (``tcp://HOST:PORT``), or a clear error within
    ``timeout_s`` when none answers or Dask is not installed."""
    try:
        from distributed import Client
    except ImportError as err:
        msg = (
            f'a Dask scheduler ({address}) needs the cluster extra: pip install "vtube[cluster]"; '
            'or leave out --scheduler to run on local processes.'
        )
        raise ExecutorError(msg) from err
    try:
        client = Client(address, timeout=timeout_s)
    except (OSError, TimeoutError, ValueError) as err:
        msg = (
            f'no Dask scheduler answered at {address} within {timeout_s:g} s ({" ".join(str(err).split())}); '
            'check the address, start one with `dask scheduler`, or raise --scheduler-timeout.'
        )
        raise ExecutorError(msg) from err
    try:
        checked_workers(client, address, timeout_s)
    except BaseException:
        client.close()
        raise
    return client


def checked_workers(client: Any, address: str, timeout_s: float) -> None:
    """Refuse a cluster that would hang or mix results: no worker within ``timeout_s``, or a worker that cannot
    import vtube or runs another version of it than this process."""
    try:
        client.wait_for_workers(1, timeout=timeout_s)
    except (OSError, TimeoutError) as err:
        msg = (
            f'the Dask scheduler at {address} has no worker after {timeout_s:g} s; start one with `dask worker '
            f'{address}` where vtube is installed, or raise --scheduler-timeout.'
        )
        raise ExecutorError(msg) from err
    try:
        versions = client.run(_vtube_version)
    except Exception as err:  # whatever the worker raised (ModuleNotFoundError: no vtube there), named below
        msg = (
            f'a worker of the Dask scheduler at {address} cannot run vtube ({type(err).__name__}: '
            f'{" ".join(str(err).split())}); install it there: pip install "vtube[cluster]".'
        )
        raise ExecutorError(msg) from err
    other = {worker: v for worker, v in versions.items() if v != _vtube_version()}
    if other:
        worker, version = next(iter(other.items()))
        msg = (
            f'the Dask worker {worker} runs vtube {version}, this process {_vtube_version()}: their rows would mix; '
            'install the same version on every worker.'
        )
        raise ExecutorError(msg)


def _vtube_version() -> str:
    """The version of vtube this process (or a worker) runs."""
    from vtube_planning import __version__

    return __version__
