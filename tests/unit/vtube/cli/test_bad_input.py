"""Bad input to ``vtube.cli.main`` (in this process; the console script's own process is tested once, in
``tests/integration/test_cli.py``): exit code, one `error:` line, no traceback, nothing lost.

Every case is one row of BAD: the command line (``{tmp}`` is a folder of prepared bad files), the exit code, and a
phrase the message must contain. Each runs with a pre-existing output folder holding a file whose bytes must
survive the failure.
"""

from __future__ import annotations

import csv
import functools
import json
import sys
from pathlib import Path

import numpy as np
import pytest

from robotarium_exp import rps_alias
from robotarium_exp.scene import load_scene
from vtube.cli.app import main
from vtube_planning.npzfile import META_KEY, read_npz, write_npz
from vtube_planning.planning.planner import plan_convex
from vtube_planning.studies.campaign import Campaign, run_key
from vtube_planning.swarm.simulate import SimConfig, simulate

PRECIOUS = b'an earlier result that a failed command must not touch'

BAD = [
    ('negative seed', 'simulate A --out {out} --seed -1', 2, "argument --seed: '-1' is not a whole number >= 0"),
    (
        'seed over 32 bits',
        'robotarium run robotarium_trapezoid --out {out} --seed 4294967296',
        2,
        "'4294967296' is not a seed from 0 to 4294967295",
    ),
    ('no seeds', 'study --out {out} --seeds 0', 2, "argument --seeds: '0' runs no seed: a bare number is a count"),
    (
        'seeds backwards',
        'robotarium compare robotarium_curve --out {out} --seeds 19-10',
        2,
        "argument --seeds: the range '19-10' runs backwards; write it first to last, like 10-19",
    ),
    ('seed twice', 'ablation --out {out} --seeds 0-4,3', 2, "argument --seeds: seed 3 is given twice in '0-4,3'"),
    ('no robots', 'simulate A --out {out} --n 0', 2, "argument --n: '0' is not a whole number >= 1"),
    ('grid too fine', 'plan A --out {out} --grid-step 1e-6', 2, 'use a grid step of at least 0.003 m'),
    ('negative grid step', 'plan A --out {out} --grid-step -1', 2, "argument --grid-step: '-1' is not a number > 0"),
    (
        'unknown objective',
        'plan A --out {out} --objective fastest',
        2,
        "argument --objective: invalid choice: 'fastest'",
    ),
    (
        'scene objective unknown',
        'plan {tmp}/objective.toml --out {out}',
        2,
        "planning option objective must be one of ('centre', 'last_out'); got 'fastest'",
    ),
    (
        'polynomial, last out',
        'plan A --out {out} --method polynomial --objective last_out',
        2,
        "the polynomial method plans for the centre's time only",
    ),
    ('figure kind', 'scene show A --out {tmp}/scene.foo', 2, 'give a file ending in one of .avif'),
    ('unknown scene', 'simulate Z --out {out}', 2, "unknown scene 'Z'"),
    ('folder as scene', 'scene show {tmp}', 2, 'is a folder, not a scene file'),
    ('scene not UTF-8', 'scene show {tmp}/latin1.toml', 2, 'is not UTF-8 text'),
    ('text waypoint', 'scene show {tmp}/text_waypoint.toml', 2, "must be numbers of metres within +-1e+06; [1.0, 'a']"),
    (
        'endless tube',
        'simulate {tmp}/endless.toml --out {out}',
        2,
        'length_m in [tube.center.pieces[0]] must be at most',
    ),
    ('binary submission', 'submission check {tmp}/binary.py', 2, 'is not a Python source file'),
    ('check without runs', 'submission check {tmp}/binary.py --seeds 0', 2, "'0' runs no seed: a bare number is a"),
    ('npz not a plan', 'simulate A --out {out} --plan {tmp}/notaplan.npz', 2, 'without vtube metadata, not a plan'),
    ('damaged plan', 'simulate A --out {out} --plan {tmp}/damaged.npz', 2, 'is not an .npz archive, or it is damaged'),
    ('npy as plan', 'simulate A --out {out} --plan {tmp}/bare.npy', 2, 'holds one bare array (.npy), not a plan'),
    ('plan missing a field', 'simulate A --out {out} --plan {tmp}/cut_plan.npz', 2, "missing ['speed_mps']"),
    ('plan of another scene', 'simulate B --out {out} --plan {tmp}/plan_A.npz', 2, "made for scene 'A'"),
    (
        'plan with a zero speed',
        'simulate A --out {out} --plan {tmp}/zero_speed.npz',
        2,
        'a speed or a density is not > 0',
    ),
    ('pickled poses', 'analyze {tmp}/pickled --out {out}', 2, 'holds pickled objects, which are never loaded'),
    ('clock jumps back', 'analyze {tmp}/clock_back --out {out}', 2, 'time stamps go back by up to 0.967 s'),
    ('stamps in milliseconds', 'analyze {tmp}/milliseconds --out {out}', 2, 'in another unit than seconds'),
    ('edited campaign table', 'campaign report {tmp}/edited', 2, "seed = 'abc' is not a whole number"),
    ('campaign record a list', 'campaign report {tmp}/listed', 2, 'holds a JSON list, not the object vtube wrote'),
    ('campaign record cut', 'campaign report {tmp}/cut_record', 2, 'is not the JSON vtube wrote there'),
    ('plan metadata a list', 'simulate A --out {out} --plan {tmp}/listed_plan.npz', 2, 'metadata is a JSON list'),
    ('log metadata a list', 'analyze {tmp}/listed_log.npz --out {out}', 2, 'its metadata is a JSON list, not an'),
    ('returned meta a list', 'analyze {tmp}/listed_meta --out {out}', 2, 'holds a JSON list, not the object a sub'),
    ('log of another scene', 'analyze {tmp}/log_A.npz --scene B --out {out}', 2, "recorded in scene 'A', whose tube"),
    ('poses of a wrong shape', 'analyze {tmp}/shapes --out {out}', 2, 'vtube_poses.npy the poses (T, 3, N)'),
    ('log of wrong shapes', 'analyze {tmp}/bad_log.npz --out {out}', 2, 'positions_m (T, 2, N); got (3,) and (4, 3)'),
    ('unknown scene among many', 'study --out {out} --scenes A,Z --seeds 1', 2, "unknown scene 'Z'"),
    ('poses all NaN', 'analyze {tmp}/nan_poses --out {out}', 2, 'has a finite position'),
    ('folder as submission', 'submission check {tmp}', 2, 'is a folder; give the submission .py file'),
    (
        'delay margin on too few seeds',
        'submission check {tmp}/binary.py --margin-seeds 5',
        2,
        "'5' gives 5 seeds; a delay margin rests on at least 10",
    ),
    ('random bytes bag', 'analyze {tmp}/random.bag --out {out}', 2, 'as a ROS bag'),
    ('bad regex', 'analyze {tmp}/shapes --out {out} --topic-pattern (', 2, "'(' is not a regular expression"),
    ('negative radius', 'analyze {tmp}/shapes --out {out} --collision-distance -1', 2, "'-1' is not a number > 0"),
    ('output under a file', 'plan A --out {tmp}/binary.py/plan', 2, 'choose another --out before any run starts'),
    ('scene off the arena', 'robotarium run A --out {out}', 2, 'does not fit the Robotarium'),
    (
        'unknown testbed model',
        'robotarium run robotarium_curve --out {out} --testbed-model fitted:0',
        2,
        "testbed model 'fitted:0': the scale '0' is not a number > 0",
    ),
    (
        'testbed models without ideal first',
        'submission check {tmp}/binary.py --testbed-models fitted,ideal',
        2,
        'the first testbed model must be ideal',
    ),
    ('compare, testbed model', 'robotarium compare robotarium_curve --out {out} --testbed-model real', 2, "'real'"),
    ('missing campaign', 'campaign run {tmp}/none.toml --out {out}', 2, 'does not exist; give the path to a .toml'),
    ('negative workers', 'campaign run {tmp}/none.toml --workers -1', 2, "'-1' is not a whole number >= 0"),
    ('held out, no seeds', 'ablation --out {out} --held-out', 2, 'held_out = true needs seeds to hold out'),
    ('compare, held out', 'robotarium compare robotarium_curve --out {out} --held-out', 2, '--held-out needs seeds'),
    (
        'family, unknown comparison',
        'campaign run {tmp}/bad_family.toml --out {out}',
        2,
        "families.fast: 'planning - nothing' is not a comparison",
    ),
    (
        'family, not a list',
        'campaign run {tmp}/flat_family.toml --out {out}',
        2,
        'families.fast.metrics must be a list',
    ),
    ('alias without a script', 'rps_alias --seed 1', 2, 'give the script to run'),
    ('alias, missing script', 'rps_alias {tmp}/none.py', 2, 'none.py: no such script'),
    (
        'alias, bad seed',
        'rps_alias --seed x {tmp}/binary.py',
        2,
        "argument --seed: 'x' is not a seed from 0 to 2**32 - 1",
    ),
    ('alias, seed over 32 bits', 'rps_alias --seed 4294967296 {tmp}/binary.py', 2, "'4294967296' is not a seed from 0"),
    ('alias, binary script', 'rps_alias {tmp}/binary.py', 2, 'binary.py is not a Python script'),
    ('replay, no scene', 'replay {tmp}/no_scene --out {out}/run.html', 2, 'records no scene, and the replay draws'),
    ('replay, another scene', 'replay {tmp}/log_A.npz --scene B --out {out}/r.html', 2, "recorded in scene 'A', whose"),
    ('replay, not a page', 'replay {tmp}/log_A.npz --out {out}/run.png', 2, 'run.png is not an .html file; give --out'),
    (
        'image smaller than the map',
        'tube generate {tmp}/tiny_pixels.toml --out {out}/s.toml',
        2,
        'the occupancy images cover 0.0 % of [workspace]',
    ),
    (
        'search grid too large',
        'tube generate {tmp}/huge_pixels.toml --out {out}/s.toml',
        2,
        'give [tube.generate] resolution_m = 22.4 or more, or a smaller [workspace]',
    ),
    (
        'comparison of another scene',
        'analyze {tmp}/no_scene --scene B --compare {tmp}/log_A.npz --out {out}',
        2,
        "the log was recorded in scene 'A', whose tube is not the tube of scene 'B'",
    ),
    ('a hundred million robots', 'simulate A --out {out} --n 100000000', 2, 'flies at most 5000 robots; give --n'),
    (
        'bend too tight to plan',
        'plan {tmp}/hairpin.toml --out {out}',
        2,
        (
            'the bend at l = 20.000..21.571 m (centre radius 1 m, turning 90 deg) lets no robot through that turns no '
            'tighter than v_min^2 / a_n = 4 m: the widest curve between its walls has radius 2.166 m; widen the tube'
        ),
    ),
    (
        'bend too tight to fly under the limits',
        'simulate {tmp}/hairpin.toml --out {out} --acceleration-limits --no-planning',
        2,
        'make the centre radius at least 2.834 m',
    ),
    ('robotarium swarm too large', 'simulate robotarium_curve --out {out} --n 1000', 2, 'which flies 1 to 20 robots'),
    (
        'build into a folder',
        'submission build robotarium_curve --out {out}',
        2,
        'is a folder; give the .py file to write',
    ),
    ('tube narrower than a robot', 'plan {tmp}/thin.toml --out {out}', 2, 'no wider than a robot (2 r_p = 0.6 m)'),
    ('campaign step too coarse', 'campaign run {tmp}/coarse.toml --out {out}', 2, 'dt_s must be a number in [0.001'),
    ('campaign step too fine', 'campaign run {tmp}/fine.toml --out {out}', 2, 'dt_s must be a number in [0.001, 0.1]'),
    (
        'campaign tube widened',
        'campaign run {tmp}/wide.toml --out {out}',
        2,
        'narrowest_m = 5 needs a tube that narrows',
    ),
    (
        'a NaN stamp',
        'analyze {tmp}/nan_stamp --out {out}',
        2,
        'vtube_t.npy hold 1 value(s) that are not a time (the first, nan, at row 7)',
    ),
    ('start off the map', 'simulate {tmp}/A_tight_map.toml --out {out}', 2, 'the start puts 20 robot bodies outside'),
    (
        'heading against the route',
        'tube generate {tmp}/headed.toml --out {out}/s.toml',
        2,
        'no lead from 2 to 12 m holds the heading given (lead_m was not given, so the generator tried 5)',
    ),
    ('empty scene name', 'study --out {out} --scenes , --seeds 1', 2, "argument --scenes: ',' holds an empty name"),
    ('no poses returned', 'analyze {tmp}/only_times --out {out}', 2, '(it holds no vtube_poses.npy; read: '),
    ('start is the goal', 'tube generate {tmp}/start_is_goal.toml --out {out}/s.toml', 2, 'start_m and goal_m are'),
    (
        'no room to start on the map',
        'tube generate {tmp}/edge_start.toml --out {out}/s.toml',
        2,
        'outside the workspace (the map), the first at (-0.40, 49.20); the 20 robots start in a formation 11.2 m deep',
    ),
    (
        'no room to run out beyond the goal',
        'tube generate {tmp}/edge_goal.toml --out {out}/s.toml',
        2,
        (
            'robot bodies outside the workspace (the map), the first at (99.72, 47.30); the robots drive on beyond the '
            "goal until the last one is through, at least 11.2 m (the depth of the 20 robots' start formation) along "
            "the tube's last heading (0 degrees): in "
        ),
    ),
]


