"""Preflight of a submission file (``vtube submission check``): will the testbed accept it and run it well?

1. It compiles as Python 3.10 and imports only the standard library, ``rps`` and the server's packages
   (``server_libraries.txt``, parsed from its AST).
2. It runs on the bundled simulator with V2's initialization phase for several seeds, and on the PyPI
   ``robotarium-python-simulator`` when that is installed, each in a fresh process and folder; the file's JSON
   summary line and the simulator's counts are collected.
3. The verdict: every run completes with zero robots too close, zero outside the boundaries and zero
   actuator-limit steps. The robot count to declare is the file's.
4. The duration to declare: the testbed's initializer runs first and counts, and it varies a lot from run to run,
   so V2's initializer is run alone for the file's initial conditions over many seeds
   (:mod:`robotarium_exp.initializer`). The declaration is its ``DECLARE_QUANTILE`` quantile plus the longest
   experiment (the file's own steps), rounded up to 10 s; the verifier stops a run only beyond 1.5 times that. The
   report gives the share of sampled runs (initializer plus experiment) that would overrun, and of stuck ones.
"""

from __future__ import annotations

import ast
import importlib.util
import json
import math
import os
import re
import subprocess
import sys
import tempfile
from collections.abc import Callable
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robotarium_exp.initializer import InitializerSample, initializer_durations
from robotarium_exp.spec import ROBOTARIUM
from submission.errors import CheckError

DECLARE_QUANTILE = 0.995
RUN_TIMEOUT_S = 900.0
"""How long one run of the file may take before the check stops it (the testbed's own limit is the declaration)."""
"""Quantile of the initializer's durations that the declared duration covers without the verifier's margin (with
the default 200 seeds, the longest). The tail is heavy: on the trapezoid's initial conditions the longest of seeds
0-49 is 148 s, of seeds 0-199 319 s, so the longest of 50 seeds left a run beyond 1.5 times the declaration."""

COUNTS = {
    'too_close': ('robots_too_close', 'collision'),
    'outside': ('robots_outside_boundaries', 'boundary'),
    'actuator': ('exceeded_actuator_limits', 'actuator'),
}


@dataclass
class RunReport:
    """One run of the file: which simulator, seed, the file's summary and the simulator's counts."""

    backend: str
    seed: int | None
    summary: dict[str, Any] | None
    returncode: int
    stderr_tail: str = ''
    timed_out_s: float | None = None
    """The time limit the run did not finish within (None: it finished)."""

    def count(self, key: str) -> int:
        errors = (self.summary or {}).get('errors', {})
        return int(sum(errors.get(name, 0) for name in COUNTS[key]))

    @property
    def ok(self) -> bool:
        return (
            self.returncode == 0
            and self.summary is not None
            and bool(self.summary.get('completed'))
            and all(self.count(k) == 0 for k in COUNTS)
        )


@dataclass
class CheckReport:
    """Everything the preflight found."""

    path: str
    disallowed_imports: list[str] = field(default_factory=list)
    runs: list[RunReport] = field(default_factory=list)
    robots: int | None = None
    initializer: InitializerSample | None = None
    declaration: Declaration | None = None
    declaration_problem: str = ''
    header_declaration: Declaration | None = None

    @property
    def passed(self) -> bool:
        runs_ok = bool(self.runs) and all(run.ok for run in self.runs)
        return not self.disallowed_imports and runs_ok and not self.declaration_problem

    @property
    def experiment_s(self) -> float | None:
        """The longest experiment of the runs, initialization excluded."""
        steps = [run.summary['steps'] * run.summary['dt_s'] for run in self.runs if run.summary]
        return max(steps) if steps else None

    @property
    def declare_duration_s(self) -> int | None:
        return None if self.declaration is None else self.declaration.duration_s


@dataclass(frozen=True)
class Declaration:
    """The duration to declare and what it rests on: the initializer's quantile, the experiment, the risks."""

    duration_s: int
    quantile_s: float
    experiment_s: float
    runs: int
    overrun_share: float
    stuck_share: float

    def basis(self) -> str:
        """What the duration rests on, in one line."""
        return (
            f'initializer {DECLARE_QUANTILE:.1%} over {self.runs} seeds {self.quantile_s:.1f} s + experiment '
            f'{self.experiment_s:.1f} s; overruns {self.overrun_share:.1%}, stuck {self.stuck_share:.1%}'
        )

    def header_lines(self, robots: int) -> list[str]:
        """The declaration as the submission's header records it (:meth:`from_header` reads it back)."""
        return [
            f'Declare on the web form: {robots} robots and {self.duration_s} s, derived by `vtube submission check`',
            f'from {self.basis()}.',
        ]

    @classmethod
    def from_header(cls, source: str) -> Declaration | None:
        """The declaration a submission's header records, or None when it records none."""
        found = HEADER_DECLARATION.search(source)
        if found is None:
            return None
        duration, runs, quantile, experiment, overruns, stuck = found.groups()
        return cls(
            int(duration), float(quantile), float(experiment), int(runs), float(overruns) / 100, float(stuck) / 100
        )


HEADER_DECLARATION = re.compile(
    r'Declare on the web form: \d+ robots and (\d+) s, derived by `vtube submission check`\s+from initializer '
    r'[\d.]+% over (\d+) seeds ([\d.]+) s \+ experiment ([\d.]+) s; overruns ([\d.]+)%, stuck ([\d.]+)%'
)


