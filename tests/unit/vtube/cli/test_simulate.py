"""``vtube simulate``: its options handed to the pipeline, and the view of a simulated passage."""

from __future__ import annotations

import json
import math
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from tests.support.passage import metrics
from vtube import pipeline
from vtube.cli.app import main
from vtube.cli.command import View
from vtube.cli.simulate import _replanning, simulate_view
from vtube_planning.geometry.obstacles import Disc, Obstacles
from vtube_planning.swarm.formation import FloatArray
from vtube_planning.swarm.metrics import PassageMetrics
from vtube_planning.swarm.simulate import SimConfig

WIDE = SimpleNamespace(length_m=30.0, half_width=lambda l_m: np.full(np.shape(l_m), 2.0))
"""A tube 4 m wide throughout, wider than the swarm's r_a = 0.8 m."""


def simulated(
    m: PassageMetrics,
    *,
    planned: bool = True,
    meta: dict | None = None,
    outside: int = 0,
    limits: bool = False,
    tube: object = None,
) -> pipeline.Simulated:
    result = SimpleNamespace(
        metrics=m,
        planned=planned,
        t_s=np.zeros(625),
        meta={'provenance': {'p': 1}} | (meta or {}),
        dynamics_violations=outside,
    )
    return pipeline.Simulated(
        scene=SimpleNamespace(
            name='C', obstacles=(), workspace=None, control=SimpleNamespace(foresight_s=0.0), tube=tube or WIDE
        ),
        swarm=SimpleNamespace(n_robots=8, r_s_m=0.4, r_a_m=0.8),
        config=SimConfig(seed=3, replan_every_s=1.0, acceleration_limits=limits),
        result=result,
        written=(Path('o/sim_C_planned.npz'), Path('o/a.png')),
    )


def test_the_view_of_a_planned_passage() -> None:
    view = simulate_view(simulated(metrics()))
    assert view.lines[0] == 'simulation of scene C with planning: N = 8, seed 3, 625 steps of 0.02 s'
    assert '  passing time       12.500 s' in view.lines
    assert '  minimum distance   0.6123 m at t = 4.25 s' in view.lines
    assert '  collisions         0 pairs closer than 2 r_p = 0.6 m' in view.lines
    assert '  tube violations    3 robot-steps, 1 robots, up to 0.013 m outside' in view.lines
    assert '  density tracking   mean 0.0123, max 0.0500 /m^2' in view.lines
    assert view.lines[-2:] == (
        f'  start              {pipeline.GRID_START}',
        '  written            o/sim_C_planned.npz, o/a.png',
    )  # where the robots started: the grid of a paper scene (Robotarium scenes: tests/unit/vtube/test_pipeline.py)
    assert "  model violations   0 commands outside (2)-(4) from the robot's velocity" in view.lines
    assert '  controller         the law alone' in view.lines
    assert view.data == {
        'log': 'o/sim_C_planned.npz',
        'metrics': metrics().to_json(),
        'provenance': {'p': 1},
        'dynamics_violations': 0,
        'controller': 'the law alone',
    }


def test_the_view_of_an_unfinished_unplanned_passage_with_replanning() -> None:
    replans = [
        {'wall_ms': 30.0, 'error': None, 'step': 50},
        {'wall_ms': 10.0, 'error': None, 'step': 100},
        {'wall_ms': 20.0, 'error': None, 'step': 150},
        {'wall_ms': 5.0, 'error': 'infeasible', 'step': 200},
    ]
    m = metrics(completed=False, speed_tracking_mean_mps=None)
    view = simulate_view(simulated(m, planned=False, meta={'replans': replans}))
    assert 'without planning' in view.lines[0] and '(not every robot exited)' in view.lines[1]
    assert not any('tracking' in line for line in view.lines)
    assert '  replanning         every 1 s: 3 replans, median 20 ms, largest 30 ms; 1 found the state ' in (
        '\n'.join(view.lines)
    )
    assert view.data['replans'] == replans
    assert _replanning([], 2.0) == 'every 2 s: 0 replans; 0 found the state infeasible and kept the plan'


def test_a_passage_with_a_collision_or_a_robot_left_behind_fails() -> None:
    view = simulate_view(simulated(metrics(collision_pairs=1, collision_steps=4, min_distance_m=0.5)))
    assert view.exit_code == 1 and view.data['failures'] == [
        '1 robot pairs collided (closer than 0.6 m, 4 steps; closest 0.500 m at t = 4.25 s)'
    ]
    assert view.lines[-2] == '  passage            FAILED: ' + view.data['failures'][0]
    view = simulate_view(simulated(metrics(completed=False, robots_passed=7, passing_time_s=math.nan)))
    assert view.exit_code == 1 and '  passing time       nan s (not every robot exited)' in view.lines
    assert view.lines[-2] == '  passage            FAILED: 1 of 8 robots never passed the exit (no passing time)'
    assert simulate_view(simulated(metrics())).exit_code == 0  # 3 robot-steps outside: measured, not judged