def map_text(image_m: float, side_m: float, start: str = '[10.0, 50.0]', goal: str = '[90.0, 50.0]') -> str:
    """A map file of a square workspace ``side_m`` on a side holding ``grid.npy`` at ``image_m`` per pixel."""
    return (
        f'[tube.generate]\nstart_m = {start}\ngoal_m = {goal}\nhalf_width_min_m = 1.0\nhalf_width_max_m = 3.0\n'
        f'[workspace]\nx_min_m = 0.0\nx_max_m = {side_m}\ny_min_m = 0.0\ny_max_m = {side_m}\nmargin_m = 0.2\n'
        f'[obstacles]\nimages = [{{ file = "grid.npy", resolution_m = {image_m}, origin_m = [0.0, 0.0] }}]\n'
    )


@pytest.fixture(scope='module')
def bad_files(tmp_path_factory) -> Path:
    tmp = tmp_path_factory.mktemp('bad')
    (tmp / 'latin1.toml').write_bytes(b'[tube.center]\npieces = [{ kind = "line", length_m = 10.0 }]\n# caf\xe9\n')
    width = '[tube.width]\nstart_m = 2.0\nparts = [{ kind = "constant" }]\n'
    (tmp / 'text_waypoint.toml').write_text('[tube.center]\nwaypoints = [[0.0, 0.0], [1.0, "a"], [2.0, 0.0]]\n' + width)
    (tmp / 'endless.toml').write_text('[tube.center]\npieces = [{ kind = "line", length_m = 1e300 }]\n' + width)
    line = '[tube.center]\npieces = [{ kind = "line", length_m = 10.0 }]\n'
    (tmp / 'objective.toml').write_text(line + width + '[planning]\nobjective = "fastest"\n')
    hairpin = '{ kind = "line", length_m = 20.0 }, { kind = "arc", radius_m = 1.0, angle_deg = 90.0 }'
    narrow = '[tube.width]\nstart_m = 0.5\nparts = [{ kind = "constant" }]\n'
    (tmp / 'hairpin.toml').write_text(f'[tube.center]\npieces = [{hairpin}, {hairpin[:34]}]\n' + narrow)
    rng = np.random.default_rng(0)
    (tmp / 'random.bag').write_bytes(rng.bytes(2000))
    (tmp / 'binary.py').write_bytes(rng.bytes(500))
    np.save(tmp / 'bare.npy', np.zeros((3, 3)))
    np.savez(tmp / 'notaplan.npz', a=np.zeros(3))
    (tmp / 'damaged.npz').write_bytes(b'PK\x03\x04 not a zip archive after all')
    scene = load_scene('A')
    plan = plan_convex(scene.tube, scene.swarm, scene.planning, scene='A')
    plan.save(tmp / 'plan_A.npz')
    arrays = dict(np.load(tmp / 'plan_A.npz'))
    np.savez(tmp / 'cut_plan.npz', **{k: v for k, v in arrays.items() if k != 'speed_mps'})
    short = SimConfig(time_limit_s=1.0)
    log = tmp / 'log_A.npz'
    simulate(scene.tube, scene.swarm, scene.control, plan=plan, config=short, log_path=log, meta={'scene': 'A'})
    log_meta = {'format': 'vtube-trajectory', 'version': 2, 'kind': 'test'}
    write_npz(tmp / 'bad_log.npz', {'t_s': np.arange(3.0), 'positions_m': np.zeros((4, 3))}, log_meta)
    (tmp / 'nan_poses').mkdir()
    np.save(tmp / 'nan_poses' / 'vtube_t.npy', 0.033 * np.arange(5))
    np.save(tmp / 'nan_poses' / 'vtube_poses.npy', np.full((5, 3, 2), np.nan))
    stored, recorded = read_npz(tmp / 'plan_A.npz', ValueError, 'plan')
    write_npz(
        tmp / 'zero_speed.npz',
        stored | {'speed_mps': np.where(np.arange(stored['l_m'].size) == 3, 0.0, stored['speed_mps'])},
        recorded,
    )
    returned = {'pickled': (0.033 * np.arange(50), np.array([{'x': 1}], dtype=object))}
    returned['clock_back'] = (np.r_[0.033 * np.arange(25), 0.033 * np.arange(25) - 0.175], np.zeros((50, 3, 2)))
    returned['milliseconds'] = (33.0 * np.arange(50), np.zeros((50, 3, 2)))
    returned['no_scene'] = (0.033 * np.arange(50), np.zeros((50, 3, 2)))
    returned['nan_stamp'] = (np.where(np.arange(50) == 7, np.nan, 0.033 * np.arange(50)), np.zeros((50, 3, 2)))
    for name, (t_s, poses) in returned.items():
        (tmp / name).mkdir()
        np.save(tmp / name / 'vtube_t.npy', t_s)
        np.save(tmp / name / 'vtube_poses.npy', poses)  # np.save pickles object arrays by default
    (tmp / 'edited').mkdir()
    campaign = '{"name": "c", "grids": [{"scene": ["C"]}], "metrics": ["passing_time_s"], "settings": {}}'
    (tmp / 'edited' / 'campaign.json').write_text(campaign)
    edited = Campaign.from_dict(json.loads(campaign))
    row = dict.fromkeys(edited.columns, '') | {'key': run_key(edited.points()[0], edited.settings), 'version': '1'}
    with (tmp / 'edited' / 'runs.csv').open('w', newline='') as handle:
        writer = csv.DictWriter(handle, fieldnames=edited.columns)
        writer.writeheader()
        writer.writerow(row | {'scene': 'C', 'mode': 'planning', 'seed': 'abc'})  # a seed typed over by hand
    (tmp / 'listed').mkdir()
    (tmp / 'listed' / 'campaign.json').write_text(f'[{campaign}]')
    (tmp / 'listed' / 'runs.csv').write_text('key\n')
    axes = 'name = "f"\n[axes]\nscene = ["C"]\nmode = ["planning"]\nseed = 2\n'
    (tmp / 'bad_family.toml').write_text(axes + '[families.fast]\ncomparisons = ["planning - nothing"]\n')
    (tmp / 'flat_family.toml').write_text(axes + '[families.fast]\nmetrics = "passing_time_s"\n')
    (tmp / 'cut_record').mkdir()
    (tmp / 'cut_record' / 'campaign.json').write_text(campaign[:20])
    (tmp / 'cut_record' / 'runs.csv').write_text('key\n')
    for name, source in (('listed_plan.npz', tmp / 'plan_A.npz'), ('listed_log.npz', log)):
        stored, recorded = read_npz(source, ValueError, 'file')
        np.savez(tmp / name, **stored, **{META_KEY: np.array(json.dumps([recorded]))})
    (tmp / 'listed_meta').mkdir()
    np.save(tmp / 'listed_meta' / 'vtube_t_s.npy', np.arange(3.0))
    (tmp / 'listed_meta' / 'vtube_meta.json').write_text('[]')
    np.save(tmp / 'grid.npy', np.zeros((100, 100), dtype=bool))  # 100 x 100 free cells
    (tmp / 'tiny_pixels.toml').write_text(map_text(1e-7, 100.0))  # issue 49: every obstacle ignored, exit 0
    (tmp / 'huge_pixels.toml').write_text(map_text(1000.0, 1e5, '[1e4, 5e4]', '[9e4, 5e4]'))  # was a 429 TiB grid
    headed = map_text(1.0, 100.0).replace('half_width_min_m', 'start_heading_deg = 180.0\nhalf_width_min_m')
    (tmp / 'headed.toml').write_text(headed)  # issue 49: a "radius 0.000 m" refusal; now each lead tried (U-turns)
    # issue 49: the grid started off the map; here 7 rows of 3 robots 1.6 m apart, the last at x = 10 - 0.8 - 6 x 1.6
    (tmp / 'edge_start.toml').write_text(map_text(1.0, 100.0))
    # issue 49: the robots drive on beyond the goal (here 5 m from the edge) until the last one is through
    (tmp / 'edge_goal.toml').write_text(map_text(1.0, 100.0, '[30.0, 50.0]', '[95.0, 50.0]'))
    (tmp / 'start_is_goal.toml').write_text(map_text(1.0, 100.0, goal='[10.0, 50.0]'))  # was an IndexError
    thin = '[tube.width]\nstart_m = 3.0\nparts = [{ kind = "constant", length_m = 10.0 }, { kind = "smooth", '
    thin += 'length_m = 5.0, to_m = 0.2 }, { kind = "constant" }]\n'  # issue 49: planned "certified"
    (tmp / 'thin.toml').write_text('[tube.center]\npieces = [{ kind = "line", length_m = 30.0 }]\n' + thin)
    for name, dt_s in (('coarse', 5.0), ('fine', 1e-7)):  # issue 49: "0 of 1 completed" at exit 0; "no finished run"
        (tmp / f'{name}.toml').write_text(
            f'name = "{name}"\n[axes]\nscene = ["C"]\nseed = 1\n[settings]\ndt_s = {dt_s}\n'
        )
    (tmp / 'wide.toml').write_text('name = "wide"\n[axes]\nscene = ["C"]\nnarrowest_m = [5.0]\nseed = 1\n')
    edges = np.concatenate(scene.tube.boundaries(np.linspace(0.0, scene.tube.length_m, 400)))
    (low_x, low_y), (high_x, high_y) = edges.min(axis=0) - 0.5, edges.max(axis=0) + 0.5  # the tube's box, no more
    tight = f'[workspace]\nx_min_m = {low_x}\nx_max_m = {high_x}\ny_min_m = {low_y}\ny_max_m = {high_y}\n'
    shipped = Path(__file__).resolve().parents[4] / 'vtube_planning' / 'scenes' / 'A.toml'
    (tmp / 'A_tight_map.toml').write_text(shipped.read_text(encoding='utf-8') + tight)  # issue 49: flew off the map
    (tmp / 'only_times').mkdir()  # issue 49: "truncated or corrupt: []"
    np.save(tmp / 'only_times' / 'vtube_t.npy', np.arange(3.0))
    (tmp / 'shapes').mkdir()
    np.save(tmp / 'shapes' / 'vtube_t.npy', np.zeros(5))
    np.save(tmp / 'shapes' / 'vtube_poses.npy', np.zeros((5, 7)))
    return tmp


