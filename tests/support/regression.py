"""The regression harness: golden metrics, continuous fingerprints and bit-for-bit hashes of every simulated
trajectory (plans, the study scenes A-D in their modes, ablations, baselines, faults, the Robotarium runs and the
committed submissions' flights), each for a fixed scene and seed, against tests/integration/regression.json.

    PYTHONPATH=$TREE python -m tests.support.regression --compare      # OK / DIFF per case; exit 1 on any drift
    PYTHONPATH=$TREE python -m tests.support.regression --write        # regenerate the golden file, on purpose
    PYTHONPATH=$TREE python -m tests.support.regression --write-variant  # add this machine kind's records
    PYTHONPATH=$TREE python -m tests.support.regression --sensitivity  # what 1e-9 on a gain and the environment move

Three layers, compared case by case:
- ``metrics``: what a researcher reads (passing-through time, minimum inter-robot distance, tube violations, tracking
  errors, the Robotarium verifier's counts, ...): integers, flags and texts exactly, floats within ``TOLERANCE``;
- ``fingerprints``: the main trajectory at a few fixed steps (every robot's position, their mean and spread) at full
  precision, within ``TOLERANCE``. These two layers are compared in every environment;
- ``arrays``: sha256 of every array of the run, compared only in an environment the golden file holds records for
  (``environment()``: the machine kind's SIMD targets and OpenBLAS kernels among others): there any changed bit is
  drift. Besides its own environment's records the file holds ``variants``: the same code's records on other machine
  kinds (``--write-variant`` there, or emulated: ``EMULATED``). Elsewhere what differs between the known
  environments beyond TOLERANCE / ULP_MARGIN is left out, like what one ulp moves.

A float x is within tolerance of its golden value g when |x - g| <= TOLERANCE * max(1, |g|) (absolute below 1,
relative above). ``--sensitivity`` measures the margin: the deviation each ``ControlParams`` gain changed by
1e-9 * min(1, |gain|) (the smaller of 1e-9 relative and 1e-9 absolute) causes, case by case, against the deviation
that changing the environment causes (threads and kernels of OpenBLAS, numpy's SIMD dispatch, one ulp).

Options: ``--case TEXT`` runs the cases whose name contains TEXT; ``--arrays FILE.npz`` keeps (--write) or reads
(--compare) the golden arrays, to name the first differing step and the largest deviation of a changed array.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import hashlib
import importlib
import importlib.metadata
import io
import json
import math
import os
import platform
import random
import re
import runpy
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

# The library, through as few and as stable names as possible: where a module moves, fix these lines only.
from robotarium_exp.experiment import ExperimentConfig, run_experiment
from robotarium_exp.rps.robotarium import Robotarium
from robotarium_exp.rps_alias import install as install_rps
from robotarium_exp.rps_alias import seed_rps
from robotarium_exp.rps_import import kept_apart
from robotarium_exp.scene import load_scene
from vtube_planning.params import ControlParams
from vtube_planning.planning.planner import plan_convex
from vtube_planning.studies import study as run_point_module  # the module whose ``simulate`` run_point calls
from vtube_planning.studies.study import Point, ablation_setup, run_point
from vtube_planning.swarm.simulate import SimConfig, simulate

ROOT = Path(__file__).resolve().parents[2]
REFERENCE = ROOT / 'tests' / 'integration' / 'regression.json'
TOLERANCE = 3e-12
"""Largest accepted deviation of a float metric or fingerprint, relative to max(1, |golden value|); chosen between
the measured deviations (``--sensitivity``): a gain changed by 1e-9 moves the fingerprints of every case that uses it
by 9e-11 or more (k_ra_m3ps, the least), the emulated environments (OpenBLAS threads and kernels, numpy without
AVX2/FMA3, one ulp) by 7e-14 at most: 30 x and 45 x margins (``--sensitivity``, in the golden file's environment
the bits catch any change besides)."""
ULP_MARGIN = 100.0
"""In another environment than the golden file's, a metric or fingerprint is compared only when one ulp on every
gain (``--write`` measures it, case by case: the last-bit difference another libm or SIMD kernel makes) moved it by
at most TOLERANCE / ULP_MARGIN; the others (chaotic passages, late steps) are compared bit for bit, at home only."""
GAINS = ('avoidance_gain', 'keeping_gain', 'k_ra_m3ps', 'r_a_max_m')
"""The numeric gains of ``ControlParams``, changed one at a time by ``--sensitivity``."""
GAIN_CHANGE = 1e-9
"""A gain g is changed to g + GAIN_CHANGE * min(1, |g|): by the smaller of 1e-9 relative and 1e-9 absolute."""
FRACTIONS = (0.125, 0.25, 0.5, 0.75, 1.0)
"""The fixed steps of the fingerprints, as fractions of the run's length."""
ENVIRONMENTS = (
    {'OPENBLAS_NUM_THREADS': '1'},
    {'OPENBLAS_NUM_THREADS': '2'},
    {'OPENBLAS_CORETYPE': 'Haswell'},
    {'OPENBLAS_CORETYPE': 'Sandybridge'},
    {'OPENBLAS_CORETYPE': 'Prescott'},
    {'NPY_DISABLE_CPU_FEATURES': 'X86_V3'},
    {'NPY_DISABLE_CPU_FEATURES': 'X86_V3', 'OPENBLAS_CORETYPE': 'Prescott'},
)
"""The environment changes ``--sensitivity`` emulates, each in a subprocess (numpy >= 2.4 groups AVX2, FMA3, ... as
X86_V3: disabling it sends numpy's loops to SSE4.2 code). It also changes each gain by one ulp in-process: the
last-bit difference another libm or compiler would make in the control law."""
EMULATED = 'NPY_DISABLE_CPU_FEATURES="X86_V4 AVX512_ICL AVX512_SPR" OPENBLAS_CORETYPE=Haswell'
"""How an AVX-512 machine flies the golden file's environment (numpy's loops up to X86_V3, OpenBLAS's Haswell
kernels): measured bit for bit on all cases (a Sapphire Rapids machine against the Haswell-kind golden file)."""
BLOCKS = 8
"""Each array is also hashed in this many blocks of rows (steps), to say where a difference starts."""
VERSIONED = ('numpy', 'scipy', 'cvxpy', 'clarabel', 'cvxopt', 'daqp', 'casadi')
"""The packages whose versions are part of the environment the bits are defined for."""

