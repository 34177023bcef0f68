"""The proof that N robots do not start in a tube's start region (`robotarium_exp.packing_proof` and its kernel):
windows decided against analytic spans on a strip and on a bend and against the packing search on random bends,
the pruning and shaving against true layouts, and the frontier search on a region that holds three robots where
Oler's bound allows five."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from robotarium_exp import fit
from robotarium_exp.fit import robotarium_fit
from robotarium_exp.packing import _search, packed_in_window, packing_bound, start_region
from robotarium_exp.packing_kernel import _judged
from robotarium_exp.packing_proof import proof_region, refuted
from robotarium_exp.scene import load_scene
from robotarium_exp.spec import ROBOTARIUM
from vtube_planning.geometry.centerline import ArcPath, ArcPiece
from vtube_planning.geometry.tube import VirtualTube
from vtube_planning.geometry.width import WidthPart, WidthProfile

SPACING = ROBOTARIUM.ic_spacing_m


def tube_of(pieces: tuple[ArcPiece, ...], half_width_m: float, start: tuple[float, float]) -> VirtualTube:
    center = ArcPath(pieces, start, 0.0)
    return VirtualTube(center, WidthProfile(half_width_m, (WidthPart('constant', center.length_m),)))


def proved_out(t: VirtualTube, k: int, first_m: float, length_m: float) -> bool:
    return refuted(t, k, (first_m, first_m + length_m))


@pytest.mark.parametrize(('half_width', 'k'), [(0.45, 3), (0.29, 2)])
def test_a_strip_holds_k_robots_from_the_analytic_span(half_width: float, k: int) -> None:
    """Across a straight strip of room w (half-width less 0.1 m) at most k - 1 robots stand side by side; k need a
    span sqrt(d^2 - (w / (k - 1))^2) along it, by pigeonhole on the offsets (w = 0.7 m: 3 robots, 0.19365 m;
    w = 0.38 m: 2 robots, 0.12490 m). The proof says no layout 4 mm short of it, and not 4 mm beyond (where one is)."""
    t = tube_of((ArcPiece(2.0),), half_width, (-1.2, 0.0))
    room = 2.0 * (half_width - 0.1)
    span = math.sqrt(SPACING**2 - (room / (k - 1)) ** 2)
    assert not proved_out(t, k - 1, 0.5, 0.0)
    assert proved_out(t, k, 0.5, span - 0.004)
    assert not proved_out(t, k, 0.5, span + 0.004)


def test_on_a_bend_the_outer_edge_holds_more() -> None:
    """A 60 degree left bend of radius 1 m, room 0.1 m across (half-width 0.15 m): |p - q|^2 is convex in the two
    radii, so two robots an angle apart are farthest on the outer edge (r = 1.05 m), and three need the angle
    2 x 2 asin(d / 2.1) = 0.7664 rad, 0.7664 m of centre line: none 8 mm short, and not 8 mm beyond. A proof that
    took the centre line's length for the outer edge's (no stretch), or turned kappa's sign, would prove that
    out too."""
    t = tube_of((ArcPiece(1.0, 1.0, True),), 0.15, (-1.0, -0.5))
    need = 2.0 * 2.0 * math.asin(SPACING / 2.1)
    assert proved_out(t, 3, 0.1, need - 0.008)
    assert not proved_out(t, 3, 0.1, need + 0.008)


def random_bend(rng: np.random.Generator) -> VirtualTube:
    radius = float(rng.uniform(0.6, 1.5))
    pieces = (
        ArcPiece(float(rng.uniform(0.2, 0.6))),
        ArcPiece(float(rng.uniform(0.3, 0.9)), radius, bool(rng.random() < 0.5)),
    )
    return tube_of(pieces, float(rng.uniform(0.25, 0.5)), (-1.2, float(rng.uniform(-0.2, 0.2))))


def test_a_window_proved_empty_is_one_the_search_cannot_fill() -> None:
    """Random bends and windows: where the proof says no layout, twenty seeded starts of the packing search find
    none; where that search finds one, the proof does not say no layout (and one of each kind occurs)."""
    rng = np.random.default_rng(7)
    said = set()
    for _ in range(12):
        t = random_bend(rng)
        region = proof_region(t)
        assert region is not None
        k = int(rng.integers(2, 5))
        first = float(rng.uniform(region.first_m, region.first_m + 0.3))
        last = first + float(rng.uniform(0.05, 0.45))
        proved = refuted(t, k, (first, last))
        found = packed_in_window(t, k, first, last, 20)
        assert not (proved and found), (k, first, last)
        said.add((proved, found))
    assert (True, False) in said and (False, True) in said


def test_pruning_and_shaving_keep_every_true_layout() -> None:
    """Layouts the packing search finds on random bends (exact: the spacing apart, in the room and the box), each
    robot wrapped in a random box around its place (sorted by l): a node never says no layout, and every robot's
    place stays in its box after the shaving, from boxes a tenth of a millimetre to 0.3 m wide."""
    rng = np.random.default_rng(11)
    checked = 0
    for _ in range(8):
        t = random_bend(rng)
        region = proof_region(t)
        k = int(rng.integers(3, 6))
        found = _search(t, k)
        if region is None or found is None:
            continue
        l_m = np.array(found[0])[::-1]
        n_m = np.einsum('ij,ij->i', np.array(found[1])[::-1] - t.center_at(l_m), t.normal(l_m))
        for _ in range(40):
            size = 10.0 ** rng.uniform(-4.0, -0.5, (k, 4))
            boxes = np.stack([l_m - size[:, 0], l_m + size[:, 1], n_m - size[:, 2], n_m + size[:, 3]], axis=1)
            assert _judged(region.geo, boxes) != 0
            assert np.all((boxes[:, 0] <= l_m) & (l_m <= boxes[:, 1]) & (boxes[:, 2] <= n_m) & (n_m <= boxes[:, 3]))
            checked += 1
    assert checked >= 200


def short_region(tmp_path: Path) -> Path:
    """A straight tube 0.9 m wide whose narrowing starts 0.31 m inside the box: its start region is 0.7 m across
    and 0.3 m along, where Oler's bound allows five robots and three fit (four need 0.325 m, by pigeonhole: two
    of them stand within 0.7 / 3 m across)."""
    path = tmp_path / 'short.toml'
    path.write_text(
        '[tube.center]\nstart_xy_m = [-1.45, 0.0]\npieces = [{ kind = "line", length_m = 2.0 }]\n'
        '[tube.width]\nstart_m = 0.45\nparts = [{ kind = "constant", length_m = 0.385 }, '
        '{ kind = "linear", length_m = 0.3, to_m = 0.3 }, { kind = "constant" }]\n[robotarium]\nn_robots = 3\n'
    )
    return path


def test_three_fit_where_olers_bound_allows_five_and_four_are_proved_out(tmp_path: Path) -> None:
    path = short_region(tmp_path)
    t = load_scene(path).tube
    region = start_region(t)
    assert packing_bound(t) == 5
    assert 0.29 < region.l_m[-1] - 0.075 < 0.31
    assert not refuted(t, 3)
    assert refuted(t, 4)  # and so five, which Oler's bound allows


def test_a_refusal_the_proof_holds_is_said_physical(tmp_path: Path) -> None:
    """Four robots on that region: refused; said physical (at most three, proved) only when the proof is asked
    for, since Oler's bound allows them."""
    scene = load_scene(short_region(tmp_path), n_robots=4)
    plain, proved = robotarium_fit(scene), robotarium_fit(scene, prove=True)
    assert not plain.fits and 'physically' not in plain.reason
    assert "(not shown to be physical: Oler's bound lets up to 5 robots fit 0.4 m apart" in plain.reason
    assert not proved.fits and 'not shown' not in proved.reason
    assert 'physically: at most 3 robots fit 0.4 m apart in the start region' in proved.reason
    assert 'robotarium_exp.packing_proof' in proved.reason


def test_a_refusal_the_proof_does_not_hold_says_so(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Where the proof is asked for and does not rule the robots out (here a stand-in that cannot), the refusal
    says it is not shown to be physical and that the proof was tried; the proof is asked once, for these robots."""
    scene = load_scene(short_region(tmp_path), n_robots=4)
    asked: list[int] = []

    def cannot(tube: VirtualTube, n_robots: int) -> bool:
        asked.append(n_robots)
        return False

    monkeypatch.setattr(fit, 'refuted', cannot)
    verdict = robotarium_fit(scene, prove=True)
    assert asked == [4] and not verdict.fits and 'physically' not in verdict.reason
    assert "not shown to be physical: Oler's bound lets up to 5 robots" in verdict.reason
    assert 'robotarium_exp.packing_proof does not rule 4 out)' in verdict.reason
