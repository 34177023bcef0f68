"""Bit-for-bit fingerprints of every simulated trajectory: plans, study and ablation runs, faults, Robotarium runs
and the committed submissions' flights, each for a fixed scene and seed.

    PYTHONPATH=$TREE python -m tests.bit_for_bit --compare   # OK / DIFF per case against tests/bit_for_bit.json
    PYTHONPATH=$TREE python -m tests.bit_for_bit --write     # regenerate the reference from $TREE's code
Options: ``--case TEXT`` runs the cases whose name contains TEXT; ``--arrays FILE.npz`` keeps (--write) or reads
(--compare) the reference arrays, to name the first differing step and the largest deviation of a DIFF.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import hashlib
import importlib.metadata
import io
import json
import os
import platform
import random
import re
import runpy
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
from vtube_planning import study as run_point_module  # the module whose ``simulate`` run_point calls
from vtube_planning.geometry.scene import load_scene
from vtube_planning.planning.planner import plan_convex
from vtube_planning.study import Point, ablation_setup, run_point
from vtube_planning.swarm.simulate import SimConfig, simulate

ROOT = Path(__file__).resolve().parents[1]
REFERENCE = Path(__file__).with_name('bit_for_bit.json')
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
    slow: bool = False


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
    """A subclass of a Robotarium class that keeps every pose it hands out (initialization included)."""

    def __init__(self, base: type) -> None:
        poses: list[np.ndarray] = []

        class Recorded(base):  # type: ignore[misc, valid-type]
            def get_poses(self) -> Any:
                out = super().get_poses()
                poses.append(np.array(out, dtype=np.float64, copy=True))
                return out

        Recorded.__name__ = base.__name__
        self.cls, self.poses = Recorded, poses

    def array(self) -> np.ndarray:
        return np.array(self.poses)


# ---------------------------------------------------------------------- the cases


def _plan(scene_name: str) -> tuple[Arrays, Scalars]:
    scene = load_scene(scene_name)
    plan = plan_convex(scene.tube, scene.swarm, scene.planning, scene=scene.name)
    arrays = {name: getattr(plan, name) for name in ('l_m', 'speed_mps', 'density_per_m2')}
    arrays |= _arrays(plan.profile, 'profile')
    return arrays, _scalars({'time_s': plan.time_s, 'objective': plan.objective}, 'plan')


def _point(point: Point) -> tuple[Arrays, Scalars]:
    """run_point's row and the arrays of the simulation it ran."""
    flown = []

    def keep(*args: Any, **kwargs: Any) -> Any:
        flown.append(simulate(*args, **kwargs))
        return flown[-1]

    if getattr(run_point_module, 'simulate', None) is not simulate:
        msg = 'run_point_module must be the module whose `simulate` run_point calls; fix the import in bit_for_bit.py'
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
    """The tube experiment on the bundled V2 simulator with seed 0, as ``vtube robotarium run`` flies it."""
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
    scalars = {'duration_s': result.duration_s, 'completed': result.completed}
    scalars |= {'errors': result.errors, 'barrier': result.barrier, 'metrics': result.metrics}
    return arrays, _scalars(scalars, 'result')