Arrays = dict[str, np.ndarray]
Scalars = dict[str, str]


@dataclass(frozen=True)
class Case:
    """One run with a fixed scene and seed: ``run`` returns its named arrays and scalars."""

    name: str
    run: Callable[[], tuple[Arrays, Scalars]]


# ---------------------------------------------------------------------- what a run returns


def _arrays(value: Any, prefix: str = '', skip: tuple[str, ...] = ()) -> Arrays:
    """Every numpy array inside ``value`` (dataclasses and dicts, recursively), by dotted name."""
    if isinstance(value, np.ndarray):
        return {prefix: value}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        items = {f.name: getattr(value, f.name) for f in dataclasses.fields(value)}
    elif isinstance(value, dict):
        items = value
    else:
        return {}
    out: Arrays = {}
    for key, item in items.items():
        if key not in skip:
            out |= _arrays(item, f'{prefix}.{key}' if prefix else str(key))
    return out


def _scalars(value: Any, prefix: str) -> Scalars:
    """Every number, flag and string inside ``value`` (dataclasses and dicts, recursively), floats as float.hex."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, bool) or value is None or isinstance(value, (int, str)):
        return {prefix: repr(value)}
    if isinstance(value, float):
        return {prefix: value.hex()}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        value = {f.name: getattr(value, f.name) for f in dataclasses.fields(value)}
    if isinstance(value, dict):
        out: Scalars = {}
        for key, item in value.items():
            out |= _scalars(item, f'{prefix}.{key}')
        return out
    return {}


def _sim_arrays(result: Any) -> Arrays:
    """A simulation's logged arrays and the plan it flew (``SimResult``)."""
    return _arrays(result, skip=('meta', 'metrics'))


class _Recorder:
    """A subclass of a Robotarium class that keeps every pose it hands out (initialization included) and its
    instances (for the verifier's counts)."""

    def __init__(self, base: type) -> None:
        poses: list[np.ndarray] = []
        made: list[Any] = []

        class Recorded(base):  # type: ignore[misc, valid-type]
            def __init__(self, *args: Any, **kwargs: Any) -> None:
                made.append(self)
                super().__init__(*args, **kwargs)

            def get_poses(self) -> Any:
                out = super().get_poses()
                poses.append(np.array(out, dtype=np.float64, copy=True))
                return out

        Recorded.__name__ = base.__name__
        self.cls, self.poses, self.made = Recorded, poses, made

    def array(self) -> np.ndarray:
        return np.array(self.poses)

    def verdict(self) -> dict[str, Any]:
        """The simulator's error counters and iterations (its verdict on the run)."""
        (robotarium,) = self.made
        errors = getattr(robotarium, 'errors', None) or getattr(robotarium, '_errors', None) or {}
        counts = {key: value for key, value in errors.items() if isinstance(value, (int, np.integer))}
        return {'errors': counts, 'iterations': getattr(robotarium, 'iterations', None)}


# ---------------------------------------------------------------------- the cases


def _plan(scene_name: str) -> tuple[Arrays, Scalars]:
    scene = load_scene(scene_name)
    plan = plan_convex(scene.tube, scene.swarm, scene.planning, scene=scene.name)
    arrays = {name: getattr(plan, name) for name in ('l_m', 'speed_mps', 'density_per_m2')}
    arrays |= _arrays(plan.profile, 'profile')
    return arrays, _scalars({'time_s': plan.time_s, 'objective': plan.objective}, 'plan')


def _point(point: Point, seconds: float | None = None) -> tuple[Arrays, Scalars]:
    """run_point's row and the arrays of the simulation it ran (its first ``seconds`` only, when given)."""
    flown = []

    def keep(*args: Any, **kwargs: Any) -> Any:
        if seconds is not None:
            kwargs['config'] = replace(kwargs['config'], time_limit_s=seconds)
        flown.append(simulate(*args, **kwargs))
        return flown[-1]

    if getattr(run_point_module, 'simulate', None) is not simulate:
        msg = 'run_point_module must be the module whose `simulate` run_point calls; fix the import in regression.py'
        raise RuntimeError(msg)
    with _patched(run_point_module, 'simulate', keep):
        row = run_point(point)
    (result,) = flown
    return _sim_arrays(result), _scalars(row, 'row') | _scalars(result.metrics, 'metrics')


def _simulation(
    scene_name: str, mode: str, config: SimConfig, control: dict[str, Any] | None = None
) -> tuple[Arrays, Scalars]:
    """simulate on ``mode``'s setup (a study mode), with ``config`` and changed control parameters."""
    scene = load_scene(scene_name)
    setup = ablation_setup(mode, scene, scene.swarm, config.dt_s)
    result = simulate(
        scene.tube,
        scene.swarm,
        replace(setup.control, **(control or {})),
        plan=setup.plan,
        config=config,
        constant_speed_mps=setup.constant_speed_mps,
        baseline=setup.baseline,
    )
    return _sim_arrays(result), _scalars(result.metrics, 'metrics')


def _experiment(scene_name: str, planning: bool, **options: Any) -> tuple[Arrays, Scalars]:
    """The tube experiment on the bundled V2 simulator with seed 0, as ``vtube robotarium run`` flies it (options:
    ``ExperimentConfig``'s, e.g. ``max_steps`` for its first steps only, and ``skip_initialization``)."""
    scene = load_scene(scene_name)
    plan = plan_convex(scene.tube, scene.swarm, scene.planning, scene=scene.name) if planning else None
    skip = options.pop('skip_initialization', False)
    recorder = _Recorder(Robotarium)
    seed_rps(0)
    result = run_experiment(
        recorder.cls,
        scene,
        plan,
        ExperimentConfig(planning=planning, **options),
        robotarium_kwargs={'skip_initialization': skip},
    )
    arrays = _arrays(result.arrays, 'arrays') | {'get_poses': recorder.array()}
    scalars = {'duration_s': result.duration_s, 'completed': result.completed, 'simulator': recorder.verdict()}
    scalars |= {'errors': result.errors, 'barrier': result.barrier, 'metrics': result.metrics}
    return arrays, _scalars(scalars, 'result')


