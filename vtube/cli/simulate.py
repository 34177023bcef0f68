"""``vtube simulate``: the swarm flown through a scene (`vtube.pipeline.simulate_scene`)."""

from __future__ import annotations

import argparse
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

from vtube.cli.arguments import count, positive, seed, writable_folder
from vtube.cli.command import EXIT_FAILED, EXIT_OK, BadInput, Command, View
from vtube.cli.plan import room_to_turn
from vtube.cli.render import progress_bars

if TYPE_CHECKING:
    from vtube.pipeline import Simulated
    from vtube_planning.swarm.map_contact import MapContact
    from vtube_planning.swarm.simulate import SimConfig, SimResult


def simulate_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('scene', help='a shipped scene name or a .toml file')
    parser.add_argument('--out', type=Path, required=True, help='folder for the log, figures and GIF')
    parser.add_argument('--no-planning', action='store_true', help='constant mid-range speed and constant r_a')
    parser.add_argument(
        '--n', type=count, default=None, dest='n_robots', help="swarm size, >= 1 (default: the scene's)"
    )
    parser.add_argument('--seed', type=seed, default=0, help='seed of the initial formation jitter, >= 0')
    parser.add_argument(
        '--acceleration-limits',
        action='store_true',
        help='make every robot obey the acceleration limits (3), (4), not only the plan',
    )
    parser.add_argument(
        '--controller',
        choices=('law', 'foresight'),
        default=None,
        help="'law': the paper's law alone; 'foresight': the law under the foresight, the safety layer of robots "
        "held to (2)-(4) (docs/theory.md section 11; its horizon: the scene's [control] foresight_s, else "
        '(v_max - v_min) / a_v). Default: foresight with --acceleration-limits, else the law',
    )
    parser.add_argument('--animate', action='store_true', help='also write an animated GIF')
    parser.add_argument('--quiet', action='store_true', help='no progress bar (none is drawn unless on a terminal)')
    parser.add_argument('--plan', type=Path, default=None, help='fly this plan file (vtube plan) instead of planning')
    parser.add_argument(
        '--replan-every',
        type=positive,
        default=0.0,
        dest='replan_every_s',
        metavar='S',
        help='replan the rest of the tube every S seconds from the measured state, > 0 (default: never)',
    )


MAX_ROBOTS = 5000
"""The largest swarm `vtube simulate` flies (--n): the paper's studies fly at most 80."""


def simulate(args: argparse.Namespace) -> Simulated:
    """Fly the scene, holding ``--out`` (`vtube_planning.studies.campaign_store.holding`: a second run into the same
    folder is refused, not mixed into one log)."""
    from vtube.pipeline import simulate_scene
    from vtube_planning.studies.campaign_store import holding
    from vtube_planning.swarm.simulate import SimConfig

    writable_folder(args.out)
    _check_swarm_size(args.scene, args.n_robots)
    if args.acceleration_limits:
        room_to_turn(args.scene)
    made = not args.out.exists()
    with holding(args.out, 'simulate'), _removed_if_left_empty(args.out, made):
        return simulate_scene(
            args.scene,
            args.out,
            planning=not args.no_planning,
            n_robots=args.n_robots,
            plan_file=args.plan,
            foresight=(args.controller or ('foresight' if args.acceleration_limits else 'law')) == 'foresight',
            config=SimConfig(
                seed=args.seed, acceleration_limits=args.acceleration_limits, replan_every_s=args.replan_every_s
            ),
            animate=args.animate,
            progress=progress_bars(quiet=args.quiet),
        )


@contextmanager
def _removed_if_left_empty(out: Path, made: bool) -> Iterator[None]:
    """Inside: a run into ``out``; a folder it ``made`` and left empty (a refusal: nothing flown) is removed."""
    from vtube_planning.studies.campaign_store import LOCK_FILE

    try:
        yield
    except BaseException:
        if made and out.is_dir() and not any(p.name != LOCK_FILE for p in out.iterdir()):
            (out / LOCK_FILE).unlink(missing_ok=True)
            out.rmdir()
        raise


def _check_swarm_size(scene_name: str, n_robots: int | None) -> None:
    """Refuse, before any work, a swarm larger than `MAX_ROBOTS`, or than the testbed holds for a Robotarium
    scene."""
    if n_robots is None:
        return
    if n_robots > MAX_ROBOTS:
        msg = f'--n {n_robots}: vtube simulate flies at most {MAX_ROBOTS} robots; give --n {MAX_ROBOTS} or fewer.'
        raise BadInput(msg)
    from robotarium_exp.scene import load_scene
    from robotarium_exp.spec import ROBOTARIUM

    if n_robots > ROBOTARIUM.max_robots and load_scene(scene_name).testbed == 'robotarium':
        msg = (
            f'--n {n_robots}: scene {scene_name!r} is a Robotarium scene, which flies 1 to {ROBOTARIUM.max_robots} '
            f"robots (the testbed's); give --n {ROBOTARIUM.max_robots} or fewer, or simulate a scene of the paper."
        )
        raise BadInput(msg)


def _map_row(contact: MapContact) -> str:
    """The summary's map row: contacts up to each robot's exit and beyond it, told apart (the fixes differ); every
    one fails the run but, for a Robotarium scene, those beyond the exit (`MapContact.fails_beyond_exit`)."""
    said = (
        f'bodies (r_p) on obstacles {contact.on_obstacles} robot-steps, outside the workspace '
        f'{contact.outside_workspace}, up to their exit'
    )
    said += (
        f'; beyond the exit, where this model drives on until the last robot is through (no parking): on obstacles '
        f'{contact.on_obstacles_after_exit}, outside the workspace {contact.outside_after_exit}'
    )
    beyond = contact.on_obstacles_after_exit + contact.outside_after_exit
    if beyond and not contact.fails_beyond_exit:
        said += ' (not failures: the Robotarium flight parks there, and `vtube robotarium run` judges it)'
    return said


