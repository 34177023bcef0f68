"""map_unordered in this process (order, errors, stopping early) and connect's errors; the process pool and a
Dask cluster run in tests/integration/test_planning_executors.py and test_planning_campaign.py."""

from __future__ import annotations

import sys
from types import SimpleNamespace

import pytest

from vtube_planning.errors import VtubeError
from vtube_planning.studies.executors import ExecutorError, connect, map_unordered


def test_one_worker_runs_every_item_here_in_order() -> None:
    seen: list[int] = []

    def square(x: int) -> int:
        seen.append(x)
        return x * x

    assert list(map_unordered(square, [3, 1, 2])) == [(0, 9), (1, 1), (2, 4)]
    assert seen == [3, 1, 2]
    assert list(map_unordered(square, [5], workers=4)) == [(0, 25)]  # one item: no pool either
    assert list(map_unordered(square, [])) == []


def test_an_error_in_a_run_propagates_after_the_runs_before_it() -> None:
    def fail_on_two(x: int) -> int:
        if x == 2:
            msg = 'two is bad'
            raise ValueError(msg)
        return x

    results = map_unordered(fail_on_two, [0, 1, 2, 3])
    assert next(results) == (0, 0) and next(results) == (1, 1)
    with pytest.raises(ValueError, match='two is bad'):
        next(results)


def test_stopping_the_iteration_runs_nothing_more() -> None:
    """What an interrupt does to a campaign here: the items not yet started never run (the campaign resumes them)."""
    ran: list[int] = []
    results = map_unordered(ran.append, list(range(10)))
    assert [i for i, _ in zip(range(3), results, strict=False)] == [0, 1, 2]
    results.close()
    assert ran == [0, 1, 2]


def test_a_cluster_without_dask_installed_is_named(monkeypatch) -> None:
    monkeypatch.setitem(sys.modules, 'distributed', None)
    with pytest.raises(ExecutorError, match=r'a Dask scheduler \(tcp://h:1\) needs the cluster extra: pip install'):
        connect('tcp://h:1')


def test_a_scheduler_that_does_not_answer_is_named_with_the_timeout() -> None:
    pytest.importorskip('distributed')
    with pytest.raises(ExecutorError, match=r'no Dask scheduler answered at tcp://127.0.0.1:9 within 0.2 s'):
        connect('tcp://127.0.0.1:9', timeout_s=0.2)


def test_the_executor_error_is_a_vtube_error_and_a_runtime_error() -> None:
    assert issubclass(ExecutorError, VtubeError) and issubclass(ExecutorError, RuntimeError)


class FakeClient:
    """A Dask client whose cluster has ``workers`` (None: none ever comes) answering ``run`` with ``answer``."""

    def __init__(self, answer: object) -> None:
        self.answer = answer

    def wait_for_workers(self, n: int, timeout: float) -> None:
        if self.answer is None:
            raise TimeoutError(f'only 0/{n} workers arrived after {timeout}')

    def run(self, fn):
        if isinstance(self.answer, BaseException):
            raise self.answer
        return self.answer


@pytest.mark.parametrize(
    ('answer', 'match'),
    [
        (None, r'the Dask scheduler at tcp://h:1 has no worker after 0.5 s; start one with `dask worker tcp://h:1`'),
        (ModuleNotFoundError("No module named 'vtube_planning'"), r'cannot run vtube \(ModuleNotFoundError: No module'),
        ({'tcp://w:2': '0.0.1'}, r'the Dask worker tcp://w:2 runs vtube 0.0.1, this process '),
    ],
)
def test_a_cluster_without_workers_or_without_this_vtube_is_refused(answer, match) -> None:
    from vtube_planning.studies.executors import ExecutorError, checked_workers

    with pytest.raises(ExecutorError, match=match):
        checked_workers(FakeClient(answer), 'tcp://h:1', 0.5)
    from vtube_planning import __version__

    checked_workers(FakeClient({'tcp://w:2': __version__}), 'tcp://h:1', 0.5)  # the same version: accepted