def test_commands_the_robots_could_not_fly_fail_a_passage_under_the_acceleration_limits() -> None:
    view = simulate_view(simulated(metrics(), outside=12, limits=True))
    assert view.exit_code == 1
    assert view.data['failures'] == ['12 commands the robots could not fly under (2)-(4)']
    assert simulate_view(simulated(metrics(), outside=12)).exit_code == 0  # the paper's model: velocities jump


def test_the_options_reach_the_pipeline(tmp_path, monkeypatch, capsys) -> None:
    calls = []

    def simulate_scene(scene, out, **options):
        calls.append((scene, out, options))
        return simulated(metrics())

    monkeypatch.setattr(pipeline, 'simulate_scene', simulate_scene)
    args = ['simulate', 'C', '--out', str(tmp_path), '--n', '8', '--seed', '3', '--no-planning', '--animate']
    assert main([*args, '--acceleration-limits', '--replan-every', '2.5', '--quiet', '--json']) == 0
    (scene, out, options) = calls[0]
    assert (scene, out, options['planning'], options['n_robots'], options['plan_file']) == (
        'C',
        tmp_path,
        False,
        8,
        None,
    )
    assert options['config'] == SimConfig(seed=3, acceleration_limits=True, replan_every_s=2.5) and options['animate']
    assert json.loads(capsys.readouterr().out)['log'] == 'o/sim_C_planned.npz'
    assert main(['simulate', 'C', '--out', str(tmp_path), '--plan', 'p.npz']) == 0
    assert calls[1][2]['plan_file'] == Path('p.npz') and calls[1][2]['config'] == SimConfig()
    assert calls[1][2]['planning'] and calls[1][2]['n_robots'] is None and not calls[1][2]['animate']
    # the foresight flies with the acceleration limits unless the law alone is asked for, and only then
    assert options['foresight'] and not calls[1][2]['foresight']
    assert main(['simulate', 'C', '--out', str(tmp_path), '--acceleration-limits', '--controller', 'law']) == 0
    assert main(['simulate', 'C', '--out', str(tmp_path), '--controller', 'foresight']) == 0
    assert not calls[2][2]['foresight'] and calls[3][2]['foresight']


def test_replanning_needs_a_plan(tmp_path, capsys) -> None:
    assert main(['simulate', 'C', '--out', str(tmp_path), '--no-planning', '--replan-every', '1']) == 2
    assert 'replanning (replan_every_s) needs a plan' in capsys.readouterr().err


@pytest.mark.parametrize('bad', [['--n', '0'], ['--seed', '-1'], ['--replan-every', '0']])
def test_bad_numbers_are_refused_by_the_parser(tmp_path, capsys, bad: list[str]) -> None:
    with pytest.raises(SystemExit) as stop:
        main(['simulate', 'C', '--out', str(tmp_path), *bad])
    assert stop.value.code == 2 and 'error: argument' in capsys.readouterr().err


def test_a_folder_another_simulate_is_writing_is_refused(tmp_path, monkeypatch, capsys) -> None:
    """Issue 49: four concurrent runs into one folder each printed "written" while the log held one of them. A run
    holds its folder while it flies; a second is refused (exit 2) naming the holder, and the hold ends with the run."""
    import os
    import socket

    seen = []

    def simulate_scene(scene, out, **options):
        seen.append(sorted(p.name for p in out.iterdir()))
        return simulated(metrics())

    monkeypatch.setattr(pipeline, 'simulate_scene', simulate_scene)
    assert main(['simulate', 'C', '--out', str(tmp_path)]) == 0
    assert seen == [['.lock']] and not (tmp_path / '.lock').exists()  # held while flying, released after
    holder = {'pid': os.getpid(), 'host': socket.gethostname(), 'since': 'now'}  # alive: this very process
    (tmp_path / '.lock').write_text(json.dumps(holder), encoding='utf-8')
    capsys.readouterr()
    assert main(['simulate', 'C', '--out', str(tmp_path)]) == 2
    assert f'is being written by another simulate run (process {os.getpid()}' in capsys.readouterr().err
    assert len(seen) == 1