def simulate_view(simulated: Simulated) -> View:
    from vtube_planning.swarm.map_contact import map_contact
    from vtube_planning.swarm.metrics import passage_failures

    result, config, m = simulated.result, simulated.config, simulated.result.metrics
    scene = simulated.scene
    mapped = bool(scene.obstacles) or scene.workspace is not None
    contact = map_contact(result.t_s, result.positions_m, scene, simulated.swarm.r_p_m, result.l_m) if mapped else None
    failures = (*passage_failures(m), *(contact.failures() if contact else ()), *_unflyable(result, config))
    rows = [
        ('passing time', f'{m.passing_time_s:.3f} s' + ('' if m.completed else ' (not every robot exited)')),
        ('minimum distance', f'{m.min_distance_m:.4f} m at t = {m.min_distance_time_s:.2f} s'),
        ('collisions', f'{m.collision_pairs} pairs closer than 2 r_p = {m.collision_distance_m:g} m'),
        (
            'tube violations',
            f'{m.tube_violation_steps} robot-steps, {m.robots_outside} robots, up to {m.max_outside_m:.3f} m outside',
        ),
        ('speed violations', f'{m.speed_violations} commands outside [v_min, v_max]'),
        ('model violations', f"{result.dynamics_violations} commands outside (2)-(4) from the robot's velocity"),
        ('controller', _controller(simulated.scene.control.foresight_s)),
    ]
    if contact is not None:  # over the whole run, before the entrance and after the exit
        rows.append(('map', _map_row(contact)))
    if m.speed_tracking_mean_mps is not None:
        rows += [
            ('speed tracking', f'mean {m.speed_tracking_mean_mps:.3f}, max {m.speed_tracking_max_mps:.3f} m/s'),
            (
                'density tracking',
                f'mean {m.density_tracking_mean_per_m2:.4f}, max {m.density_tracking_max_per_m2:.4f} /m^2',
            ),
        ]
    rows += [('start', simulated.start), *_narrows(simulated)]
    replans: list[dict[str, Any]] | None = result.meta.get('replans')
    if replans is not None:
        rows.append(('replanning', _replanning(replans, config.replan_every_s)))
    if failures:
        rows.append(('passage', 'FAILED: ' + '; '.join(failures)))
    rows.append(('written', ', '.join(map(str, simulated.written))))
    head = (
        f'simulation of scene {simulated.scene.name} {"with" if result.planned else "without"} planning: '
        f'N = {simulated.swarm.n_robots}, seed {config.seed}, {result.t_s.size} steps of {config.dt_s} s'
    )
    data = {'log': str(simulated.log), 'metrics': m.to_json(), 'provenance': result.meta['provenance']}
    data['dynamics_violations'] = result.dynamics_violations
    data['controller'] = _controller(simulated.scene.control.foresight_s)
    if replans is not None:
        data['replans'] = replans
    if failures:
        data['failures'] = list(failures)
    lines = (head, *(f'  {name:<18} {value}' for name, value in rows))
    return View(lines, data, exit_code=EXIT_FAILED if failures else EXIT_OK)


def _narrows(simulated: Simulated) -> list[tuple[str, str]]:
    """A row where the tube is narrower than the avoidance radius r_a: the law's wall barrier (sigma(d, r_s, r_a)
    of the clearance d) acts from both walls there, and its lateral push, saturated radially, leaves little forward
    speed (none where the half-width is r_s or less): robots crawl or stop, far behind the plan (issue 49)."""
    import numpy as np

    tube, swarm = simulated.scene.tube, simulated.swarm
    l_m = np.linspace(0.0, tube.length_m, 2001)
    half = np.asarray(tube.half_width(l_m), dtype=float)
    k = int(np.argmin(half))
    if half[k] >= swarm.r_a_m:
        return []
    said = (
        f'half-width {half[k]:.3f} m at l = {l_m[k]:.2f} m, below r_a = {swarm.r_a_m:g} m: the wall barrier pushes '
        'from both walls there and leaves little forward speed'
        + (f' (none at r_s = {swarm.r_s_m:g} m or less: no robot passes)' if half[k] <= swarm.r_s_m else '')
        + '; robots crawl through, far slower than planned: widen the tube or lower r_a_m'
    )
    return [('narrowest', said)]


def _unflyable(result: SimResult, config: SimConfig) -> tuple[str, ...]:
    """The failure of commands the robots could not fly, under the acceleration limits (the paper's model flies
    any command)."""
    if config.acceleration_limits and result.dynamics_violations:
        return (f'{result.dynamics_violations} commands the robots could not fly under (2)-(4)',)
    return ()


def _controller(horizon_s: float) -> str:
    """What commanded the robots, in words."""
    return f'the law under the foresight (horizon {horizon_s:g} s)' if horizon_s > 0 else 'the law alone'


def _replanning(replans: list[dict[str, Any]], every_s: float) -> str:
    """The replanning calls in one line: how many, how long, how many found the state infeasible."""
    done = sorted(call['wall_ms'] for call in replans if not call['error'])
    timing = f', median {done[len(done) // 2]:.0f} ms, largest {done[-1]:.0f} ms' if done else ''
    infeasible = len(replans) - len(done)
    return (
        f'every {every_s:g} s: {len(done)} replans{timing}; {infeasible} found the state infeasible and kept the plan'
    )


COMMAND = Command(
    'simulate',
    'fly the swarm through a scene, with or without planning',
    simulate_arguments,
    simulate,
    simulate_view,
    json=True,
)
