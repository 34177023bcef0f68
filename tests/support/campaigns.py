"""Small campaign files for the campaign tests, and the metrics of a fake run."""

from __future__ import annotations

from pathlib import Path

from vtube_planning.studies.campaign import METRICS
from vtube_planning.studies.study import Point

SMALL = """
[axes]
scene = ["C"]
mode = ["planning", "no planning"]
seed = [0, 1]
latency_steps = [0, 2]
"""


def write(folder: Path, text: str, name: str = 'campaign.toml') -> Path:
    """``text`` written as ``folder/name``."""
    path = folder / name
    path.write_text(text, encoding='utf-8')
    return path


def fake_metrics(point: Point) -> dict[str, object]:
    """What the fake run measures: values that name the run, so that a row shows which run wrote it."""
    values = dict.fromkeys(METRICS, 0.5) | {'collision_pairs': point.seed, 'tube_violation_steps': 0}
    return values | {'completed': True, 'passing_time_s': 10.0 + point.seed + point.latency_steps}
