"""Build the single file submitted to the remote Robotarium from a scene and a plan (``vtube submission build``).

The testbed runs one uploaded file with numpy, scipy, matplotlib, cvxopt and its own ``rps`` (no cvxpy, no package
of ours), so the file carries everything: the flight data (the caller's plan as arrays, or none; the tube as
samples, the initial conditions and parking slots), the sources of the package code the flight runs, and the
runtime itself (`submission.runtime`). The builder never plans. Apart from its build stamp line the output is
deterministic (no paths, numbers rounded to six significant digits), so a committed submission can be checked
against a fresh build.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import math
import pprint
import shlex
import sys
import tempfile
import textwrap
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from types import FunctionType, ModuleType

from robotarium_exp.experiment import ExperimentConfig, flight_data
from robotarium_exp.fit import robotarium_fit
from robotarium_exp.flight_data import FlightData
from robotarium_exp.scene import load_scene
from submission import runtime
from submission.check import RUN_TIMEOUT_S, CheckReport, check, imported_modules
from submission.declaration import FULL_BUILD_INITIALIZER_SEEDS, Declaration
from submission.errors import SubmissionError
from submission.robustness import CHECKED_MODELS
from vtube_planning import __version__
from vtube_planning.files import write_atomically
from vtube_planning.geometry.scene import Scene
from vtube_planning.planning.plan import Plan
from vtube_planning.provenance import provenance, sha256_of

RUNTIME_MARKER = '# ---- runtime ----'
OUR_PACKAGES = ('vtube_planning', 'unicycle_mapping', 'robotarium_exp', 'submission')
UNDECLARED = 'Declare on the web form: the robot count above, and the duration `vtube submission check` derives.'
"""The header's declaration line until [`Submission.declared`][submission.builder.Submission.declared] stamps the
derived one in its place."""
PLAN_METHODS = {'convex': 'convex slowness method', 'polynomial': "the paper's segmented cubics"}


@dataclass(frozen=True)
class Submission:
    """The generated source and what it was built from."""

    source: str
    scene: str
    planned: bool
    n_robots: int

    def declared(self, declaration: Declaration) -> Submission:
        """The same file with ``declaration`` in its header, in place of the line that asks for one."""
        if UNDECLARED not in self.source:
            msg = 'this submission already records a declaration; build it again to declare another duration.'
            raise SubmissionError(msg)
        lines = '\n'.join(declaration.header_lines(self.n_robots))
        return replace(self, source=self.source.replace(UNDECLARED, lines, 1))


def build(
    name_or_path: str | Path | Scene,
    plan: Plan | None,
    *,
    declaration: Declaration | None = None,
    plan_file: Path | None = None,
) -> Submission:
    """The submission's source for a Robotarium scene (shipped name, .toml file or Scene) flying ``plan``, or
    unplanned (constant speed, constant r_a) when ``plan`` is None; ``declaration``: the duration to declare, as
    [`submission.check.check`][submission.check.check] derived it for this file, recorded in the header;
    ``plan_file``: the file ``plan`` was read from, which the header's command to rebuild names."""
    scene = name_or_path if isinstance(name_or_path, Scene) else load_scene(name_or_path)
    fit = robotarium_fit(scene)
    if not fit.fits:
        raise SubmissionError(f'scene {scene.name!r} {fit.reason}')
    data = flight_data(scene, plan, ExperimentConfig(planning=plan is not None))
    body = '\n'.join(
        [
            '',
            'from __future__ import annotations',
            '',
            f'DATA = {pprint.pformat(data.to_plain(), width=118, compact=True, sort_dicts=False)}',
            '',
            '# ---- from the vtube package (inlined so that the testbed needs nothing of ours) ----',
            _inlined_sources(),
            _runtime_body(),
            '',
            "if __name__ == '__main__':",
            '    import rps.robotarium as robotarium',
            '',
            '    run(FlightData.from_plain(DATA), robotarium)',
            '',
        ]
    )
    plain = data.to_plain()
    _check_finite(plain)
    header = _header(scene, plan, data, body, plan_file)
    submission = Submission(header + body, scene.name, data.planned, data.n_robots)
    submission = submission if declaration is None else submission.declared(declaration)
    _check_source(submission.source, plain)
    return submission


def _check_finite(value: object, where: str = 'DATA') -> None:
    """Refuse flight data holding a NaN or an infinity: Python has no literal for them (the file would stop with
    a NameError on the testbed)."""
    if isinstance(value, dict):
        for key, item in value.items():
            _check_finite(item, f'{where}[{key!r}]')
    elif isinstance(value, list):
        for k, item in enumerate(value):
            _check_finite(item, f'{where}[{k}]')
    elif isinstance(value, float) and not math.isfinite(value):
        msg = f'the flight data holds {value} at {where}; plan again (vtube plan) or check the scene.'
        raise SubmissionError(msg)


