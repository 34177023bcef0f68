"""A replay page in a headless Chromium: the slider, set from the URL's fragment through its own input handler,
draws the robots where the embedded data (and so the trajectory) has them, and the page renders offline."""

from __future__ import annotations

import html
import json
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from robotarium_exp.analysis.loaders import load_trajectory
from robotarium_exp.analysis.replay import playback_frames
from vtube.cli import main
from vtube_planning.log import LOG_FORMAT, LOG_VERSION
from vtube_planning.npzfile import write_npz

CHROMIUM = shutil.which('chromium')
pytestmark = pytest.mark.skipif(CHROMIUM is None, reason='no chromium on this machine')


@pytest.fixture(scope='module')
def page(tmp_path_factory) -> tuple[Path, Path]:
    """Four robots crossing scene A for 10 s at 50 Hz, replayed by the command: the page and the log."""
    folder = tmp_path_factory.mktemp('replay')
    t = 0.02 * np.arange(500)
    k = np.arange(4)
    x = -4.0 + 5.0 * t[:, None] + 0.9 * (k % 2)[None, :]
    y = np.broadcast_to(np.where(k < 2, -0.9, 0.9)[None, :], x.shape)
    log = folder / 'log.npz'
    meta = {'format': LOG_FORMAT, 'version': LOG_VERSION, 'kind': 'simulation', 'scene': 'A', 'planned': True}
    write_npz(log, {'t_s': t, 'positions_m': np.stack([x, y], axis=1)}, meta)
    assert main(['replay', str(log), '--out', str(folder / 'run.html')]) == 0
    return folder / 'run.html', log


def chromium(*args: str, profile: Path) -> str:
    """Chromium's output for ``args``, headless, in its own profile (tests may run side by side)."""
    assert CHROMIUM is not None
    command = [CHROMIUM, '--headless', '--no-sandbox', '--disable-gpu', f'--user-data-dir={profile}', *args]
    done = subprocess.run(command, check=False, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout


def embedded(page: Path) -> dict[str, object]:
    text = page.read_text(encoding='utf-8')
    found = re.search(r'<script id="replay-data" type="application/json">(.*?)</script>', text, re.DOTALL)
    assert found is not None
    data: dict[str, object] = json.loads(found.group(1))
    return data


def drawn(page: Path, seconds: float, profile: Path) -> dict[str, object]:
    """What the page says it drew when opened at ``#t=seconds``."""
    dom = chromium('--virtual-time-budget=5000', '--dump-dom', f'{page.as_uri()}#t={seconds}', profile=profile)
    state = re.search(r'<pre id="state">(.*?)</pre>', dom, re.DOTALL)
    assert state is not None, dom[-2000:]
    result: dict[str, object] = json.loads(html.unescape(state.group(1)))
    return result


def test_the_slider_set_from_the_fragment_draws_the_robots_of_that_frame(page, tmp_path) -> None:
    path, log = page
    data = embedded(path)
    trajectory = load_trajectory([log])
    frames = playback_frames(trajectory.t_s)
    times = np.asarray(data['t'])
    at_two, at_seven = drawn(path, 2.0, tmp_path / 'a'), drawn(path, 7.01, tmp_path / 'b')
    assert at_two['frame'] == 60 and at_seven['frame'] == int(np.flatnonzero(times <= 7.01)[-1]) == 210
    for state in (at_two, at_seven):
        k = int(state['frame'])  # type: ignore[call-overload]
        assert state['t'] == times[k] and state['xy'] == data['xy'][k]  # type: ignore[index]
        expected = np.round(1000 * trajectory.positions_m[frames[k]].T).astype(int).ravel().tolist()
        assert state['xy'] == expected
    assert at_two['xy'] != at_seven['xy']
    assert drawn(path, 0.0, tmp_path / 'c')['frame'] == 0
    assert at_two['playing'] is False


def test_the_fragment_can_start_the_playback(page, tmp_path) -> None:
    path, _ = page
    dom = chromium('--virtual-time-budget=2000', '--dump-dom', f'{path.as_uri()}#t=2&play', profile=tmp_path / 'p')
    state = re.search(r'<pre id="state">(.*?)</pre>', dom, re.DOTALL)
    assert state is not None
    played = json.loads(html.unescape(state.group(1)))
    assert played['playing'] is True and played['frame'] >= 60  # how far it got depends on the machine's clock
    assert 'pause' in dom


def test_the_page_renders_offline(page, tmp_path) -> None:
    from matplotlib.image import imread

    path, _ = page
    shot = tmp_path / 'replay.png'
    chromium(
        '--hide-scrollbars',
        f'--screenshot={shot}',
        '--window-size=1200,800',
        f'{path.as_uri()}#t=5',
        profile=tmp_path / 'p',
    )
    pixels = imread(shot)
    assert pixels.shape[:2] == (800, 1200)
    colours = np.unique(np.round(pixels[..., :3] * 255).astype(int).reshape(-1, 3), axis=0)
    assert len(colours) > 50  # the tube, four robots in their colours, the panels' lines: not a blank page
    assert 'http' not in re.sub(r'https?://www\.w3\.org\S*', '', path.read_text(encoding='utf-8'))  # nothing fetched