def _submission(filename: str) -> tuple[Arrays, Scalars]:
    """A committed submission file run as ``rps_alias --seed 0 FILE`` runs it: every pose the simulator handed out,
    and every numeric array the file saved (compared by content: names may change)."""
    with tempfile.TemporaryDirectory() as folder, _inside(Path(folder)), _headless(), kept_apart():
        install_rps(seed=0)
        module = importlib.import_module('rps.robotarium')
        recorder = _Recorder(module.Robotarium)
        module.Robotarium = recorder.cls  # type: ignore[attr-defined]
        runpy.run_path(str(ROOT / 'submissions' / filename), run_name='__main__')
        saved = _saved_arrays(Path(folder))
    arrays = {'get_poses': recorder.array()} | {f'saved.{name}': a for name, a in saved.items()}
    return arrays, _scalars(recorder.verdict(), 'simulator')


def _saved_arrays(folder: Path) -> Arrays:
    """The numeric arrays of the .npy and .npz files in ``folder``, by file (and key), wall-clock times left out."""
    out: Arrays = {}
    for path in sorted(folder.glob('*.npy')):
        out[path.stem] = np.load(path, allow_pickle=False)
    for path in sorted(folder.glob('*.npz')):
        with np.load(path, allow_pickle=False) as npz:
            out |= {f'{path.stem}.{key}': npz[key] for key in npz.files}
    return {
        name: a
        for name, a in out.items()
        if np.issubdtype(a.dtype, np.number) or a.dtype == np.bool_
        if 'wall' not in name.rsplit('.', 1)[-1]
    }


@contextlib.contextmanager
def _patched(owner: Any, name: str, value: Any) -> Iterator[None]:
    original = getattr(owner, name)
    setattr(owner, name, value)
    try:
        yield
    finally:
        setattr(owner, name, original)


@contextlib.contextmanager
def _inside(folder: Path) -> Iterator[None]:
    before = Path.cwd()
    os.chdir(folder)
    try:
        yield
    finally:
        os.chdir(before)


@contextlib.contextmanager
def _headless() -> Iterator[None]:
    before = os.environ.get('VTUBE_HEADLESS')
    os.environ['VTUBE_HEADLESS'] = '1'
    try:
        yield
    finally:
        if before is None:
            del os.environ['VTUBE_HEADLESS']
        else:
            os.environ['VTUBE_HEADLESS'] = before


def _slug(mode: str) -> str:
    return re.sub(r'[^A-Za-z0-9.]+', '_', mode).strip('_')


C = 'C'  # the rapid scene of the ablation and fault campaigns (docs/ablation, docs/faults, docs/replanning)
CUT_S = 8.0
"""Length (simulated seconds) of the fault, baseline and control-option runs on scene C: the first CUT_S s of each
(the full runs are ~18-30 s, failure 'stop' ~130 s), enough to reach the narrow part, where the options act."""
ROBOTARIUM_STEPS = 300
"""Steps (33 ms each) of the package's Robotarium runs with the safety filter: the planned ones after the
simulator's initialization (~3.5 s of CPU, the same as the submissions'), the unplanned ones without it. The full
flights are pinned by the committed submissions' (the same bits as the package's planned runs) and the run without
filter and initialization."""
CASES = (
    *(
        Case(f'plan_{s}', lambda s=s: _plan(s))
        for s in ('A', 'B', 'C', 'D', 'robotarium_trapezoid', 'robotarium_curve')
    ),
    *(
        Case(f'study_{s}_{_slug(m)}', lambda s=s, m=m: _point(Point(s, mode=m)))
        for s in ('A', 'B', 'C', 'D')
        for m in ('planning', 'no planning')
    ),
    *(
        Case(f'ablation_C_{_slug(m)}', lambda m=m: _point(Point(C, mode=m)))
        for m in (
            'planning without (p7)',
            'planned speed, (a3) off',
            'constant speed, (a3) to rho_d',
            'no planning at v_max',
            'replanning every 0.5 s',
        )
    ),
    Case('baseline_C_flocking_first_8s', lambda: _point(Point(C, mode='flocking'), CUT_S)),
    Case('baseline_C_flocking_v_min_first_8s', lambda: _point(Point(C, mode='flocking (v_min)'), CUT_S)),
    Case('baseline_C_nmpc_first_0.4s', lambda: _simulation(C, 'nmpc', SimConfig(time_limit_s=0.4))),
    Case('model_C_acceleration_limits_first_8s', lambda: _point(Point(C, model='acceleration limits'), CUT_S)),
    Case('saturation_C_forward_first_8s', lambda: _point(Point(C, saturation='forward'), CUT_S)),
    Case('fault_C_pose_noise_0.02_first_8s', lambda: _point(Point(C, pose_noise_m=0.02), CUT_S)),
    Case('fault_C_latency_2_first_8s', lambda: _point(Point(C, latency_steps=2), CUT_S)),
    Case('fault_C_dropout_0.1_first_8s', lambda: _point(Point(C, dropout=0.1), CUT_S)),
    Case('fault_C_failure_stop_first_14s', lambda: _point(Point(C, failure='stop'), 14.0)),
    Case('fault_C_failure_coast_first_14s', lambda: _point(Point(C, failure='coast'), 14.0)),
    Case(
        'fault_C_replanning_failure_coast_first_14s',
        lambda: _point(Point(C, mode='replanning every 0.5 s', failure='coast'), 14.0),
    ),
    Case('grid_C_N80_kdtree_first_8s', lambda: _point(Point(C, n_robots=80), CUT_S)),
    Case(
        'control_C_kdtree_forced_first_8s',
        lambda: _simulation(C, 'planning', SimConfig(time_limit_s=CUT_S), {'kdtree_above': 0}),
    ),
    Case(
        'control_C_practical_law_current_padding',
        lambda: _simulation(C, 'planning', SimConfig(), {'law': 'practical', 'density_padding': 'current'}),
    ),
    *(
        Case(
            f'robotarium_{s}_planned_first_{ROBOTARIUM_STEPS}',
            lambda s=s: _experiment(f'robotarium_{s}', True, max_steps=ROBOTARIUM_STEPS),
        )
        for s in ('trapezoid', 'curve')
    ),
    *(
        Case(
            f'robotarium_{s}_unplanned_no_init_first_{ROBOTARIUM_STEPS}',
            lambda s=s: _experiment(f'robotarium_{s}', False, max_steps=ROBOTARIUM_STEPS, skip_initialization=True),
        )
        for s in ('trapezoid', 'curve')
    ),
    Case(
        'robotarium_trapezoid_planned_no_barrier_no_init',
        lambda: _experiment('robotarium_trapezoid', True, barrier=False, skip_initialization=True),
    ),
    *(
        Case(f'submission_{f}', lambda f=f: _submission(f))
        for f in ('vtube_robotarium_curve.py', 'vtube_robotarium_trapezoid.py')
    ),
)