def test_a_cluster_that_fails_mid_way_is_named_after_the_runs_it_finished(monkeypatch) -> None:
    """The scheduler goes away at the second future (CommClosedError): the first result is yielded, then a clear
    ExecutorError; an error of ``fn`` itself still propagates as it is."""
    distributed = pytest.importorskip('distributed')
    from distributed.comm.core import CommClosedError

    from vtube_planning.studies.executors import ExecutorError, map_unordered

    class Future:
        def __init__(self, key: int, outcome: object) -> None:
            self.key, self.outcome = key, outcome

        def result(self) -> object:
            if isinstance(self.outcome, BaseException):
                raise self.outcome
            return self.outcome

    class Client:
        def __init__(self) -> None:
            self.outcomes: tuple[object, ...] = ()
            self.cancelled: list[Future] = []

        def map(self, fn, items, pure):
            return [Future(k, outcome) for k, outcome in enumerate(self.outcomes)]

        def cancel(self, futures) -> None:
            self.cancelled.extend(futures)

    monkeypatch.setattr(distributed, 'as_completed', iter)
    client = Client()
    client.outcomes = ('first', CommClosedError('in <TCP (closed)>: Stream is closed'), 'third')
    got = []
    with pytest.raises(
        ExecutorError,
        match=r'the Dask cluster failed during the runs \(CommClosedError: in <TCP .*rerun the same command',
    ):
        for i, value in map_unordered(str, ['a', 'b', 'c'], client=client):
            got.append((i, value))
    assert got == [(0, 'first')] and len(client.cancelled) == 3
    client.outcomes = (ValueError('the run itself'),)
    with pytest.raises(ValueError, match='the run itself'):
        list(map_unordered(str, ['a'], client=client))
    # issue 49: a killed scheduler is named by its address, and one that no longer takes a cancellation is let go
    from types import SimpleNamespace

    def refuse(futures) -> None:
        raise OSError('the scheduler is gone')

    client.scheduler = SimpleNamespace(address='tcp://10.0.0.7:8786')
    client.cancel = refuse
    client.outcomes = ('first', CommClosedError('in <TCP (closed)>: Stream is closed'))
    with pytest.raises(ExecutorError, match=r'^the Dask cluster of the scheduler at tcp://10\.0\.0\.7:8786 failed'):
        list(map_unordered(str, ['a', 'b'], client=client))


def test_the_client_s_own_log_of_a_lost_scheduler_is_not_printed(monkeypatch, caplog) -> None:
    """Issue 49: a scheduler killed mid-campaign printed distributed's "Failed to reconnect to scheduler ...,
    closing client" above the one error line, and its reconnection's traceback after it; the client's log is quiet
    while the runs go, and after a loss."""
    import logging

    distributed = pytest.importorskip('distributed')
    from distributed.comm.core import CommClosedError

    from vtube_planning.studies.executors import ExecutorError, map_unordered

    logger = logging.getLogger('distributed.client')
    before = logger.level

    class Lost:
        key = 0

        def result(self) -> object:
            logger.error('Failed to reconnect to scheduler after 10.00 seconds, closing client')
            raise CommClosedError('in <TCP (closed)>: Stream is closed')

    client = SimpleNamespace(map=lambda fn, items, pure: [Lost()], cancel=lambda futures: None)
    monkeypatch.setattr(distributed, 'as_completed', iter)
    with caplog.at_level(logging.DEBUG), pytest.raises(ExecutorError, match='the Dask cluster failed during the runs'):
        list(map_unordered(str, ['a'], client=client))
    assert not [r for r in caplog.records if 'Failed to reconnect' in r.getMessage()]
    assert logger.level == logging.CRITICAL  # and its tracebacks of the reconnection, later, neither
    logger.setLevel(before)
