"""Preflight of a submission file (``vtube submission check``): will the testbed accept it and run it well?

1. It compiles as Python 3.10, imports only the standard library, ``rps`` and the server's packages
   (``server_libraries.txt``, parsed from its AST) and carries vtube flight data (``DATA``, read, not run).
2. It runs, each time in a fresh process and folder, on the bundled simulator with V2's initialization for several
   seeds under each testbed model of `submission.robustness.CHECKED_MODELS` (the real robots' delay, lag and noise),
   and on the PyPI ``robotarium-python-simulator`` when it is installed: `submission.recording` records what the
   simulator held (each step's validated poses and commands, its counters); nothing the file prints or saves is read.
3. The verdict of a run: it ends normally after the end-of-script call; the simulator counted no robots too close,
   none outside the arena and no actuator-limit steps, and neither do the verifier's rules
   (`robotarium_exp.verifier.recount`) applied to its recorded poses and commands; every robot ends past the tube's
   exit (completion). The robot count to declare is the simulator's. Runs under the stress models (``fitted:2``)
   are reported with their margins (`submission.robustness`) but do not decide the verdict.
4. The duration to declare (`submission.declaration`): V2's initializer alone for the file's initial conditions
   over many seeds, plus the longest experiment of the verdict's runs. Every run must fit the verifier's
   ``duration_factor`` times the declaration (the header's, when it records one).
"""

from __future__ import annotations

import ast
import importlib.util
import os
import subprocess
import sys
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path
from typing import Literal

from robotarium_exp.fit import fit_of_flight
from robotarium_exp.flight_data import FlightData
from robotarium_exp.initializer import InitializerSample, initializer_durations
from robotarium_exp.spec import ROBOTARIUM
from robotarium_exp.verdict import run_failures
from robotarium_exp.verifier import VerifierCounts, closest_centres_m, recount
from submission.declaration import Declaration, declare
from submission.delay_margin import MIN_SEEDS, DelayMargin, search
from submission.errors import CheckError
from submission.recording import SimulatorRecord, read_record
from submission.reuse import cached_initializer_durations, simulator_salt
from submission.robustness import CHECKED_MODELS, VERDICT_MODELS, Margins, margins, record_passage
from submission.schedule import Job, batch, flights
from vtube_planning.onboard import SampledTube
from vtube_planning.swarm.metrics import PassageMetrics

Backend = Literal['bundled', 'pypi']
RUN_TIMEOUT_S = 900.0
"""How long one run of the file may take before the check stops it (the testbed's own limit is the declaration)."""
RECORD_FILE = 'preflight_record.npz'


@dataclass(frozen=True, eq=False)
class RunReport:
    """One run of the file: which simulator and seed, how the process ended, and what the simulator recorded.

    ``record`` is None when the run left none (stopped after ``timed_out_s``, or the runner itself failed);
    ``completed``: every robot's last recorded pose lies past the tube's exit; ``metrics``: the passage measured on
    the robots' bodies from the record (`submission.robustness.record_passage`; None: not measured).
    """

    backend: Backend
    seed: int | None
    returncode: int
    stderr_tail: str = ''
    timed_out_s: float | None = None
    record: SimulatorRecord | None = None
    completed: bool = False
    model: str = 'ideal'
    metrics: PassageMetrics | None = None

    @property
    def label(self) -> str:
        """The run's name in reports: the simulator, the seed, the testbed model unless ideal."""
        seed = f' seed {self.seed}' if self.seed is not None else ''
        return self.backend + seed + (f' {self.model}' if self.model != 'ideal' else '')

    @property
    def counted(self) -> VerifierCounts | None:
        """The simulator's own counters."""
        return None if self.record is None else VerifierCounts.from_simulator(self.record.errors)

    @property
    def recounted(self) -> VerifierCounts | None:
        """The verifier's rules applied to the poses and commands the simulator validated."""
        return None if self.record is None else recount(self.record.poses, self.record.commands)

    @property
    def min_center_distance_m(self) -> float | None:
        """The closest two robots' centres came after the initialization."""
        return None if self.record is None else closest_centres_m(self.record.poses)

    @property
    def experiment_s(self) -> float | None:
        """The experiment's duration by the simulator's step count (initialization excluded)."""
        return None if self.record is None else self.record.experiment_steps * self.record.dt_s

    @property
    def duration_s(self) -> float | None:
        """The whole run by the simulator's step count: what the testbed's clock sees."""
        return None if self.record is None else self.record.iterations * self.record.dt_s

    @property
    def problems(self) -> list[str]:
        """Why the testbed would refuse the run or the run failed (empty when it is fine)."""
        tail = self.stderr_tail.strip().splitlines()[-1:]
        if self.timed_out_s is not None:
            return [f'did not finish in {self.timed_out_s:g} s (raise --run-timeout if it should)']
        record, counted, recounted = self.record, self.counted, self.recounted
        if record is None or counted is None or recounted is None:
            return [f'left no record of the simulator (exit {self.returncode}): {tail}']
        found = []
        if record.robotariums != 1:
            found.append(f'made {record.robotariums} Robotarium objects; the testbed runs scripts that make one')
        if self.returncode != 0:
            found.append(f'crashed (exit {self.returncode}): {tail}')
        elif not record.end_of_script:
            found.append('never called debug() / call_at_scripts_end(), which the testbed needs at the end')
        found += run_failures(counted, self.metrics, parked=self.completed) if record.robotariums else []
        if not recounted.clean:
            found.append(
                f"the verifier's rules on the simulator's recorded poses and commands count {recounted.describe()}"
            )
        return found

    @property
    def ok(self) -> bool:
        return not self.problems