# ---------------------------------------------------------------------- fingerprints


def _sha(a: np.ndarray) -> str:
    a = np.ascontiguousarray(a, dtype=np.float64)
    return hashlib.sha256(repr(a.shape).encode() + a.tobytes()).hexdigest()


def array_record(a: np.ndarray) -> dict[str, Any]:
    """sha256 of the float64 C-contiguous bytes (with the shape), per block of rows too; a (T, 3, N) pose array
    also has the hashes of its positions [:, :2] and headings [:, 2] ("parts")."""
    record: dict[str, Any] = {'sha256': _sha(a), 'shape': list(a.shape), 'dtype': str(a.dtype)}
    if a.ndim and len(a):
        record['blocks'] = ' '.join(_sha(b)[:12] for b in np.array_split(a, min(BLOCKS, len(a))))
    if a.ndim == 3 and a.shape[1] == 3:
        record['parts'] = f'{_sha(a[:, :2])} {_sha(a[:, 2])}'
    return record


def _main_array(arrays: Arrays) -> tuple[str, np.ndarray] | None:
    """The run's main array: the robots' positions (T, 2, N) or poses (T, 3, N), or a plan's speed."""
    for name in ('positions_m', 'arrays.positions_m', 'get_poses', 'speed_mps'):
        if name in arrays:
            return name, np.asarray(arrays[name], dtype=np.float64)
    return None


def diagnostics(arrays: Arrays) -> dict[str, Any]:
    """Steps and the first robot's last pose (float.hex) of the run's main array."""
    found = _main_array(arrays)
    if found is None:
        return {}
    name, a = found
    last = a[-1, :, 0] if a.ndim == 3 else a[-1:]
    return {'array': name, 'steps': len(a), 'last_first_robot': [float(x).hex() for x in last]}


def trajectory_fingerprints(arrays: Arrays) -> dict[str, Any]:
    """The main array at the steps ``FRACTIONS`` of its length: for positions, per step the list [mean x, mean y,
    spread (Frobenius norm of the positions about their mean), x of every robot, y of every robot]; for a plan's
    speed, its values there and its norm."""
    found = _main_array(arrays)
    if found is None:
        return {}
    name, a = found
    steps = sorted({round(f * (len(a) - 1)) for f in FRACTIONS})
    out: dict[str, Any] = {'array': name, 'steps': steps}
    if a.ndim == 3:
        for k in steps:
            p = a[k, :2]
            mean = p.mean(axis=1)
            spread = np.linalg.norm(p - mean[:, None])
            out[f'step {k}'] = [float(mean[0]), float(mean[1]), float(spread), *map(float, p.ravel())]
    else:
        out['values'] = [*(float(a[k]) for k in steps), float(np.linalg.norm(a))]
    return out


def _fingerprint_entry(index: int, n_robots: int) -> str:
    """What entry ``index`` of a step's fingerprint list is."""
    if index < 3:
        return ('mean x', 'mean y', 'spread')[index]
    axis, robot = divmod(index - 3, n_robots)
    return f'robot {robot} {"xy"[axis]}'


@contextlib.contextmanager
def changed_gains(change: Callable[[str, float], float], names: tuple[str, ...] = GAINS) -> Iterator[None]:
    """Every controller built meanwhile flies its gains ``names`` changed by ``change(name, value)`` (through
    ``ControlParams.step_params``, which every run, the study's and the Robotarium's, builds its controller from)."""
    original = ControlParams.step_params

    def step_params(self: ControlParams, swarm: Any) -> Any:
        params = original(self, swarm)
        return replace(params, **{name: change(name, getattr(params, name)) for name in names})

    with _patched(ControlParams, 'step_params', step_params):
        yield


def fingerprint(case: Case) -> tuple[dict[str, Any], Arrays]:
    """The case's record (arrays' hashes, scalars, trajectory fingerprints, diagnostics, seconds) and its arrays."""
    started, cpu = time.perf_counter(), time.process_time()
    state = random.getstate(), np.random.get_state()
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            arrays, scalars = case.run()
    finally:
        random.setstate(state[0])
        np.random.set_state(state[1])
    record = {
        'arrays': {name: array_record(a) for name, a in sorted(arrays.items())},
        'scalars': dict(sorted(scalars.items())),
        'fingerprints': trajectory_fingerprints(arrays),
        'diagnostics': diagnostics(arrays),
        'seconds': round(time.perf_counter() - started, 2),
        'cpu_seconds': round(time.process_time() - cpu, 2),
    }
    return record, arrays


