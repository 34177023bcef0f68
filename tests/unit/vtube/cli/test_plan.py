"""``vtube plan``: the plan file, its figure and its summary; uncertified and infeasible plans."""

from __future__ import annotations

import json
from pathlib import Path

from robotarium_exp.scene import load_scene
from tests.support.scenes import LINE_SCENE
from vtube.cli.app import main
from vtube.cli.plan import plan_view
from vtube.pipeline import Planned
from vtube_planning.planning.plan import Plan, make_plan
from vtube_planning.planning.planner import plan_convex


def test_plan_writes_plan_file_and_figure(tmp_path, capsys) -> None:
    assert main(['plan', 'C', '--out', str(tmp_path), '--grid-step', '0.5']) == 0
    text = capsys.readouterr().out
    assert 'certificate           certified' in text and 'min 0.1' in text
    plan = Plan.load(tmp_path / 'plan_C.npz', load_scene('C').tube)
    assert plan.scene == 'C' and plan.options.grid_step_m == 0.5 and plan.l_m.size == 121
    assert (tmp_path / 'plan_C.png').read_bytes()[:4] == b'\x89PNG'


def test_the_plan_view_reads_the_plan(tmp_path) -> None:
    scene = load_scene('robotarium_trapezoid')
    plan = plan_convex(scene.tube, scene.swarm, scene.planning, scene=scene.name)
    files = (Path('p.npz'), Path('p.png'), Path('s.toml'))
    view = plan_view(Planned(scene, plan, 'convex', *files))
    k = int(plan.density_per_m2.argmin())
    assert view.lines[0].startswith(f'plan for scene robotarium_trapezoid (convex, {plan.l_m.size} grid points, ')
    assert f'  traversal time        {plan.time_s:.4f} s' in view.lines
    assert f'  density               min {plan.density_per_m2[k]:.4g} at l = {plan.l_m[k]:.3f} m, ' in view.lines[4]
    assert view.lines[5].startswith('  certificate           certified: ') and view.lines[-1].endswith('p.png, s.toml')
    assert json.loads(json.dumps(view.data)) == {
        'plan_file': 'p.npz',
        'time_s': plan.time_s,
        'objective': plan.objective,
        'certificate': plan.certificate,
        'certified': True,
        'provenance': plan.provenance,
    }


def test_plan_reports_uncertified_polynomial_plans_and_fails(tmp_path, capsys) -> None:
    assert main(['plan', 'A', '--out', str(tmp_path), '--method', 'polynomial']) == 1
    out = capsys.readouterr().out
    assert 'NOT certified' in out and '\n  fails                 (p3) the speed change a_v is exceeded by ' in out
    assert (tmp_path / 'plan_A.npz').exists()  # the plan is still written, to be inspected


def test_the_view_of_an_uncertified_plan_fails_with_its_reasons() -> None:
    scene = load_scene('robotarium_trapezoid')
    plan = plan_convex(scene.tube, scene.swarm, scene.planning, scene=scene.name)
    density = plan.density_per_m2.copy()
    density[0] *= 1.25
    args = (scene.tube, scene.swarm, scene.planning, plan.l_m, plan.speed_mps, density)
    broken = make_plan(*args, solved=plan.solved, scene=scene.name)
    view = plan_view(Planned(scene, broken, 'convex', Path('p.npz'), Path('p.png'), Path('s.toml')))
    assert view.exit_code == 1 and view.data['certified'] is False
    assert view.data['failures'] == list(broken.failures(scene.tube))
    assert view.lines[6] == '  fails                 ' + '; '.join(broken.failures(scene.tube))
    assert 'the initial speed and density miss the boundary values by 2.5e-01 (relative)' in view.lines[6]


def test_infeasible_plan_gives_exit_2_naming_constraint_and_arc_length(tmp_path, capsys) -> None:
    path = tmp_path / 'tight.toml'
    path.write_text(
        LINE_SCENE.replace(
            '{ kind = "line", length_m = 10.0 }',
            '{ kind = "line", length_m = 5.0 }, { kind = "arc", radius_m = 3.0, angle_deg = 60.0 }',
        )
    )
    assert main(['plan', str(path), '--out', str(tmp_path)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith('error: (p4) is incompatible with (p2) at l = 4.')
    assert not (tmp_path / 'plan_tight.npz').exists()
    assert main(['plan', 'Z', '--out', str(tmp_path / 'p'), '--json']) == 2  # an error: nothing on stdout
    assert capsys.readouterr().out == ''


def test_plan_for_the_last_robot_out_from_the_command_line(tmp_path, capsys) -> None:
    assert main(['plan', 'C', '--out', str(tmp_path), '--objective', 'last_out']) == 0
    lines = capsys.readouterr().out.splitlines()
    plan = Plan.load(tmp_path / 'plan_C.npz', load_scene('C').tube)
    assert plan.options.objective == 'last_out'
    terms = plan.objective
    passing = terms['time_s'] + terms['entry_s'] + terms['exit_s']
    assert f'  passing time (model)  {passing:.4f} s  (first robot in to last robot out)' in lines
    assert terms['total'] == sum(terms[name] for name in ('time_s', 'entry_s', 'exit_s', 'density'))
    assert f'exit half-extent {terms["exit_s"]:.6f} + density' in next(line for line in lines if 'objective J' in line)


def test_a_scene_files_planning_table_chooses_the_objective(tmp_path, capsys) -> None:
    path = tmp_path / 'line.toml'
    path.write_text(LINE_SCENE + '[planning]\nobjective = "last_out"\n')
    assert main(['plan', str(path), '--out', str(tmp_path)]) == 0
    assert 'passing time (model)' in capsys.readouterr().out
    assert Plan.load(tmp_path / 'plan_line.npz', load_scene(str(path)).tube).options.objective == 'last_out'
    assert main(['plan', str(path), '--out', str(tmp_path), '--objective', 'centre']) == 0  # the option overrides
    assert 'passing time (model)' not in capsys.readouterr().out


def test_the_command_offers_the_planner_s_objectives() -> None:
    from vtube.cli import plan as plan_command
    from vtube_planning.params import OBJECTIVES

    assert plan_command.OBJECTIVES == OBJECTIVES