def _check_source(source: str, plain: object) -> None:
    """The file as the testbed will read it: it compiles, its docstring is the only statement before its
    ``__future__`` import, and its DATA reads back as the data embedded (text from a scene file or a command line
    stays text)."""
    try:
        tree = ast.parse(source)
        compile(tree, 'submission', 'exec')
    except (SyntaxError, ValueError) as err:
        msg = f'the generated file does not compile ({err}); report this with the scene file.'
        raise SubmissionError(msg) from err
    first = tree.body[:3]
    docstring = isinstance(first[0], ast.Expr) and isinstance(first[0].value, ast.Constant)
    future = isinstance(first[1], ast.ImportFrom) and first[1].module == '__future__'
    data = isinstance(first[2], ast.Assign) and ast.literal_eval(first[2].value) == plain
    if not (docstring and future and data):
        msg = 'the generated file does not start with its docstring and DATA; report this with the scene file.'
        raise SubmissionError(msg)


def _text(value: object) -> str:
    """Text from outside (a title, a path, a command line) as it may stand in the file's docstring: one line,
    ASCII, backslashes and quotes escaped, so that it reads back as itself and can never end the docstring."""
    return str(value).encode('unicode_escape').decode('ascii').replace('"', '\\"')


def build_declared(
    scene: Scene,
    plan: Plan | None,
    path: str | Path,
    *,
    seeds: int | Sequence[int] = 3,
    initializer_seeds: int = FULL_BUILD_INITIALIZER_SEEDS,
    run_timeout_s: float = RUN_TIMEOUT_S,
    progress: Callable[[str], None] | None = None,
    seed_done: Callable[[], None] | None = None,
    testbed_models: tuple[str, ...] = CHECKED_MODELS,
    plan_file: Path | None = None,
    workers: int | None = None,
    margin_seeds: Sequence[int] = (),
    reuse: bool = True,
) -> tuple[Submission, CheckReport, Path]:
    """Build the submission and check it ([`submission.check.check`][submission.check.check], options as there) in a
    private folder; when it passes, stamp the declaration the check derived into the header of the file checked and
    write that to ``path``. A file that fails keeps no declaration and is written beside, as ``NAME.failed.py``:
    whatever was at ``path`` (an earlier declared build) stays until a build passes. Returns the submission, the report
    (naming the file written) and the file written."""
    path = Path(path)
    submission = build(scene, plan, plan_file=plan_file)
    with tempfile.TemporaryDirectory(prefix='vtube-build-') as folder:
        report = check(
            write(submission, Path(folder) / path.name),
            seeds=seeds,
            initializer_seeds=initializer_seeds,
            run_timeout_s=run_timeout_s,
            progress=progress,
            seed_done=seed_done,
            testbed_models=testbed_models,
            workers=workers,
            margin_seeds=margin_seeds,
            reuse=reuse,
        )
    if report.passed and report.declaration is not None:
        submission = submission.declared(report.declaration)
        written = write(submission, path)
    else:
        written = write(submission, path.with_name(f'{path.stem}.failed{path.suffix}'))
    return submission, replace(report, path=str(written)), written


