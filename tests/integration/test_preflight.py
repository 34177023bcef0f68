"""The preflight on built files that must fail it (the demo's file, which passes it, is checked in test_demo.py)."""

from __future__ import annotations

from pathlib import Path

from robotarium_exp.experiment import ExperimentConfig, flight_data
from robotarium_exp.scene import load_scene
from submission.check import check
from vtube.cli.app import main

ROOT = Path(__file__).resolve().parents[2]


STEPS_OUTSIDE = 150


def pair_scene(tmp_path: Path) -> Path:
    """robotarium_curve with 2 robots: V2's initializer places them in a few seconds."""
    text = (ROOT / 'robotarium_exp' / 'scenes' / 'robotarium_curve.toml').read_text(encoding='utf-8')
    path = tmp_path / 'pair.toml'
    path.write_text(text.replace('n_robots = 6', 'n_robots = 2'), encoding='utf-8')
    return path


def lying_file(tmp_path: Path) -> Path:
    """Two robots driven backwards out of the arena by a file that prints a clean vtube summary."""
    data = flight_data(load_scene(pair_scene(tmp_path)), None, ExperimentConfig(planning=False))
    clean = {'vtube_summary': 1, 'robots': 2, 'completed': True, 'errors': {}, 'min_center_distance_m': 0.4}
    path = tmp_path / 'lying.py'
    path.write_text(
        '\n'.join(
            [
                'import json',
                'import numpy as np',
                'import rps.robotarium as robotarium',
                f'DATA = {data.to_plain()!r}',
                "ic = np.array(DATA['initial_conditions'])",
                'headless = {"show_figure": False, "sim_in_real_time": False}',
                'r = robotarium.Robotarium(number_of_robots=2, initial_conditions=ic, **headless)',
                f'for _ in range({STEPS_OUTSIDE}):',
                '    r.get_poses()',
                '    r.set_velocities(np.arange(2), np.array([[-0.1, -0.1], [0.0, 0.0]]))',
                '    r.step()',
                f'print(json.dumps({clean!r}))',
                "r.debug() if hasattr(r, 'debug') else r.call_at_scripts_end()",
                '',
            ]
        ),
        encoding='utf-8',
    )
    return path


def test_a_file_that_leaves_the_arena_and_prints_a_clean_summary_fails(tmp_path) -> None:
    """The verdict comes from the simulator's counters and recorded poses, never from what the file prints."""
    report = check(lying_file(tmp_path), seeds=1, initializer_seeds=1)
    assert not report.passed
    bundled = report.runs[0]
    counted, recounted = bundled.counted, bundled.recounted
    assert counted is not None and counted.outside > 0 and counted == recounted  # V2's counters, recounted alike
    assert bundled.record is not None and bundled.record.experiment_steps == STEPS_OUTSIDE
    assert f'bundled seed 0: the testbed would not run it (0 pair-steps of robots too close, {counted.outside} ' in (
        '\n'.join(report.problems)
    )  # the one verdict on a run (robotarium_exp.verdict.run_failures), as robotarium run says it
    assert 'bundled seed 0: not every robot parked beyond the exit by the last step' in '\n'.join(report.problems)
    for run in report.runs:  # the PyPI simulator too, when installed: its own counters and the recount
        assert not run.ok and run.counted is not None and run.counted.outside > 0
        assert run.recounted is not None and run.recounted.outside > 0 and run.recounted.too_close == 0


def silent_files(tmp_path: Path) -> dict[str, Path]:
    """Files with flight data that never end, that end without a Robotarium, and one without flight data."""
    plain = flight_data(load_scene(pair_scene(tmp_path)), None, ExperimentConfig(planning=False)).to_plain()
    data = f'DATA = {plain!r}\n'
    files = {
        'forever': data + 'import time\nwhile True:\n    time.sleep(0.1)\n',
        'silent': data + "print('hello')\n",
        'plain': 'import time\nwhile True:\n    time.sleep(0.1)\n',
    }
    for name, text in files.items():
        (tmp_path / f'{name}.py').write_text(text, encoding='utf-8')
    return {name: tmp_path / f'{name}.py' for name in files}