def map_run(x_m: FloatArray, y_m: FloatArray, obstacles: tuple[Any, ...] = (), testbed: str | None = None) -> View:
    """The summary of one robot flown along (x, y) (T,) every 0.02 s on a map [-5, 32] x [-10, 10] m with
    ``obstacles``, through a straight tube from x = 0, 30 m long."""
    from vtube_planning.geometry.workspace import Workspace

    positions = np.stack([x_m, y_m])[:, :, None].transpose(1, 0, 2)  # (T, 2, 1)
    result = SimpleNamespace(
        metrics=metrics(),
        planned=True,
        t_s=0.02 * np.arange(len(x_m)),
        positions_m=positions,
        l_m=positions[:, 0, :] + 0.0,
        meta={'provenance': {}},
        dynamics_violations=0,
    )
    scene = SimpleNamespace(
        name='map',
        obstacles=Obstacles(discs=obstacles),
        workspace=Workspace(-5.0, 32.0, -10.0, 10.0),
        tube=SimpleNamespace(length_m=30.0, half_width=lambda l_m: np.full(np.shape(l_m), 2.0)),
        control=SimpleNamespace(foresight_s=0.0),
        testbed=testbed,
    )
    swarm = SimpleNamespace(n_robots=1, r_p_m=0.3, r_s_m=0.4, r_a_m=0.8)
    return simulate_view(pipeline.Simulated(scene, swarm, SimConfig(), result, (Path('o/s.npz'),)))


def test_a_run_on_a_map_counts_bodies_off_the_map_over_the_whole_run() -> None:
    """Issue 49: the robots of a map scene ended 36 m beyond a 30 m map and the summary said nothing. Bodies
    outside the workspace fail the run, before the exit and beyond it (this model does not park: a robot drives on
    until the last one is through), told apart, since the fixes differ."""
    x = np.linspace(-1.0, 40.0, 625)
    y = np.zeros(625)
    y[10] = 9.9  # once 0.1 m from the map's edge: inside the tube's span
    view = map_run(x, y)
    beyond = int((x > 32.0 - 0.3).sum())
    assert view.exit_code == 1
    before, after = view.data['failures'][-2:]
    assert before.startswith('robot bodies were outside the workspace (the map) in 1 robot-steps (first at t = 0.20 s')
    assert after.startswith(
        f'robot bodies were outside the workspace (the map) in {beyond} robot-steps beyond the exit'
    )
    assert 'move goal_m or goal_region_m of [tube.generate]' in after
    line = next(line for line in view.lines if line.startswith('  map '))
    assert line.endswith(f'on obstacles 0, outside the workspace {beyond}')
    assert 'outside the workspace 1, up to their exit;' in line


def test_a_run_into_a_wall_beyond_the_goal_fails() -> None:
    """Issue 49, item 7: a map scene whose robots drive on after the exit into a wall passed (exit 0, the contacts
    "told, not failed"); every contact over the whole run fails it now, and the failure names the fix. A Robotarium
    scene's simulation is the exception: its flight parks where the simulated robots drive on."""
    x = np.linspace(-1.0, 31.0, 400)  # the robot ends 1 m past the exit, on a disc 0.5 m beyond it
    wall = (Disc((31.5, 0.0), 0.5),)
    view = map_run(x, np.zeros(400), wall)
    assert view.exit_code == 1
    (failure,) = view.data['failures']
    assert (
        failure.startswith('robot bodies were on an obstacle in ')
        and ' robot-steps beyond the exit (first at' in failure
    )
    assert 'goal_heading_deg pointing into free space with lead_m' in failure
    assert next(line for line in view.lines if line.startswith('  passage ')).startswith('  passage            FAILED')
    robotarium = map_run(x, np.zeros(400), wall, testbed='robotarium')
    assert robotarium.exit_code == 0
    assert next(line for line in robotarium.lines if line.startswith('  map ')).endswith('judges it)')
    assert map_run(np.linspace(-1.0, 29.0, 400), np.zeros(400), wall).exit_code == 0  # it stops short of the wall


@pytest.mark.parametrize(('narrowest', 'said'), [(0.6, ''), (0.398, ' (none at r_s = 0.4 m or less: no robot passes)')])
def test_a_tube_narrower_than_r_a_is_told_where(narrowest: float, said: str) -> None:
    """Issue 49: passing times of 200 s and more against a plan of 32 s, on tubes from maps. Where the half-width
    is below r_a, the law's wall barrier pushes from both walls and, saturated radially, leaves little forward
    speed (none at r_s or less): the summary says where, and what to change."""
    tube = SimpleNamespace(
        length_m=20.0, half_width=lambda l_m: np.where(np.abs(np.asarray(l_m) - 5.0) < 1.0, narrowest, 2.0)
    )
    line = next(line for line in simulate_view(simulated(metrics(), tube=tube)).lines if 'narrowest' in line)
    assert line == (
        f'  narrowest          half-width {narrowest:.3f} m at l = 4.01 m, below r_a = 0.8 m: the wall barrier pushes '
        f'from both walls there and leaves little forward speed{said}; robots crawl through, far slower than planned: '
        'widen the tube or lower r_a_m'
    )
    assert not [line for line in simulate_view(simulated(metrics())).lines if 'narrowest' in line]