def declare(initializer: InitializerSample, experiment_s: float) -> Declaration:
    """The duration to declare for an initializer sample and an experiment's duration, and the measured risks.

    Stuck runs count as infinitely long: they raise the quantile when they are more than 1 - DECLARE_QUANTILE of
    the sample, and they always count as overruns.
    """
    if initializer.runs == 0:
        raise CheckError('the initializer sample is empty; run it for at least one seed.')
    durations = np.array(initializer.durations_s + (np.inf,) * len(initializer.stuck_seeds))
    quantile = float(np.quantile(durations, DECLARE_QUANTILE, method='higher'))
    if not math.isfinite(quantile):
        msg = (
            f'{len(initializer.stuck_seeds)} of {initializer.runs} initializations did not finish (seeds '
            f'{list(initializer.stuck_seeds)}): no duration covers them; change the initial conditions.'
        )
        raise CheckError(msg)
    duration = int(math.ceil((quantile + experiment_s) / 10.0) * 10)
    overruns = float(np.mean(durations + experiment_s > ROBOTARIUM.duration_factor * duration))
    return Declaration(
        duration, quantile, experiment_s, initializer.runs, overruns, len(initializer.stuck_seeds) / initializer.runs
    )


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


def run_file(path: Path, backend: str, seed: int | None, timeout_s: float = RUN_TIMEOUT_S) -> RunReport:
    """Run the submission in a fresh process and folder on 'bundled' (V2 initialization) or 'pypi'; a run that
    does not finish within ``timeout_s`` is stopped and reported so."""
    with tempfile.TemporaryDirectory() as folder:
        env = dict(os.environ, VTUBE_HEADLESS='1', MPLBACKEND='Agg')
        if backend == 'bundled':
            command = [sys.executable, '-m', 'robotarium_exp.rps_alias', '--seed', str(seed), str(path)]
        else:
            command = [sys.executable, str(path)]
        try:
            result = subprocess.run(
                command, cwd=folder, env=env, capture_output=True, text=True, timeout=timeout_s, check=False
            )
        except subprocess.TimeoutExpired:
            return RunReport(backend, seed, None, -1, timed_out_s=timeout_s)
    summary = None
    for line in result.stdout.splitlines():
        if line.startswith('{') and '"vtube_summary"' in line:
            summary = json.loads(line)
    return RunReport(backend, seed, summary, result.returncode, result.stderr[-400:])


def file_initial_conditions(source: str) -> NDArray[np.float64]:
    """The initial conditions a built file carries (its ``DATA['initial_conditions']``)."""
    for node in ast.parse(source, feature_version=(3, 10)).body:
        if isinstance(node, ast.Assign) and any(getattr(t, 'id', None) == 'DATA' for t in node.targets):
            data = ast.literal_eval(node.value)
            return np.array(data['initial_conditions'], dtype=float)
    raise CheckError('the file has no DATA with initial_conditions; build it with `vtube submission build`.')


def check(
    path: str | Path,
    *,
    seeds: int = 3,
    initializer_seeds: int = 200,
    run_timeout_s: float = RUN_TIMEOUT_S,
    progress: Callable[[str], None] | None = None,
    seed_done: Callable[[], None] | None = None,
) -> CheckReport:
    """Run the whole preflight on a submission file; the initializer alone over ``initializer_seeds`` seeds; each
    run of the file stopped after ``run_timeout_s``; ``progress`` is told what starts, ``seed_done`` each
    initializer seed that ends."""
    path = Path(path).resolve()
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
    try:
        source = path.read_text(encoding='utf-8')
    except UnicodeDecodeError as err:
        msg = f'{path} is not a Python source file (not UTF-8 text); give the .py file `vtube submission build` wrote.'
        raise CheckError(msg) from err
    try:
        compile(source, str(path), 'exec')
        disallowed = static_check(source)
    except (SyntaxError, ValueError) as err:  # ValueError: NUL bytes in the source
        msg = f'{path} is not valid Python 3.10: {err}.'
        raise CheckError(msg) from err
    report = CheckReport(str(path), disallowed)
    if disallowed:
        return report
    initial_conditions = file_initial_conditions(source)  # before any run: a file without them is refused
    tell = progress or (lambda text: None)
    for seed in range(seeds):
        tell(f'running the file on the bundled simulator, seed {seed} (at most {run_timeout_s:g} s)')
        report.runs.append(run_file(path, 'bundled', seed, run_timeout_s))
    if importlib.util.find_spec('rps') is not None:
        tell(f'running the file on the PyPI simulator (at most {run_timeout_s:g} s)')
        report.runs.append(run_file(path, 'pypi', None, run_timeout_s))
    tell(f"V2's initializer alone for the file's initial conditions, {initializer_seeds} seeds")
    robots = {run.summary['robots'] for run in report.runs if run.summary}
    report.robots = robots.pop() if len(robots) == 1 else None
    report.initializer = initializer_durations(initial_conditions, range(initializer_seeds), seed_done=seed_done)
    report.header_declaration = Declaration.from_header(source)
    if report.experiment_s is not None:
        try:
            report.declaration = declare(report.initializer, report.experiment_s)
        except CheckError as err:
            report.declaration_problem = str(err)
    recorded, derived = report.header_declaration, report.declaration
    if recorded is not None and derived is not None and recorded.duration_s < derived.duration_s:
        report.declaration_problem = (
            f'the header records {recorded.duration_s} s, shorter than the {derived.duration_s} s derived now; '
            f'declare {derived.duration_s} s, and rebuild the file with `vtube submission build` to record it.'
        )
    return report