def test_a_submission_that_never_ends_or_prints_nothing_is_reported_so(tmp_path, capsys) -> None:
    """Through ``vtube submission check`` (stderr not a terminal: what starts is said, no bar is drawn)."""
    files = silent_files(tmp_path)
    limits = ['--seeds', '1', '--initializer-seeds', '1', '--run-timeout', '1']
    assert main(['submission', 'check', str(files['forever']), *limits]) == 1
    forever = capsys.readouterr()
    assert 'Traceback' not in forever.err
    assert (
        f'{"bundled seed 0":<23} did not finish in 1 s' in forever.out and 'verdict                FAIL' in forever.out
    )
    assert 'seed 0 (at most 1 s)' in forever.err  # told before it waits
    assert "V2's initializer:" not in forever.err  # no bar off a terminal
    # the silent file ends at once, but a loaded machine may take more than 1 s to start Python and import numpy
    patient = [*limits[:-1], '60']
    assert main(['submission', 'check', str(files['silent']), *patient]) == 1
    assert 'made 0 Robotarium objects' in capsys.readouterr().out
    assert main(['submission', 'check', str(files['plain']), *limits]) == 2
    refused = capsys.readouterr().err
    assert refused.startswith('error: ') and 'no DATA with flight data' in refused  # before any run


TWO_ROBOTS = """
import numpy as np
import rps.robotarium as robotarium
ic = np.array([[0.3, -0.4], [0.2, -0.3], [2.5, 0.0]])
r = robotarium.Robotarium(number_of_robots=2, initial_conditions=ic, show_figure=False, sim_in_real_time=False)
for k in range(60):
    r.get_poses()
    r.set_velocities(np.arange(2), np.array([[0.05, 0.05], [0.3 * np.sin(0.1 * k)] * 2]))
    r.step()
r.debug()
"""


def test_a_run_from_a_reused_initialization_records_what_a_run_from_v2s_records(tmp_path, monkeypatch) -> None:
    """The preflight's runs take V2's initialized state from the cache (`submission.reuse.InitializedStates`):
    the record of a run without it, of the run that stores it and of the run that takes it are the same, under
    the fitted testbed model (whose draws follow the initialization's); the second stores the state, the third
    takes it, given the salt as the check gives it (a fourth, after the stored step count was raised by 1000, counts
    1000 steps more; a fifth, under another salt, does not find it)."""
    import subprocess
    import sys

    import numpy as np

    from submission.recording import read_record
    from submission.reuse import simulator_salt

    monkeypatch.setenv('VTUBE_CACHE_DIR', str(tmp_path / 'cache'))
    script = tmp_path / 'two.py'
    script.write_text(TWO_ROBOTS, encoding='utf-8')
    records = []
    for k, reuse in enumerate((False, True, True, True, True)):
        if k == 3:
            (path,) = (tmp_path / 'cache' / 'initialized').glob('*.npz')
            with np.load(path) as stored:
                state = dict(stored)
            np.savez(path, **(state | {'_iteration': state['_iteration'] + 1000}))
        command = [sys.executable, '-m', 'submission.recording', '--simulator', 'bundled', '--seed', '3']
        command += ['--testbed-model', 'fitted', '--record', str(tmp_path / f'{k}.npz')]
        command += ['--reuse-initialization'] if reuse else []
        command += {2: ['--salt', simulator_salt().hex()], 4: ['--salt', '00' * 32]}.get(k, [])
        subprocess.run([*command, str(script)], check=True, capture_output=True, text=True, cwd=tmp_path)
        records.append(read_record(tmp_path / f'{k}.npz'))
        stored = sorted((tmp_path / 'cache' / 'initialized').glob('*.npz'))
        assert len(stored) == [0, 1, 1, 1, 2][k]
    first = records[0]
    assert first.initialization_steps > 0 and first.poses.shape == (60, 3, 2)
    assert records[3].iterations == first.iterations + 1000
    for other in [*records[1:3], records[4]]:
        assert np.array_equal(other.poses, first.poses) and np.array_equal(other.commands, first.commands)
        assert (other.iterations, other.initialization_steps, other.errors) == (
            first.iterations,
            first.initialization_steps,
            first.errors,
        )
