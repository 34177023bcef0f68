"""``vtube plan``: speed and density along a scene's tube (`vtube.pipeline.plan_scene`)."""

from __future__ import annotations

import argparse
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

from vtube.cli.arguments import positive, writable_folder
from vtube.cli.command import EXIT_FAILED, EXIT_OK, BadInput, Command, View

if TYPE_CHECKING:
    from vtube.pipeline import Planned


TERMS = {'entry_s': 'entry half-extent', 'exit_s': 'exit half-extent'}
"""The last-robot-out terms of the objective, as the plan's summary names them."""


OBJECTIVES = ('centre', 'last_out')
"""`vtube_planning.params.OBJECTIVES`, written here so that a refusal of the plan command's options imports no
numerical library."""


def plan_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('scene', help='a shipped scene name (see `vtube scene list`) or a .toml file')
    parser.add_argument('--out', type=Path, required=True, help='folder for the plan file and its figure')
    parser.add_argument(
        '--method',
        choices=('convex', 'polynomial'),
        default='convex',
        help="convex: slowness form (default); polynomial: the paper's cubic segments",
    )
    parser.add_argument(
        '--grid-step',
        type=positive,
        default=None,
        dest='grid_step_m',
        help="planning grid step in m, > 0 (default: the scene's)",
    )
    parser.add_argument(
        '--objective',
        choices=OBJECTIVES,  # the planner's (tests/unit/vtube/cli/test_plan.py holds them equal)
        default=None,
        help="centre: the swarm centre's traversal time, the paper's (p1); last_out: first robot in to last robot "
        "out, the passing time measured (default: the scene's [planning] objective, else centre)",
    )


def plan(args: argparse.Namespace) -> Planned:
    from vtube.pipeline import plan_scene

    writable_folder(args.out)
    room_for_a_robot(args.scene)
    room_to_turn(args.scene, paper_plan_only=True)
    return plan_scene(args.scene, args.out, method=args.method, grid_step_m=args.grid_step_m, objective=args.objective)


def room_for_a_robot(name_or_path: str) -> None:
    """Refuse, before planning, a tube whose narrowest part is no wider than a robot (half-width <= r_p): the
    planner's model sees densities, not bodies, and would certify a plan that no robot can fly."""
    import numpy as np

    from robotarium_exp.scene import load_scene

    scene = load_scene(name_or_path)
    l_m = np.linspace(0.0, scene.tube.length_m, 4001)
    half = np.asarray(scene.tube.half_width(l_m), dtype=float)
    k = int(np.argmin(half))
    if half[k] <= scene.swarm.r_p_m:
        msg = (
            f'scene {scene.name!r}: the tube is {2 * half[k]:.3f} m wide at l = {l_m[k]:.3f} m, no wider than a robot '
            f'(2 r_p = {2 * scene.swarm.r_p_m:g} m): no robot fits through; widen the tube there.'
        )
        raise BadInput(msg)


def room_to_turn(name_or_path: str, *, paper_plan_only: bool = False) -> None:
    """Refuse, before any work, a tube with a bend through which no path turns no tighter than v_min^2 / a_n, the
    tightest turn of a robot held to (2) and (4) (`vtube_planning.geometry.bends`, ``docs/theory.md`` §3.6); with
    ``paper_plan_only`` only for a plan held to the paper's (p4) (a relaxed plan leaves (4) out)."""
    from robotarium_exp.scene import load_scene
    from vtube_planning.geometry.bends import too_tight

    scene = load_scene(name_or_path)
    if paper_plan_only and scene.planning.freedom != 'paper':
        return
    swarm = scene.swarm
    why = too_tight(scene.tube, swarm.v_min_mps**2 / swarm.a_n_mps2, swarm.r_p_m)
    if why is not None:
        raise BadInput(f'scene {scene.name!r}: {why}.')


def plan_view(planned: Planned) -> View:
    plan, scene = planned.plan, planned.scene
    k = int(plan.density_per_m2.argmin())
    worst = ', '.join(f'{name} {value:.1e}' for name, value in plan.certificate.items())
    verdict = 'certified' if plan.is_certified() else 'NOT certified (violation above 1e-6)'
    lines: tuple[str, ...] = (
        (
            f'plan for scene {scene.name} ({planned.method}, {plan.l_m.size} grid points, {plan.solved.status} after '
            f'{plan.solved.iterations} iterations, {plan.solved.solve_time_s:.3f} s)'
        ),
        f'  traversal time        {plan.time_s:.4f} s',
        *_last_out_line(plan.objective),
        (
            f'  objective J           {plan.objective["total"]:.6f}  (time {plan.objective["time_s"]:.6f} + '
            + ''.join(f'{TERMS[name]} {plan.objective[name]:.6f} + ' for name in TERMS if name in plan.objective)
            + f'density {plan.objective["density"]:.6f})'
        ),
        f'  speed                 {plan.speed_mps.min():.4g} .. {plan.speed_mps.max():.4g} m/s',
        (
            f'  density               min {plan.density_per_m2[k]:.4g} at l = {plan.l_m[k]:.3f} m, '
            f'rho_d = {scene.swarm.rho_d_per_m2:g} /m^2'
        ),
        f'  certificate           {verdict}: {worst}',
    )
    failures = plan.failures(scene.tube)
    if failures:
        lines += (f'  fails                 {"; ".join(failures)}',)
    if planned.fit is not None:
        lines += (f'  Robotarium            {planned.fit.reason}',)
        failures = failures if planned.fit.fits else (*failures, planned.fit.reason)
    lines += (f'  written               {planned.plan_file}, {planned.figure}, {planned.scene_copy}',)
    data = {'plan_file': str(planned.plan_file), 'time_s': plan.time_s, 'objective': plan.objective}
    data |= {'certificate': plan.certificate, 'certified': plan.is_certified()}
    data |= {'failures': list(failures)} if failures else {}
    return View(lines, data | {'provenance': plan.provenance}, exit_code=EXIT_FAILED if failures else EXIT_OK)


def _last_out_line(objective: Mapping[str, float]) -> tuple[str, ...]:
    """The modelled passing time of a plan made for the last robot out (none for the centre's time)."""
    if 'exit_s' not in objective:
        return ()
    passing = objective['time_s'] + objective['entry_s'] + objective['exit_s']
    return (f'  passing time (model)  {passing:.4f} s  (first robot in to last robot out)',)


COMMAND = Command('plan', "plan speed and density along a scene's tube", plan_arguments, plan, plan_view, json=True)