def _submission(filename: str) -> tuple[Arrays, Scalars]:
    """A committed submission file run as ``rps_alias --seed 0 FILE`` runs it: every pose the simulator handed out,
    and every numeric array the file saved (compared by content: names may change)."""
    rps_modules = {name: module for name, module in sys.modules.items() if name.split('.')[0] == 'rps'}
    with tempfile.TemporaryDirectory() as folder, _inside(Path(folder)), _headless():
        try:
            install_rps(seed=0)
            module = sys.modules['rps.robotarium']
            recorder = _Recorder(module.Robotarium)
            module.Robotarium = recorder.cls  # type: ignore[attr-defined]
            runpy.run_path(str(ROOT / 'submissions' / filename), run_name='__main__')
        finally:
            for name in [name for name in sys.modules if name.split('.')[0] == 'rps']:
                del sys.modules[name]
            sys.modules.update(rps_modules)
        saved = _saved_arrays(Path(folder))
    return {'get_poses': recorder.array()} | {f'saved.{name}': a for name, a in saved.items()}, {}


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
    Case('baseline_C_flocking', lambda: _point(Point(C, mode='flocking'))),
    Case('baseline_C_flocking_v_min', lambda: _point(Point(C, mode='flocking (v_min)'))),
    Case('baseline_C_nmpc_first_1s', lambda: _simulation(C, 'nmpc', SimConfig(time_limit_s=1.0)), slow=True),
    Case('model_C_acceleration_limits', lambda: _point(Point(C, model='acceleration limits'))),
    Case('saturation_C_forward', lambda: _point(Point(C, saturation='forward'))),
    Case('fault_C_pose_noise_0.02', lambda: _point(Point(C, pose_noise_m=0.02))),
    Case('fault_C_latency_2', lambda: _point(Point(C, latency_steps=2))),
    Case('fault_C_dropout_0.1', lambda: _point(Point(C, dropout=0.1))),
    Case('fault_C_failure_stop', lambda: _point(Point(C, failure='stop')), slow=True),
    Case('fault_C_failure_coast', lambda: _point(Point(C, failure='coast'))),
    Case('fault_C_replanning_failure_coast', lambda: _point(Point(C, mode='replanning every 0.5 s', failure='coast'))),
    Case('grid_C_N80_kdtree', lambda: _point(Point(C, n_robots=80))),
    Case('control_C_kdtree_forced', lambda: _simulation(C, 'planning', SimConfig(), {'kdtree_above': 0})),
    Case(
        'control_C_practical_law_current_padding',
        lambda: _simulation(C, 'planning', SimConfig(), {'law': 'practical', 'density_padding': 'current'}),
    ),
    *(
        Case(f'robotarium_{s}_{p}', lambda s=s, p=p: _experiment(f'robotarium_{s}', p == 'planned'), slow=True)
        for s in ('trapezoid', 'curve')
        for p in ('planned', 'unplanned')
    ),
    Case(
        'robotarium_trapezoid_planned_no_barrier_no_init',
        lambda: _experiment('robotarium_trapezoid', True, barrier=False, skip_initialization=True),
    ),
    *(
        Case(f'submission_{f}', lambda f=f: _submission(f), slow=True)
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


def diagnostics(arrays: Arrays) -> dict[str, Any]:
    """Steps and the first robot's last pose (float.hex) of the run's main array."""
    for name in ('positions_m', 'arrays.positions_m', 'get_poses', 'speed_mps'):
        if name in arrays:
            a = np.asarray(arrays[name], dtype=np.float64)
            last = a[-1, :, 0] if a.ndim == 3 else a[-1:]
            return {'array': name, 'steps': len(a), 'last_first_robot': [float(x).hex() for x in last]}
    return {}


def fingerprint(case: Case) -> tuple[dict[str, Any], Arrays]:
    """The case's record (arrays' hashes, scalars, diagnostics, seconds) and its arrays."""
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
        'diagnostics': diagnostics(arrays),
        'seconds': round(time.perf_counter() - started, 2),
        'cpu_seconds': round(time.process_time() - cpu, 2),
    }
    return record, arrays


def environment() -> dict[str, str]:
    """What the bits depend on beyond the code: the machine, the C library, Python, the numerical packages'
    versions, the SIMD features numpy dispatches to and numpy's BLAS."""
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
    try:
        from numpy._core._multiarray_umath import __cpu_features__ as features
    except ImportError:  # numpy < 2
        from numpy.core._multiarray_umath import __cpu_features__ as features
    key['numpy_simd'] = ' '.join(sorted(name for name, on in features.items() if on))
    try:
        blas = np.show_config(mode='dicts')['Build Dependencies']['blas']
        key['numpy_blas'] = f'{blas.get("name")} {blas.get("version")}'
    except (TypeError, KeyError):  # numpy < 1.26: no dicts
        key['numpy_blas'] = 'unknown'
    return key


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


def differences(
    old: dict[str, Any], new: dict[str, Any], arrays: Arrays | None = None, reference: Arrays | None = None
) -> tuple[list[str], list[str]]:
    """(differences, notes) of a run's record ``new`` against the reference record ``old``. An array is the same
    when its name holds the same bits or, when no array has its name (or it is a file's, ``saved.``), when some
    array (or a pose array's positions and headings) holds them; a scalar differs when its name holds another
    value (a scalar no longer returned is a note)."""
    found, notes = [], []
    content = _candidates(new['arrays'])
    for name, record in old['arrays'].items():
        if name in new['arrays'] and new['arrays'][name]['sha256'] == record['sha256']:
            continue
        if name in new['arrays'] and not name.startswith('saved.'):
            found.append(_where(name, record, new['arrays'][name], arrays or {}, reference))
        elif record['sha256'] in content:
            notes.append(f'{name} is now {content[record["sha256"]]} (same bits)')
        elif record.get('parts') and all(p in content for p in record['parts'].split()):
            notes.append(f'{name} is now {" + ".join(content[p] for p in record["parts"].split())} (same bits)')
        elif name in new['arrays']:
            found.append(_where(name, record, new['arrays'][name], arrays or {}, reference))
        else:
            found.append(f'{name}: no array of the run holds its bits')
    known = set(_candidates(old['arrays']))
    notes += [f'new array {n}' for n, r in new['arrays'].items() if n not in old['arrays'] and r['sha256'] not in known]
    for name, value in old['scalars'].items():
        if name not in new['scalars']:
            notes.append(f'scalar {name} no longer returned')
        elif new['scalars'][name] != value:
            found.append(f'{name}: {value} -> {new["scalars"][name]}')
    if found and old.get('diagnostics') != new.get('diagnostics'):
        found.append(f'diagnostics {old.get("diagnostics")} -> {new.get("diagnostics")}')
    return found, notes