def write(submission: Submission, path: str | Path) -> Path:
    """Write the submission's source; creates the folder."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    write_atomically(path, submission.source)
    return path


BUILD_STAMP = 'built on'
"""Starts the header line that records when and by which command the file was built (the only line of a build that
changes from one build to the next)."""


def rebuild_command(scene: Scene, planned: bool, plan_file: Path | None) -> str:
    """The command that builds the file again, as printed in its header: a shipped scene by name, a scene file by
    its absolute path, the plan file when one was given (else the build plans the scene again)."""
    shipped = scene.source.startswith('<shipped>/')
    words = ['vtube', 'submission', 'build', scene.name if shipped else str(Path(scene.source).resolve())]
    words += ['--out', 'FILE']
    words += ['--plan', str(Path(plan_file).resolve())] if planned and plan_file is not None else []
    words += [] if planned else ['--no-planning']
    return shlex.join(words)


def _header(scene: Scene, plan: Plan | None, data: FlightData, body: str, plan_file: Path | None = None) -> str:
    """The file's docstring: what it flies, the declaration (or the line asking for it), provenance, imports."""
    made = provenance(scene=scene)
    if plan is not None:
        certified = (
            'every constraint holds within 1e-6 (relative)'
            if plan.is_certified()
            else f'NOT certified, largest relative violation {max(plan.certificate.values()):.1e}'
        )
        flies = [
            (
                f'Plan: {PLAN_METHODS.get(plan.solved.method, plan.solved.method)}, {plan.l_m.size} grid points, traversal time '
                f'{plan.time_s:.2f} s;'
            ),
            f'certificate: {certified}.',
        ]
    else:
        flies = [
            (
                f'No plan: constant forward speed {data.constant_speed_mps:g} m/s and constant avoidance radius '
                f'{data.step.r_a_m:g} m.'
            )
        ]
    return '\n'.join(
        [
            '"""vtube: a speed- and density-planned robot swarm through a virtual tube, for the Robotarium.',
            '',
            (
                f"Scene '{_text(scene.name)}': {_text(scene.title)}. {data.n_robots} robots, "
                f'{"with" if data.planned else "without"} speed and density planning.'
            ),
            '',
            UNDECLARED,
            *flies,
            'Arrays rounded to six significant digits.',
            'Method: Song, Gao, Quan, "Speed and Density Planning for a Speed-Constrained Robot Swarm Through a Virtual',
            'Tube" (arXiv:2310.00623), as implemented by the vtube package.',
            '',
            f'Generated by vtube {__version__} from scene file {_text(scene.source)} (sha256 {sha256_of(scene.text)[:16]});',
            f'{BUILD_STAMP} {made["utc"]} with `{_text(made["command"])}`; do not edit. Rebuild with:',
            f'    {_text(rebuild_command(scene, data.planned, plan_file))}',
            *_imports_line(body),
            'It saves its trajectory log as vtube_*.npy with vtube_meta.json every 100 steps and at the end, and',
            'prints one JSON summary line to stdout (log.txt).',
            '"""',
            '',
        ]
    )


def _imports_line(body: str) -> list[str]:
    """What the file imports, read from its source: the packages, then the standard library's modules."""
    found = imported_modules(body) - {'__future__'}
    standard = sorted(m for m in found if m in sys.stdlib_module_names)
    packages = ["the testbed's rps" if m == 'rps' else m for m in sorted(found - set(standard))]
    text = f'It imports {", ".join(packages)} and, from the standard library, {", ".join(standard)}.'
    return textwrap.wrap(text, width=116)


def _inlined_sources() -> str:
    """The constants of ``runtime.INLINED_CONSTANTS``, the modules of ``runtime.INLINED_MODULES`` whole, then the
    functions of ``runtime.INLINED_FUNCTIONS``."""
    constants = [
        f'{name} = {getattr(importlib.import_module(module_name), name)!r}'
        for module_name, names in runtime.INLINED_CONSTANTS
        for name in names
    ]
    parts = ['\n'.join(constants), *(_module_body(name) for name in runtime.INLINED_MODULES)]
    for module_name, names in runtime.INLINED_FUNCTIONS:
        module = importlib.import_module(module_name)
        for name in names:
            value = getattr(module, name)
            for helper in _private_helpers(value, module):
                parts.append(inspect.getsource(helper).rstrip())
            parts.append(inspect.getsource(value).rstrip())
    return '\n\n\n'.join(dict.fromkeys(parts)) + '\n\n'


def _module_body(module_name: str) -> str:
    """A module's source without its docstring, ``__future__`` import and imports from our packages."""
    source = inspect.getsource(importlib.import_module(module_name))
    lines = source.splitlines()
    tree = ast.parse(source)
    drop: set[int] = set()
    for k, node in enumerate(tree.body):
        docstring = k == 0 and isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant)
        ours = isinstance(node, ast.ImportFrom) and (
            node.module == '__future__' or (node.module or '').split('.')[0] in OUR_PACKAGES
        )
        if docstring or ours:
            drop.update(range(node.lineno - 1, node.end_lineno or node.lineno))
    kept = '\n'.join(line for k, line in enumerate(lines) if k not in drop).strip()
    return f'# ---- {module_name} ----\n' + kept


def _private_helpers(func: object, module: ModuleType) -> list[FunctionType]:
    """Module-private functions (``_name``) a function calls, which must travel with it."""
    code = getattr(func, '__code__', None)
    if code is None:
        return []
    return [
        getattr(module, n) for n in code.co_names if n.startswith('_') and inspect.isfunction(getattr(module, n, None))
    ]


def _runtime_body() -> str:
    text = inspect.getsource(runtime)
    return text[text.index(RUNTIME_MARKER) + len(RUNTIME_MARKER) :].strip() + '\n'