def vtube(args: list[str], monkeypatch) -> int:
    """``vtube ARGS`` in this process (``python -m robotarium_exp.rps_alias ARGS`` when the first word is
    ``rps_alias``): its exit code, argparse's ``SystemExit`` included."""
    if args[0] == 'rps_alias':
        monkeypatch.setattr(sys, 'argv', ['rps_alias', *args[1:]])
        call = rps_alias.main
    else:
        call = functools.partial(main, args)
    try:
        code = call()
    except SystemExit as stop:
        code = stop.code
    return code


@pytest.mark.parametrize(('case', 'command', 'code', 'phrase'), BAD, ids=[row[0] for row in BAD])
def test_bad_input_gets_one_error_line_and_loses_nothing(
    bad_files, tmp_path, capsys, monkeypatch, case, command, code, phrase
) -> None:
    out = tmp_path / 'out'
    out.mkdir()
    (out / 'earlier.npz').write_bytes(PRECIOUS)
    args = [part.format(tmp=bad_files, out=out) for part in command.split()]
    assert vtube(args, monkeypatch) == code
    stderr = capsys.readouterr().err
    errors = [line for line in stderr.splitlines() if 'error:' in line]
    assert len(errors) == 1 and phrase in errors[0], stderr
    assert 'Traceback' not in stderr
    assert [p.name for p in out.iterdir()] == ['earlier.npz'] and (out / 'earlier.npz').read_bytes() == PRECIOUS


@pytest.mark.parametrize(
    'command',
    ['simulate A --out {out} --n -3', 'robotarium run', 'robotarium', '--bogus', 'plan A --out {out} --method x'],
)
def test_a_bad_command_line_is_one_error_line(tmp_path, capsys, monkeypatch, command: str) -> None:
    """Issue 49: argparse printed its usage block, five lines, above the error; one `error:` line, as everywhere."""
    args = [part.format(out=tmp_path / 'out') for part in command.split()]
    assert vtube(args, monkeypatch) == 2
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 1 and ': error: ' in lines[0] and lines[0].endswith(' --help)'), lines