def _json(value: Any, depth: int = 0) -> str:
    """JSON with one line per array record (depth 4: cases / case / arrays / array)."""
    if not isinstance(value, dict) or depth == 4 or not value:
        return json.dumps(value)
    pad = ' ' * (depth + 1)
    items = (f'{pad}{json.dumps(k)}: {_json(v, depth + 1)}' for k, v in value.items())
    return '{\n' + ',\n'.join(items) + '\n' + ' ' * depth + '}'


def load_reference(path: Path = REFERENCE) -> dict[str, Any]:
    return json.loads(path.read_text(encoding='utf-8'))


def _selected(text: str | None) -> list[Case]:
    cases = [c for c in CASES if text is None or text in c.name]
    if not cases:
        raise SystemExit(f'no case name contains {text!r}; the cases: {", ".join(c.name for c in CASES)}')
    return cases


def write(cases: list[Case], arrays_path: Path | None) -> None:
    """Fingerprint ``cases`` into the reference (other cases' records are kept when only some are run)."""
    old = load_reference() if REFERENCE.exists() and len(cases) < len(CASES) else {'cases': {}}
    records, kept = dict(old['cases']), {}
    for case in cases:
        records[case.name], arrays = fingerprint(case)
        kept |= {f'{case.name}/{name}': a for name, a in arrays.items()}
        seconds = records[case.name]['seconds'], records[case.name]['cpu_seconds']
        print(f'{seconds[0]:7.2f} s ({seconds[1]:6.2f} s CPU)  {case.name}', flush=True)
    names = [c.name for c in CASES]
    out = {'environment': environment(), 'cases': {n: records[n] for n in names if n in records}}
    REFERENCE.write_text(_json(out) + '\n', encoding='utf-8')
    seconds = sum(r['cpu_seconds'] for r in out['cases'].values())
    print(f'written {REFERENCE} ({seconds:.1f} s of runs, CPU)')
    if arrays_path is not None:
        np.savez_compressed(arrays_path, **kept)
        print(f'written {arrays_path}')


def compare(cases: list[Case], arrays_path: Path | None) -> int:
    """Print OK / DIFF per case against the reference; 1 on any DIFF or missing case, else 0."""
    reference = load_reference()
    changed = environment_differences(reference['environment'])
    if changed:
        print(f'note: the reference was written in another environment ({changed}); bits may differ for that alone')
    saved = np.load(arrays_path) if arrays_path is not None else None
    failed, total = 0, 0.0
    for case in cases:
        old = reference['cases'].get(case.name)
        new, arrays = fingerprint(case)
        total += new['cpu_seconds']
        if old is None:
            failed += 1
            print(f'DIFF  {case.name}: not in the reference (--write it)', flush=True)
            continue
        mine = None
        if saved is not None:
            mine = {k.split('/', 1)[1]: saved[k] for k in saved.files if k.startswith(case.name + '/')}
        found, notes = differences(old, new, arrays, mine)
        failed += bool(found)
        print(f'{"DIFF" if found else "OK  "}  {case.name} ({new["cpu_seconds"]:.2f} s CPU)', flush=True)
        for line in found:
            print(f'        {line}')
        for line in notes:
            print(f'        note: {line}')
    missing = [name for name in reference['cases'] if name not in {c.name for c in CASES}]
    for name in missing:
        print(f'DIFF  {name}: in the reference, no longer a case')
    print(f'{len(cases) - failed} of {len(cases)} cases the same bits ({total:.1f} s CPU)')
    return 1 if failed or missing else 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog='python -m tests.bit_for_bit', description=__doc__.split('\n\n')[0])
    action = parser.add_mutually_exclusive_group(required=True)
    action.add_argument('--write', action='store_true', help='regenerate tests/bit_for_bit.json from this tree')
    action.add_argument('--compare', action='store_true', help='OK / DIFF per case; exit 1 on any DIFF')
    parser.add_argument('--case', default=None, help='only the cases whose name contains this text')
    parser.add_argument('--arrays', type=Path, default=None, help='reference arrays (.npz): write, or read to locate')
    args = parser.parse_args(argv)
    cases = _selected(args.case)
    if args.write:
        write(cases, args.arrays)
        return 0
    return compare(cases, args.arrays)


if __name__ == '__main__':
    sys.exit(main())