@dataclass(frozen=True)
class CheckReport:
    """Everything the preflight found."""

    path: str
    disallowed_imports: tuple[str, ...] = ()
    misfits: tuple[str, ...] = ()
    runs: tuple[RunReport, ...] = ()
    robots: int | None = None
    initializer: InitializerSample | None = None
    declaration: Declaration | None = None
    declaration_problem: str = ''
    header_declaration: Declaration | None = None
    stress_runs: tuple[RunReport, ...] = ()
    margins: tuple[Margins, ...] = ()
    delay_margin: DelayMargin | None = None
    margin_runs: tuple[RunReport, ...] = ()

    @property
    def passed(self) -> bool:
        runs_ok = bool(self.runs) and all(run.ok for run in self.runs)
        return not self.disallowed_imports and not self.misfits and runs_ok and not self.declaration_problem

    @property
    def experiment_s(self) -> float | None:
        """The longest experiment of the runs, initialization excluded."""
        steps = [run.experiment_s for run in self.runs if run.experiment_s is not None]
        return max(steps) if steps else None

    @property
    def declare_duration_s(self) -> int | None:
        return None if self.declaration is None else self.declaration.duration_s

    @property
    def problems(self) -> list[str]:
        """Every reason the check fails, one line each (the runs' prefixed with the run's name)."""
        missing = ', '.join(self.disallowed_imports)
        found = [f'imports missing on the Robotarium server: {missing}'] * bool(missing)
        found += [f'does not fit the Robotarium: {misfit}' for misfit in self.misfits]
        found += [f'{run.label}: {problem}' for run in self.runs for problem in run.problems]
        return found + [self.declaration_problem] * bool(self.declaration_problem)


def server_libraries() -> set[str]:
    """Import names of the server's packages (distribution names normalised), plus rps."""
    text = resources.files('submission').joinpath('server_libraries.txt').read_text(encoding='utf-8')
    names = {
        line.split('==')[0].strip().lower().replace('-', '_')
        for line in text.splitlines()
        if line.strip() and not line.startswith('#')
    }
    aliases = {'opencv_python': 'cv2', 'pyyaml': 'yaml', 'scikit_learn': 'sklearn', 'gtsam_develop': 'gtsam'}
    return {aliases.get(n, n) for n in names} | {'rps'}


