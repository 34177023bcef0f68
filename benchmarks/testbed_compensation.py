"""The shipped Robotarium scenes under the testbed models, with and without the delay compensation.

    python -m benchmarks.testbed_compensation [--seeds 10] [--scenes robotarium_trapezoid,robotarium_curve]
        [--models ideal,fitted,fitted:2] [--no-initialization] [--workers 2]

Each scene is flown planned on the bundled simulator with V2's initialization (seeds 0..n-1; the same seed gives
the same initialization in every column) under each testbed model (`robotarium_exp.rps.testbed_model`), with
the swarm step acting on where the robots are (``none``), or compensating the fitted model's delay and lag
(``fitted``: the Robotarium scenes' default, what a submission knows of the real robots), or the flown model's own (``own``: the same as
``fitted`` under ``fitted``; under ``ideal`` it is ``none``). Printed per scene, model and compensation, over the
seeds: the verifier's counts (pair-steps too close, steps outside, actuator steps), runs in which every robot
passed and parked, body-on-wall robot-steps, the smallest distance between centres, and the passing time (mean
[min, max]). Distances and violations are measured on the poses the simulator hands out (with the model's pose
noise, under a millimetre); the verifier counts the true poses.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import itertools
import multiprocessing
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace

import numpy as np

COMPENSATIONS = ('none', 'fitted', 'own')


def fly(scene_name: str, model_name: str, compensation: str, seed: int, initialize: bool) -> dict[str, float]:
    """One planned flight; its counts and metrics."""
    from robotarium_exp.experiment import ExperimentConfig, run_experiment
    from robotarium_exp.rps.robotarium import Robotarium
    from robotarium_exp.rps.testbed_model import testbed_model
    from robotarium_exp.rps_alias import seed_rps
    from robotarium_exp.scene import load_scene
    from vtube.pipeline import plan_for

    scene = load_scene(scene_name)
    plan = plan_for(scene)
    known = {'none': testbed_model('ideal'), 'fitted': testbed_model('fitted'), 'own': testbed_model(model_name)}
    model = known[compensation]
    delay = 0.5 * (model.delay_v_steps + model.delay_omega_steps)
    scene = replace(scene, control=replace(scene.control, compensate_delay_steps=delay, compensate_lag_s=model.lag_s))
    seed_rps(seed)
    kwargs = {'skip_initialization': not initialize, 'testbed_model': model_name}
    with contextlib.redirect_stdout(io.StringIO()):  # V2's "Initializing..." lines
        result = run_experiment(Robotarium, scene, plan, ExperimentConfig(planning=True), robotarium_kwargs=kwargs)
    e, m = result.errors, result.metrics
    return {
        'too_close': e.too_close,
        'outside': e.outside,
        'actuator': e.actuator,
        'through': float(result.completed),
        'wall': m.tube_violation_steps,
        'min_distance_m': m.min_distance_m,
        'passing_time_s': m.passing_time_s,
    }


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seeds', type=int, default=10)
    parser.add_argument('--scenes', default='robotarium_trapezoid,robotarium_curve')
    parser.add_argument('--models', default='ideal,fitted,fitted:2')
    parser.add_argument('--no-initialization', action='store_true')
    parser.add_argument('--workers', type=int, default=2)
    args = parser.parse_args(argv)
    cases = list(itertools.product(args.scenes.split(','), args.models.split(','), COMPENSATIONS))
    cases = [c for c in cases if not (c[2] == 'own' and c[1] in ('fitted', 'ideal'))]  # the same as another
    jobs = [(*case, seed, not args.no_initialization) for case in cases for seed in range(args.seeds)]
    context = multiprocessing.get_context('spawn')
    with ProcessPoolExecutor(args.workers, mp_context=context) as pool:
        rows = list(pool.map(fly, *zip(*jobs)))
    print(
        '| scene | model | compensation | too close / outside / actuator | through and parked | body on wall '
        '| min distance [m] | passing time [s] |'
    )
    print('|---|---|---|---|---|---|---|---|')
    for k, (scene, model, compensation) in enumerate(cases):
        runs = rows[k * args.seeds : (k + 1) * args.seeds]
        total = {key: sum(r[key] for r in runs) for key in ('too_close', 'outside', 'actuator', 'wall')}
        times = np.array([r['passing_time_s'] for r in runs])
        through = int(sum(r['through'] for r in runs))
        print(
            f'| {scene} | {model} | {compensation} | {total["too_close"]:.0f} / {total["outside"]:.0f} / '
            f'{total["actuator"]:.0f} | {through}/{len(runs)} | {total["wall"]:.0f} | '
            f'{min(r["min_distance_m"] for r in runs):.3f} | '
            f'{np.nanmean(times):.1f} [{np.nanmin(times):.1f}, {np.nanmax(times):.1f}] |'
        )


if __name__ == '__main__':
    main()
