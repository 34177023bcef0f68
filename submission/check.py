"""Preflight of a submission file (``vtube submission check``): will the testbed accept it and run it well?

1. It compiles as Python 3.10 and imports only the standard library, ``rps`` and the server's packages
   (``server_libraries.txt``, parsed from its AST).
2. It runs on the bundled simulator with V2's initialization phase for several seeds, and on the PyPI
   ``robotarium-python-simulator`` when that is installed, each in a fresh process and folder; the file's JSON
   summary line and the simulator's counts are collected.
3. The verdict: every run completes with zero robots too close, zero outside the boundaries and zero
   actuator-limit steps. The duration to declare is the longest run (initialization included) times the
   verifier's 1.5 margin, rounded up to 10 s; the robot count to declare is the file's.
"""

from __future__ import annotations

import ast
import importlib.util
import json
import math
import os
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

from robotarium_exp.spec import ROBOTARIUM
from submission.errors import CheckError

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

    @property
    def passed(self) -> bool:
        return not self.disallowed_imports and bool(self.runs) and all(run.ok for run in self.runs)

    @property
    def declare_duration_s(self) -> int | None:
        iterations = [run.summary['iterations'] for run in self.runs if run.summary]
        if not iterations:
            return None
        return int(math.ceil(max(iterations) * ROBOTARIUM.time_step_s * ROBOTARIUM.duration_factor / 10.0) * 10)


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


def run_file(path: Path, backend: str, seed: int | None, timeout_s: float = 900.0) -> RunReport:
    """Run the submission in a fresh process and folder on 'bundled' (V2 initialization) or 'pypi'."""
    with tempfile.TemporaryDirectory() as folder:
        env = dict(os.environ, VTUBE_HEADLESS='1', MPLBACKEND='Agg')
        if backend == 'bundled':
            command = [sys.executable, '-m', 'robotarium_exp.rps_alias', '--seed', str(seed), str(path)]
        else:
            command = [sys.executable, str(path)]
        result = subprocess.run(
            command, cwd=folder, env=env, capture_output=True, text=True, timeout=timeout_s, check=False
        )
    summary = None
    for line in result.stdout.splitlines():
        if line.startswith('{') and '"vtube_summary"' in line:
            summary = json.loads(line)
    return RunReport(backend, seed, summary, result.returncode, result.stderr[-400:])


def check(path: str | Path, *, seeds: int = 3) -> CheckReport:
    """Run the whole preflight on a submission file."""
    path = Path(path).resolve()
    if not path.is_file():
        msg = f'submission file {str(path)!r} does not exist; build one with `vtube submission build`.'
        raise CheckError(msg)
    source = path.read_text(encoding='utf-8')
    try:
        compile(source, str(path), 'exec')
        disallowed = static_check(source)
    except SyntaxError as err:
        msg = f'{path} is not valid Python 3.10: {err}.'
        raise CheckError(msg) from err
    report = CheckReport(str(path), disallowed)
    if disallowed:
        return report
    for seed in range(seeds):
        report.runs.append(run_file(path, 'bundled', seed))
    if importlib.util.find_spec('rps') is not None:
        report.runs.append(run_file(path, 'pypi', None))
    robots = {run.summary['robots'] for run in report.runs if run.summary}
    report.robots = robots.pop() if len(robots) == 1 else None
    return report