def environment() -> dict[str, str]:
    """What the bits depend on beyond the code: the machine, the C library, Python, the numerical packages'
    versions, the SIMD features numpy dispatches to, numpy's BLAS and the OpenBLAS kernels it runs."""
    key = {
        'machine': platform.machine(),
        'system': platform.system(),
        'libc': ' '.join(platform.libc_ver()),
        'python': '.'.join(platform.python_version_tuple()[:2]),
    }
    for name in VERSIONED:
        try:
            key[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            key[name] = 'absent'
    key['numpy_simd'] = ' '.join(_numpy_simd())
    try:
        blas = np.show_config(mode='dicts')['Build Dependencies']['blas']
        key['numpy_blas'] = f'{blas.get("name")} {blas.get("version")}'
    except (TypeError, KeyError):  # numpy < 1.26: no dicts
        key['numpy_blas'] = 'unknown'
    key['openblas_core'] = openblas_core()
    return key


def _numpy_simd() -> list[str]:
    """The SIMD targets numpy runs its loops with here: its baseline and the dispatch targets this CPU has (and
    NPY_DISABLE_CPU_FEATURES leaves on). Features numpy was not built to dispatch to (GFNI, AVX512F alone, ...)
    change no bit, so they are not part of the key."""
    try:
        from numpy._core import _multiarray_umath as umath
    except ImportError:  # numpy < 2
        from numpy.core import _multiarray_umath as umath
    targets = set(umath.__cpu_baseline__) | set(umath.__cpu_dispatch__)
    return sorted(name for name, on in umath.__cpu_features__.items() if on and name in targets)


def openblas_core() -> str:
    """The kernel set numpy's OpenBLAS picked for this CPU (or OPENBLAS_CORETYPE): it changes the last bits of the
    Robotarium runs (measured: Haswell here, Sandybridge or Prescott 7e-14 away), and CPUs of the same numpy SIMD
    features may get different ones."""
    import ctypes
    import glob

    for path in sorted(glob.glob(os.path.join(os.path.dirname(np.__file__), os.pardir, 'numpy.libs', '*openblas*'))):
        library = ctypes.CDLL(path)
        for name in ('scipy_openblas_get_corename64_', 'scipy_openblas_get_corename', 'openblas_get_corename'):
            function = getattr(library, name, None)
            if function is not None:
                function.restype = ctypes.c_char_p
                return str(function().decode())
    return 'unknown'


def environment_differences(reference: dict[str, str]) -> str:
    """How this environment differs from ``reference`` ('' when it is the same)."""
    here = environment()
    changed = []
    for key in sorted(set(here) | set(reference)):
        old, new = reference.get(key), here.get(key)
        if old == new:
            continue
        if key == 'numpy_simd' and old is not None and new is not None:
            gone, added = sorted(set(old.split()) - set(new.split())), sorted(set(new.split()) - set(old.split()))
            changed.append(f'{key}: ' + ' '.join([f'-{f}' for f in gone] + [f'+{f}' for f in added]))
        else:
            changed.append(f'{key}: {old!r} -> {new!r}')
    return '; '.join(changed)


# ---------------------------------------------------------------------- comparison


def _candidates(records: dict[str, Any]) -> dict[str, str]:
    """Content hash -> name, of every array and pose part of a run."""
    out = {}
    for name, record in records.items():
        out[record['sha256']] = name
        for index, part in enumerate(record.get('parts', '').split()):
            out.setdefault(part, f'{name}[{"positions" if index == 0 else "headings"}]')
    return out


def _where(name: str, old: dict[str, Any], new: dict[str, Any], arrays: Arrays, reference: Arrays | None) -> str:
    """Where array ``name`` first differs: the step and the largest deviation (with the reference arrays), else
    the first differing block of steps."""
    shape = '' if old['shape'] == new['shape'] else f'shape {old["shape"]} -> {new["shape"]}'
    if reference is not None and name in reference and name in arrays and old['shape'][1:] == new['shape'][1:]:
        a, b = np.asarray(reference[name], dtype=np.float64), np.asarray(arrays[name], dtype=np.float64)
        if a.ndim:
            a, b = a[: min(len(a), len(b))], b[: min(len(a), len(b))]
        differ = ~((a == b) | (np.isnan(a) & np.isnan(b)))
        rows = np.flatnonzero(differ.reshape(len(a), -1).any(axis=1)) if a.ndim else np.array([0])
        deviation = np.nanmax(np.abs(a - b)[differ]) if differ.any() else 0.0
        if not rows.size:
            return f'{name}: {shape}, the same bits over the common steps'
        where = f'first differs at step {rows[0]}, max abs deviation {deviation:.3g}'
        return f'{name}: {shape}, {where}' if shape else f'{name}: {where}'
    if shape:
        return f'{name}: {shape}'
    old_blocks, new_blocks = old.get('blocks', '').split(), new.get('blocks', '').split()
    first = next((k for k, (x, y) in enumerate(zip(old_blocks, new_blocks, strict=False)) if x != y), None)
    if first is None:
        return f'{name}: differs'
    bounds = np.array_split(np.arange(old['shape'][0]), len(old_blocks))[first]
    return f'{name}: first differs in steps {bounds[0]}..{bounds[-1]} of {old["shape"][0]}'


def _float(text: str) -> float | None:
    """The float a scalar's text holds (float.hex), None for an integer, flag or text."""
    if re.fullmatch(r'-?(0x[0-9a-f.]+p[+-]?\d+|inf|nan)', text):
        return float.fromhex(text)
    return None


def deviation(golden: float, value: float) -> float:
    """|value - golden| / max(1, |golden|); 0 for the same value (NaN for NaN included), inf for NaN against a number."""
    if golden == value or (math.isnan(golden) and math.isnan(value)):
        return 0.0
    if math.isnan(golden) or math.isnan(value) or math.isinf(golden) or math.isinf(value):
        return math.inf
    return abs(value - golden) / max(1.0, abs(golden))


def ulp_moves(old: dict[str, Any], new: dict[str, Any]) -> dict[str, float]:
    """The deviation of each metric and fingerprint of ``new`` from ``old`` that is not 0 (inf: an integer, flag,
    text, length or run length changed), by 'metric NAME' / 'fingerprint KEY'."""
    out: dict[str, float] = {}
    for name, value in old['scalars'].items():
        now = new['scalars'].get(name)
        golden, moved = _float(value), None if now is None else _float(now)
        d = (
            deviation(golden, moved)
            if golden is not None and moved is not None
            else (math.inf if now != value else 0.0)
        )
        if d:
            out[f'metric {name}'] = d
    before, after = old['fingerprints'], new['fingerprints']
    if before.get('steps') != after.get('steps'):
        out['fingerprint steps'] = math.inf
    for key, golden in before.items():
        now = after.get(key)
        if key in ('array', 'steps'):
            continue
        if now is None or len(now) != len(golden):
            out[f'fingerprint {key}'] = math.inf
        elif d := max(deviation(g, v) for g, v in zip(golden, now, strict=True)):
            out[f'fingerprint {key}'] = d
    return out


def unstable(record: dict[str, Any]) -> set[str]:
    """The metrics and fingerprints of a golden record that one ulp on every gain moved by more than
    TOLERANCE / ULP_MARGIN when it was written, or that differ so between the environments the golden file holds
    (``golden`` adds those as 'environments'): the run amplifies last-bit differences there (chaotic passages)."""
    moves = record.get('ulp', {}) | record.get('environments', {})
    return {name for name, d in moves.items() if d > TOLERANCE / ULP_MARGIN}


def golden(reference: dict[str, Any], here: dict[str, str] | None = None) -> tuple[dict[str, Any], bool]:
    """The golden records of every case for the environment ``here`` (this one by default), and whether their bits
    are compared. In the golden file's environment its records, bits compared; in the environment of one of its
    ``variants`` (another machine kind, written with --write-variant) the variant's records where they differ,
    bits compared; elsewhere the golden file's records, each knowing what moved between the environments it holds
    (``unstable``), bits not compared."""
    here = environment() if here is None else here
    cases = reference['cases']
    if here == reference['environment']:
        return cases, True
    variants = list(reference.get('variants', {}).values())
    for variant in variants:
        if here == variant['environment']:
            return cases | variant['cases'], True
    records = {}
    for name, record in cases.items():
        moves: dict[str, float] = {}
        for variant in variants:
            if name in variant['cases']:
                for key, d in ulp_moves(record, variant['cases'][name]).items():
                    moves[key] = max(d, moves.get(key, 0.0))
        records[name] = record | {'environments': moves}
    return records, False


@dataclass
class Drift:
    """How a run differs from its golden record: ``found`` (drift), ``notes``, and the largest deviation of a float
    metric and of a fingerprint (``largest``: name -> deviation)."""

    found: list[str]
    notes: list[str]
    largest: dict[str, tuple[str, float]]

    def worst(self) -> float:
        return max((d for _, d in self.largest.values()), default=0.0)


def _keep_largest(largest: dict[str, tuple[str, float]], layer: str, name: str, value: float) -> None:
    if value > largest.get(layer, ('', -1.0))[1]:
        largest[layer] = (name, value)


def _metric_drift(old: Scalars, new: Scalars, drift: Drift, tolerance: float, skip: set[str]) -> None:
    """Integers, flags and texts exactly; floats within ``tolerance``; not the metrics named in ``skip``."""
    for name, value in old.items():
        if f'metric {name}' in skip:
            continue
        if name not in new:
            drift.found.append(f'metric {name}: no longer returned')
            continue
        golden, now = _float(value), _float(new[name])
        if golden is None or now is None:
            if new[name] != value:
                drift.found.append(f'metric {name}: {value} -> {new[name]}')
            continue
        d = deviation(golden, now)
        _keep_largest(drift.largest, 'metrics', name, d)
        if d > tolerance:
            drift.found.append(f'metric {name}: {golden!r} -> {now!r} (deviation {d:.3g} > {tolerance:.3g})')
    drift.notes += [f'new metric {name}' for name in new if name not in old]


def _fingerprint_drift(
    old: dict[str, Any], new: dict[str, Any], drift: Drift, tolerance: float, skip: set[str]
) -> None:
    """The same steps, each fingerprint within ``tolerance`` (the worst entry named); not those named in ``skip``."""
    for key in ('array', 'steps'):
        if old.get(key) != new.get(key) and f'fingerprint {key}' not in skip:
            drift.found.append(f'fingerprint {key}: {old.get(key)} -> {new.get(key)}')
            return
    for key, golden in old.items():
        if key in ('array', 'steps') or f'fingerprint {key}' in skip:
            continue
        now = new.get(key)
        if now is None or len(now) != len(golden):
            drift.found.append(f'fingerprint {key}: {len(golden)} values -> {None if now is None else len(now)}')
            continue
        ds = [deviation(g, v) for g, v in zip(golden, now, strict=True)]
        i = int(np.argmax(ds))
        n_robots = (len(golden) - 3) // 2
        what = f'{key} {_fingerprint_entry(i, n_robots)}' if key.startswith('step') else f'{key}[{i}]'
        _keep_largest(drift.largest, 'fingerprints', what, ds[i])
        if ds[i] > tolerance:
            drift.found.append(
                f'fingerprint {what}: {golden[i]!r} -> {now[i]!r} (deviation {ds[i]:.3g} > {tolerance:.3g}; '
                f'{sum(d > tolerance for d in ds)} of {len(ds)} values of the step beyond)'
            )


def _array_drift(
    old: dict[str, Any], new: dict[str, Any], drift: Drift, arrays: Arrays | None, reference: Arrays | None
) -> None:
    """An array is the same when its name holds the same bits or, when no array has its name (or it is a file's,
    ``saved.``), when some array (or a pose array's positions and headings) holds them."""
    content = _candidates(new)
    for name, record in old.items():
        if name in new and new[name]['sha256'] == record['sha256']:
            continue
        if name in new and not name.startswith('saved.'):
            drift.found.append('bits ' + _where(name, record, new[name], arrays or {}, reference))
        elif record['sha256'] in content:
            drift.notes.append(f'{name} is now {content[record["sha256"]]} (same bits)')
        elif record.get('parts') and all(p in content for p in record['parts'].split()):
            drift.notes.append(f'{name} is now {" + ".join(content[p] for p in record["parts"].split())} (same bits)')
        elif name in new:
            drift.found.append('bits ' + _where(name, record, new[name], arrays or {}, reference))
        else:
            drift.found.append(f'bits {name}: no array of the run holds its bits')
    known = set(_candidates(old))
    drift.notes += [f'new array {n}' for n, r in new.items() if n not in old and r['sha256'] not in known]


def differences(
    old: dict[str, Any],
    new: dict[str, Any],
    arrays: Arrays | None = None,
    reference: Arrays | None = None,
    *,
    bits: bool = True,
    tolerance: float = TOLERANCE,
) -> Drift:
    """The drift of a run's record ``new`` from its golden record ``old``: metrics and fingerprints always (in
    another environment, ``bits`` False, only those one ulp leaves within TOLERANCE / ULP_MARGIN: ``unstable``), the
    arrays' bits when ``bits`` (the golden file's environment)."""
    drift = Drift([], [], {})
    skip = set() if bits else unstable(old)
    if skip:
        drift.notes.append(
            f'{len(skip)} metrics or fingerprints that one ulp moves are compared in the golden environment only'
        )
    _metric_drift(old['scalars'], new['scalars'], drift, tolerance, skip)
    _fingerprint_drift(old.get('fingerprints', {}), new['fingerprints'], drift, tolerance, skip)
    if bits:
        _array_drift(old['arrays'], new['arrays'], drift, arrays, reference)
    if drift.found and old.get('diagnostics') != new.get('diagnostics'):
        drift.found.append(f'diagnostics {old.get("diagnostics")} -> {new.get("diagnostics")}')
    return drift


def _json(value: Any, depth: int = 0, flat: int = 4) -> str:
    """JSON with one line per array record (depth 4: cases / case / arrays / array; 6 in a variant)."""
    if not isinstance(value, dict) or depth == flat or not value:
        return json.dumps(value)
    pad = ' ' * (depth + 1)
    items = (f'{pad}{json.dumps(k)}: {_json(v, depth + 1, 6 if k == "variants" else flat)}' for k, v in value.items())
    return '{\n' + ',\n'.join(items) + '\n' + ' ' * depth + '}'


def load_reference(path: Path = REFERENCE) -> dict[str, Any]:
    return json.loads(path.read_text(encoding='utf-8'))


def _selected(text: str | None, pattern: str | None = None) -> list[Case]:
    cases = [c for c in CASES if (text is None or text in c.name) and (pattern is None or re.search(pattern, c.name))]
    if not cases:
        raise SystemExit(f'no case name contains {text!r}; the cases: {", ".join(c.name for c in CASES)}')
    return cases


def write(cases: list[Case], arrays_path: Path | None) -> None:
    """Fingerprint ``cases`` into the golden file, in this environment (other cases' records are kept when only some
    are run); the variants of the cases written are dropped: they were made by the code before."""
    old = load_reference() if REFERENCE.exists() and len(cases) < len(CASES) else {'cases': {}}
    records, kept = dict(old['cases']), {}
    for case in cases:
        records[case.name], arrays = fingerprint(case)
        with changed_gains(_ulp):
            records[case.name]['ulp'] = dict(sorted(ulp_moves(records[case.name], fingerprint(case)[0]).items()))
        kept |= {f'{case.name}/{name}': a for name, a in arrays.items()}
        seconds = records[case.name]['seconds'], records[case.name]['cpu_seconds']
        print(f'{seconds[0]:7.2f} s ({seconds[1]:6.2f} s CPU)  {case.name}', flush=True)
    names = [c.name for c in CASES]
    written = {c.name for c in cases}
    variants = {
        label: v | {'cases': {n: r for n, r in v['cases'].items() if n not in written}}
        for label, v in old.get('variants', {}).items()
        if old.get('environment') == environment()
    }
    out = {'environment': environment(), 'cases': {n: records[n] for n in names if n in records}, 'variants': variants}
    REFERENCE.write_text(_json(out) + '\n', encoding='utf-8')
    seconds = sum(r['cpu_seconds'] for r in out['cases'].values())
    print(f'written {REFERENCE} ({seconds:.1f} s of runs, CPU)')
    print(f'add the records of the other machine kinds with --write-variant there (emulated: {EMULATED})')
    if arrays_path is not None:
        np.savez_compressed(arrays_path, **kept)
        print(f'written {arrays_path}')


def write_variant(cases: list[Case]) -> int:
    """Add this environment's records of ``cases`` to the golden file as a variant, where they differ from the
    golden file's (the same code, another machine kind); 2 in the golden file's own environment."""
    reference = load_reference()
    here = environment()
    if here == reference['environment']:
        print("error: this is the golden file's own environment; write its records with --write", file=sys.stderr)
        return 2
    label = '; '.join(f'{k}={v}' for k, v in here.items() if reference['environment'].get(k) != v)
    variants = reference.get('variants', {})
    mine = variants.pop(label, {'cases': {}})['cases']
    for case in cases:
        record, _ = fingerprint(case)
        same = differences(reference['cases'][case.name], record, bits=True, tolerance=0.0)
        mine.pop(case.name, None)
        if same.found:
            mine[case.name] = record
        print(f'{"differs" if same.found else "same   "}  {case.name}', flush=True)
    variants[label] = {'environment': here, 'cases': {c.name: mine[c.name] for c in CASES if c.name in mine}}
    REFERENCE.write_text(_json(reference | {'variants': variants}) + '\n', encoding='utf-8')
    print(f"written {REFERENCE}: {len(mine)} cases of this environment differ from the golden file's")
    return 0


def compare(cases: list[Case], arrays_path: Path | None, deviations: Path | None = None) -> int:
    """Print OK / DIFF per case against the golden file; 1 on any drift or missing case, else 0. ``deviations``:
    write each case's largest deviations there (JSON), for ``--sensitivity``."""
    reference = load_reference()
    records, bits = golden(reference)
    if not bits:
        changed = environment_differences(reference['environment'])
        print(
            f'note: the golden file was written in another environment ({changed}) and holds no variant of this '
            'one: bits are not compared'
        )
    saved = np.load(arrays_path) if arrays_path is not None else None
    failed, total, largest = 0, 0.0, {}
    for case in cases:
        old = records.get(case.name)
        new, arrays = fingerprint(case)
        total += new['cpu_seconds']
        if old is None:
            failed += 1
            print(f'DIFF  {case.name}: not in the golden file (--write it)', flush=True)
            continue
        mine = None
        if saved is not None:
            mine = {k.split('/', 1)[1]: saved[k] for k in saved.files if k.startswith(case.name + '/')}
        drift = differences(old, new, arrays, mine, bits=bits)
        largest[case.name] = {'found': len(drift.found), **{k: v for k, (_, v) in drift.largest.items()}}
        failed += bool(drift.found)
        worst = ', '.join(f'{k} {v:.2g} ({n})' for k, (n, v) in drift.largest.items())
        print(
            f'{"DIFF" if drift.found else "OK  "}  {case.name} ({new["cpu_seconds"]:.2f} s CPU; largest deviation: '
            f'{worst})',
            flush=True,
        )
        for line in drift.found:
            print(f'        {line}')
        for line in drift.notes:
            print(f'        note: {line}')
    missing = [name for name in reference['cases'] if name not in {c.name for c in CASES}]
    for name in missing:
        print(f'DIFF  {name}: in the golden file, no longer a case')
    print(f'{len(cases) - failed} of {len(cases)} cases without drift ({total:.1f} s CPU; tolerance {TOLERANCE:g})')
    if deviations is not None:
        deviations.write_text(json.dumps(largest, indent=1) + '\n', encoding='utf-8')
    return 1 if failed or missing else 0


def _gain_change(gain: str) -> Callable[[str, float], float]:
    """``gain`` + 1e-9 * min(1, |gain|); the other gains as they are."""
    return lambda name, value: value + GAIN_CHANGE * min(1.0, abs(value)) if name == gain else value


def _ulp(name: str, value: float) -> float:
    return float(np.nextafter(value, math.inf))


def sensitivity(cases: list[Case], out: Path | None) -> int:
    """Measure, per case, the largest deviation (metrics and fingerprints, as the comparison computes it) that each
    gain changed by 1e-9 causes, and the largest that any emulated environment change causes; print the table and
    the margins to ``TOLERANCE``; 1 when a gain change exceeds 10 x the tolerance in no case, or an environment
    change goes beyond it. Measured as the comparison outside the golden environment does: without the metrics and
    fingerprints that one ulp moves (``unstable``)."""
    reference = load_reference()
    table: dict[str, dict[str, float]] = {case.name: {} for case in cases}
    for label, change in [*((gain, _gain_change(gain)) for gain in GAINS), ('1 ulp (every gain)', _ulp)]:
        print(f'-- {label}', flush=True)
        for case in cases:
            with changed_gains(change):
                new, _ = fingerprint(case)
            drift = differences(reference['cases'][case.name], new, bits=False, tolerance=math.inf)
            table[case.name][label] = drift.worst()
    for env in ENVIRONMENTS:
        label = ' '.join(f'{k}={v}' for k, v in env.items())
        print(f'-- {label}', flush=True)
        with tempfile.TemporaryDirectory() as folder:
            path = Path(folder) / 'deviations.json'
            command = [sys.executable, '-m', 'tests.support.regression', '--compare', '--deviations', str(path)]
            names = '|'.join(re.escape(case.name) for case in cases)
            subprocess.run(
                [*command, '--pattern', f'^({names})$'],
                env=os.environ | env,
                cwd=ROOT,
                check=False,
                stdout=subprocess.DEVNULL,
            )
            measured = json.loads(path.read_text(encoding='utf-8'))
        for name, row in measured.items():
            table[name][label] = max((v for k, v in row.items() if k != 'found'), default=0.0)
    return _sensitivity_report(table, out)


def _sensitivity_report(table: dict[str, dict[str, float]], out: Path | None) -> int:
    """Print the table and the margins: per gain, the cases it moves and its smallest deviation there; the largest
    deviation of an environment change."""
    gains = [g for g in GAINS]
    environments = [k for k in next(iter(table.values())) if k not in gains]
    print(f'\n{"case":52s} ' + ' '.join(f'{g[:14]:>14s}' for g in gains) + f' {"environment":>14s}')
    for name, row in table.items():
        env = max(row[k] for k in environments)
        print(f'{name[:52]:52s} ' + ' '.join(f'{row[g]:14.2e}' for g in gains) + f' {env:14.2e}')
    status = 0
    print(f'\ntolerance {TOLERANCE:g} (relative to max(1, |golden|))')
    for gain in gains:
        moved = {name: row[gain] for name, row in table.items() if row[gain] > 0}
        if not moved:
            print(f'{gain}: moves no case')
            continue
        name = min(moved, key=moved.__getitem__)
        below = [n for n, d in moved.items() if d <= TOLERANCE]
        status |= all(d <= 10 * TOLERANCE for d in moved.values())
        print(
            f'{gain}: moves {len(moved)} of {len(table)} cases; smallest deviation {moved[name]:.2e} ({name}), '
            f'{moved[name] / TOLERANCE:.3g} x the tolerance' + (f'; WITHIN the tolerance: {below}' if below else '')
        )
    for label in environments:
        worst = max(table, key=lambda n: table[n][label])
        print(
            f'{label}: largest deviation {table[worst][label]:.2e} ({worst}), '
            f'{table[worst][label] / TOLERANCE:.3g} x the tolerance'
        )
        status |= table[worst][label] > TOLERANCE
    if out is not None:
        out.write_text(json.dumps(table, indent=1) + '\n', encoding='utf-8')
    return status


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog='python -m tests.support.regression', description=__doc__.split('\n\n')[0])
    action = parser.add_mutually_exclusive_group(required=True)
    action.add_argument('--write', action='store_true', help='regenerate the golden file from this tree')
    action.add_argument(
        '--write-variant', action='store_true', help="add this machine kind's records where they differ"
    )
    action.add_argument('--compare', action='store_true', help='OK / DIFF per case; exit 1 on any drift')
    action.add_argument('--sensitivity', action='store_true', help='measure 1e-9 gain changes against environments')
    parser.add_argument('--case', default=None, help='only the cases whose name contains this text')
    parser.add_argument('--pattern', default=None, help='only the cases whose name matches this regular expression')
    parser.add_argument('--arrays', type=Path, default=None, help='golden arrays (.npz): write, or read to locate')
    parser.add_argument('--deviations', type=Path, default=None, help="--compare: each case's largest deviations")
    parser.add_argument('--out', type=Path, default=None, help='--sensitivity: the table as JSON')
    args = parser.parse_args(argv)
    cases = _selected(args.case, args.pattern)
    if args.write:
        write(cases, args.arrays)
        return 0
    if args.write_variant:
        return write_variant(cases)
    if args.sensitivity:
        return sensitivity(cases, args.out)
    return compare(cases, args.arrays, args.deviations)


if __name__ == '__main__':
    sys.exit(main())