def imported_modules(source: str) -> set[str]:
    """Top-level names of every module the source imports (anywhere in it)."""
    found: set[str] = set()
    for node in ast.walk(ast.parse(source, feature_version=(3, 10))):
        if isinstance(node, ast.Import):
            found.update(alias.name.split('.')[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.add(node.module.split('.')[0])
    return found


def static_check(source: str) -> list[str]:
    """Modules the file imports that the server does not have (empty when all is well)."""
    allowed = server_libraries() | set(sys.stdlib_module_names) | {'__future__'}
    return sorted(m for m in imported_modules(source) if m not in allowed)


def file_flight_data(source: str) -> FlightData:
    """The flight data a built file carries (its ``DATA``), read without running the file."""
    for node in ast.parse(source, feature_version=(3, 10)).body:
        if isinstance(node, ast.Assign) and any(getattr(t, 'id', None) == 'DATA' for t in node.targets):
            try:
                return FlightData.from_plain(ast.literal_eval(node.value))
            except (ValueError, TypeError, KeyError, AttributeError) as err:
                msg = f"the file's DATA is not vtube flight data ({err}); build it with `vtube submission build`."
                raise CheckError(msg) from err
    raise CheckError('the file has no DATA with flight data; build it with `vtube submission build`.')


def run_file(
    path: Path,
    backend: Backend,
    seed: int | None,
    data: FlightData,
    timeout_s: float = RUN_TIMEOUT_S,
    testbed_model: str = 'ideal',
    *,
    reuse: bool = True,
    salt: bytes | None = None,
) -> RunReport:
    """Run the submission in a fresh process and folder on 'bundled' (V2 initialization, recalled with ``reuse``:
    `submission.reuse`, under ``salt`` when given; under ``testbed_model``) or 'pypi', recording the simulator
    (`submission.recording`); a run that does not finish within ``timeout_s`` is stopped."""
    with tempfile.TemporaryDirectory() as folder:
        env = dict(os.environ, VTUBE_HEADLESS='1', MPLBACKEND='Agg')
        record_path = Path(folder) / RECORD_FILE
        command = [sys.executable, '-m', 'submission.recording', '--simulator', backend, '--record', str(record_path)]
        if reuse and backend == 'bundled':
            command += ['--reuse-initialization', *(['--salt', salt.hex()] if salt else [])]
        command += ['--seed', str(seed)] if seed is not None else []
        command += ['--testbed-model', testbed_model] if testbed_model != 'ideal' else []
        try:
            result = subprocess.run(
                [*command, str(Path(path).resolve())],  # the run's folder is not ours: a relative path is lost
                cwd=folder,
                env=env,
                capture_output=True,
                text=True,
                timeout=timeout_s,
                check=False,
            )
        except subprocess.TimeoutExpired:
            return RunReport(backend, seed, -1, timed_out_s=timeout_s, model=testbed_model)
        record = read_record(record_path) if record_path.is_file() else None
    tail, completed = result.stderr[-400:], _completed(record, data)
    metrics = _passage(record, data)
    return RunReport(backend, seed, result.returncode, tail, None, record, completed, testbed_model, metrics)


def _passage(record: SimulatorRecord | None, data: FlightData) -> PassageMetrics | None:
    """The recorded run's passage through the file's tube, on the robots' bodies (None: nothing to measure)."""
    if record is None or record.poses.shape[0] == 0 or record.poses.shape[2] != data.n_robots:
        return None
    tube = SampledTube(data.tube.l_m, data.tube.xy_m, data.tube.half_width_m, data.tube.area_m2)
    return record_passage(record, tube, ROBOTARIUM.collision_diameter_m)[0]


def _completed(record: SimulatorRecord | None, data: FlightData) -> bool:
    """Whether every robot's last recorded pose lies past the exit of the file's tube."""
    if record is None or record.poses.shape[0] == 0 or record.poses.shape[2] != data.n_robots:
        return False
    tube = SampledTube(data.tube.l_m, data.tube.xy_m, data.tube.half_width_m, data.tube.area_m2)
    return bool((tube.project(record.poses[-1, :2]).l_m > tube.length_m).all())


def check(
    path: str | Path,
    *,
    seeds: int | Sequence[int] = 3,
    initializer_seeds: int = 200,
    run_timeout_s: float = RUN_TIMEOUT_S,
    progress: Callable[[str], None] | None = None,
    seed_done: Callable[[], None] | None = None,
    testbed_models: tuple[str, ...] = CHECKED_MODELS,
    workers: int | None = None,
    margin_seeds: Sequence[int] = (),
    reuse: bool = True,
) -> CheckReport:
    """Run the whole preflight on a file: a run per seed of ``seeds`` (n: 0..n-1) under each of ``testbed_models``,
    each stopped after ``run_timeout_s``, on ``workers`` processes (`submission.schedule`); V2's initializer over
    ``initializer_seeds`` seeds (``progress``: what starts, ``seed_done``: each seed done); `submission.reuse` with
    ``reuse``; with ``margin_seeds`` (10 or more), the delay margin (`submission.delay_margin`)."""
    path = Path(path).resolve()
    run_seeds = tuple(range(seeds)) if isinstance(seeds, int) else tuple(seeds)
    source = _read_source(path, len(run_seeds), len(margin_seeds))
    try:
        compile(source, str(path), 'exec')
        disallowed = tuple(static_check(source))
    except (SyntaxError, ValueError) as err:  # ValueError: NUL bytes in the source
        msg = f'{path} is not valid Python 3.10: {err}.'
        raise CheckError(msg) from err
    if disallowed:
        return CheckReport(str(path), disallowed)
    data = file_flight_data(source)  # before any run: a file without flight data is refused
    fit = fit_of_flight(data)  # the scene's commands judged the same data: a misfit is a fail before any run
    if not fit.fits:
        return CheckReport(str(path), misfits=tuple(map(str, fit.misfits)))
    starts = _teller(tell := progress or (lambda text: None), run_timeout_s)

    salt = simulator_salt() if reuse else None  # once, for every run

    def run(job: Job) -> RunReport:
        return run_file(path, job[0], job[1], data, run_timeout_s, job[2], reuse=reuse, salt=salt)

    pypi = importlib.util.find_spec('rps') is not None
    by_model, pypi_runs = flights(run, run_seeds, testbed_models, pypi=pypi, starts=starts, workers=workers)
    runs = [run for model, done in by_model.items() if model in VERDICT_MODELS for run in done] + pypi_runs
    fine = bool(margin_seeds) and all(run.ok for run in runs)  # no margin for a file that fails
    found = search(lambda jobs: batch(run, jobs, starts, workers), margin_seeds, by_model) if fine else (None, [])
    tell(f"V2's initializer alone for the file's initial conditions, {initializer_seeds} seeds")
    robots = {run.record.poses.shape[2] for run in runs if run.record is not None and run.record.robotariums}
    durations = cached_initializer_durations if reuse else initializer_durations
    initializer = durations(data.initial_conditions, range(initializer_seeds), seed_done=seed_done)
    report = CheckReport(
        str(path),
        runs=tuple(runs),
        robots=robots.pop() if len(robots) == 1 else None,
        initializer=initializer,
        header_declaration=Declaration.from_header(source),
        stress_runs=tuple(run for model, done in by_model.items() if model not in VERDICT_MODELS for run in done),
        margins=tuple(margins(m, [(r.ok, r.record, r.duration_s) for r in done], data) for m, done in by_model.items()),
        delay_margin=found[0],
        margin_runs=tuple(found[1]),
    )
    return _declared(report, initializer)


def _teller(tell: Callable[[str], None], run_timeout_s: float) -> Callable[[Job], None]:
    """What ``progress`` is told as a run starts."""

    def starts(job: Job) -> None:
        backend, seed, model = job
        under = f'bundled simulator, seed {seed}' + (f', {model}' if model != 'ideal' else '')
        where = under if backend == 'bundled' else 'PyPI simulator'
        tell(f'running the file on the {where} (at most {run_timeout_s:g} s)')

    return starts


def _read_source(path: Path, seeds: int, margin_seeds: int = 0) -> str:
    """The file's text, refused with what to give instead when it is not a Python source file."""
    if path.is_dir():
        msg = f'{str(path)!r} is a folder; give the submission .py file (vtube submission build writes one).'
        raise CheckError(msg)
    if not path.is_file():
        msg = f'submission file {str(path)!r} does not exist; build one with `vtube submission build`.'
        raise CheckError(msg)
    if seeds < 1:
        msg = (
            "the duration to declare rests on runs with the testbed's initialization; check with seeds >= 1 "
            f'(got {seeds}).'
        )
        raise CheckError(msg)
    if 0 < margin_seeds < MIN_SEEDS:
        msg = (
            f'a delay margin rests on at least {MIN_SEEDS} seeds (got {margin_seeds}); give --margin-seeds {MIN_SEEDS}.'
        )
        raise CheckError(msg)
    try:
        return path.read_text(encoding='utf-8')
    except UnicodeDecodeError as err:
        msg = f'{path} is not a Python source file (not UTF-8 text); give the .py file `vtube submission build` wrote.'
        raise CheckError(msg) from err


def _declared(report: CheckReport, initializer: InitializerSample) -> CheckReport:
    """The report with the duration to declare, and what is wrong with the header's or with a run's duration."""
    if report.experiment_s is None:
        return report
    try:
        derived = replace(
            declare(initializer, report.experiment_s), margins=report.margins, delay_margin=report.delay_margin
        )
    except CheckError as err:
        return replace(report, declaration_problem=str(err))
    recorded = report.header_declaration
    problem = ''
    if recorded is not None and recorded.duration_s < derived.duration_s:
        problem = (
            f'the header records {recorded.duration_s} s, shorter than the {derived.duration_s} s derived now; '
            f'declare {derived.duration_s} s, and rebuild the file with `vtube submission build` to record it.'
        )
    declared = recorded or derived
    limit_s = ROBOTARIUM.duration_factor * declared.duration_s
    for run in report.runs:
        if not problem and run.duration_s is not None and run.duration_s > limit_s:
            problem = (
                f"{run.label} took {run.duration_s:.1f} s by the simulator's count, beyond the {limit_s:.0f} s the "
                f'verifier allows for a declaration of {declared.duration_s} s; declare more.'
            )
    return replace(report, declaration=derived, declaration_problem=problem)
