"""The one verdict on "fits the Robotarium": each misfit alone, made by editing the flight data of a shipped scene
that fits, its reason and its fix; the "at most K robots" and "lengthen by" fixes checked by doing what they say."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from robotarium_exp.design import first_narrowing, neighbour_counts, start_formation
from robotarium_exp.experiment import ExperimentConfig, flight_data
from robotarium_exp.fit import Fit, Misfit, fit_of_flight, robotarium_fit
from robotarium_exp.flight_data import FlightData
from robotarium_exp.parking_slots import PARKING_SPACING_M, parking, parking_bound
from robotarium_exp.safety import WALL_KEEP_M
from robotarium_exp.scene import load_scene, shipped_scene_text
from robotarium_exp.spec import ROBOTARIUM

SHIPPED = ('robotarium_trapezoid', 'robotarium_curve')


@pytest.fixture(scope='module')
def data() -> FlightData:
    """The trapezoid's flight data (six robots, 2 x 3 at the entrance), as a submission embeds them."""
    return flight_data(load_scene('robotarium_trapezoid'), None, ExperimentConfig(planning=False))


def only_misfit(data: FlightData) -> Misfit:
    fit = fit_of_flight(data)
    assert len(fit.misfits) == 1, fit.misfits
    assert not fit.fits and fit.reason == f'does not fit the Robotarium: {fit.misfits[0]}'
    return fit.misfits[0]


def moved(ic: np.ndarray, k: int, x: float | None = None, y: float | None = None) -> np.ndarray:
    out = ic.copy()
    out[0, k] = out[0, k] if x is None else x
    out[1, k] = out[1, k] if y is None else y
    return out


@pytest.mark.parametrize('name', SHIPPED)
def test_the_shipped_scenes_fit(name: str) -> None:
    fit = robotarium_fit(load_scene(name))
    assert fit == Fit() and fit.fits and fit.reason == 'fits the Robotarium'


@pytest.mark.parametrize('n', [0, 21])
def test_a_robot_count_the_testbed_does_not_have(data: FlightData, n: int) -> None:
    misfit = only_misfit(replace(data, n_robots=n))
    assert misfit.what == f'{n} robots' and misfit.fix == 'the testbed has 20: use 1 to 20'


def test_a_tube_outside_the_arena(data: FlightData) -> None:
    edges = data.tube_edges_m.copy()
    edges[1, 1] -= 0.6  # the right boundary, y = -0.5 in the wide part, down to -1.1
    misfit = only_misfit(replace(data, tube_edges_m=edges))
    first = edges[1][:, int(np.argmax(ROBOTARIUM.outside_arena(edges[1], 0.05)))]
    assert misfit.what.startswith(f"the tube's right boundary reaches ({first[0]:.2f}, {first[1]:.2f}), outside")
    assert 'the arena [-1.6, 1.6] x [-1, 1] less 0.05 m' in misfit.what and misfit.fix == 'move or shrink the tube'


@pytest.mark.parametrize('narrowest', [WALL_KEEP_M, WALL_KEEP_M - 1e-4])
def test_a_tube_narrower_than_a_robot_passes_through(data: FlightData, narrowest: float) -> None:
    """At exactly the half-width the wall rows keep it fits; a tenth of a millimetre less is refused, at the
    narrowest sample, with the width a robot needs."""
    l_m = data.tube.l_m
    pinch = np.minimum(data.tube.half_width_m, narrowest + (l_m[-1] - l_m))  # narrowest at the exit
    half_width = np.where(l_m > 0.9 * l_m[-1], pinch, data.tube.half_width_m)
    fit = fit_of_flight(replace(data, tube=replace(data.tube, half_width_m=half_width)))
    if narrowest == WALL_KEEP_M:
        assert fit.fits
        return
    (misfit,) = fit.misfits
    at = data.tube.l_m[int(np.argmin(half_width))]
    assert misfit.what.startswith(f'the tube narrows to {2 * narrowest:.2f} m at l = {at:.2f} m, under the 0.18 m')
    assert misfit.fix == 'widen it to at least 0.18 m there' and misfit.kind == 'width'


def test_a_robot_outside_the_start_box(data: FlightData) -> None:
    ic = data.initial_conditions
    back = int(np.argmin(ic[0]))  # a back-row robot 0.025 m beyond the box's |x| <= 1.375, no closer to the others
    misfit = only_misfit(replace(data, initial_conditions=moved(ic, back, x=-1.4)))
    assert misfit.what.startswith(f'robot {back} starts at (-1.40, {ic[1, back]:.2f}), outside the box |x| <= 1.375')
    assert 'move the tube entrance inwards' in misfit.fix


def test_two_robots_too_close(data: FlightData) -> None:
    ic = data.initial_conditions
    k = int(np.argmax((ic[0] < ic[0].max()) & (ic[1] > 0.3)))  # the back row's robot at y = +0.4 ...
    closer = moved(ic, k, y=0.35)  # ... 0.35 m from its neighbour at y = 0: as crowded as before
    assert list(neighbour_counts(closer)) == list(neighbour_counts(ic))
    misfit = only_misfit(replace(data, initial_conditions=closer))
    assert misfit.what == 'two robots start 0.350 m apart, closer than the 0.4 m the initialization needs'
    assert 'start_formation' in misfit.fix


def test_robots_zero_and_one_side_by_side(data: FlightData) -> None:
    ic = data.initial_conditions
    gaps = np.hypot(*(ic[:2] - ic[:2, :1]))
    beside = int(np.argmin(np.where(gaps > 0, gaps, np.inf)))  # robot 0's neighbour in the 2 x 3 grid, 0.4 m away
    swapped = ic[:, [0, beside, *[k for k in range(1, 6) if k != beside]]]
    misfit = only_misfit(replace(data, initial_conditions=swapped))
    assert misfit.what.startswith('robots 0 and 1 start 0.40 m apart')
    assert 'order_for_v2_initializer' in misfit.fix


def test_a_formation_reaching_the_narrowing(data: FlightData) -> None:
    """Moved 1.0 m forward: rows at l = 1.1 and 1.5 m, the front row 0.1 m past the narrowing at 1.40 m; the back
    row alone (3 robots) ends before it."""
    ic = data.initial_conditions.copy()
    ic[0] += 1.0
    misfit = only_misfit(replace(data, initial_conditions=ic))
    back, front = float(ic[0].min()) + 1.45, float(ic[0].max()) + 1.45  # l along the straight tube from x = -1.45
    assert back < 1.4 < front
    assert misfit.what == (
        f'the start formation (2 row(s) of up to 3) reaches l = {front:.2f} m, past the start of the narrowing at '
        'l = 1.40 m: the swarm would start inside it, and no robot can queue behind the entrance at (-1.45, 0.00), '
        'outside the box |x| <= 1.375, |y| <= 0.875 the testbed initializes robots in'
    )
    assert misfit.fix == f'lengthen the wide part before the narrowing by {front - 1.4:.2f} m, or use at most 3 robots'


def test_a_formation_ending_at_the_narrowing_fits(data: FlightData) -> None:
    ic = data.initial_conditions.copy()
    ic[0] += 1.4 - (float(ic[0].max()) + 1.45) - 1e-3  # the front row 1 mm before the narrowing
    assert fit_of_flight(replace(data, initial_conditions=ic)).fits


def test_a_parking_slot_outside(data: FlightData) -> None:
    slots = data.parking_slots.copy()
    slots[1, 4] = 0.97
    misfit = only_misfit(replace(data, parking_slots=slots))
    # the trapezoid's farthest row: the arena's edge x = 1.6 less the 0.2 m wall
    assert misfit.what.startswith('parking slot 4 lies at (1.40, 0.97), outside the arena')
    assert misfit.fix.startswith('move the tube exit at (1.00, 0.00) away from the arena edge')


def test_the_reason_names_the_first_misfit_and_every_one_is_kept(data: FlightData) -> None:
    slots = data.parking_slots.copy()
    slots[0, 0] = 1.7
    fit = fit_of_flight(replace(data, n_robots=25, parking_slots=slots))
    assert [m.what.split()[0] for m in fit.misfits] == ['25', 'parking']
    assert fit.reason == f'does not fit the Robotarium: 25 robots; {fit.misfits[0].fix}'


def at_most(fit: Fit) -> int:
    (k,) = [int(m) for misfit in fit.misfits for m in re.findall(r'use at most (\d+) robots', misfit.fix)]
    return k


@pytest.mark.parametrize(
    ('name', 'n'),
    [
        ('robotarium_trapezoid', 13),
        ('robotarium_trapezoid', 15),
        ('robotarium_curve', 13),
    ],
)
def test_the_at_most_k_robots_fix_is_right(name: str, n: int) -> None:
    """K robots start before the narrowing, K + 1 do not (the curve's twelve robots start in a packing,
    `robotarium_exp.packing`)."""

    def formation_misfits(k: int) -> list[Misfit]:
        fit = robotarium_fit(load_scene(name, n_robots=k))
        return [m for m in fit.misfits if m.what.startswith('the start formation')]

    k = at_most(robotarium_fit(load_scene(name, n_robots=n)))
    assert not formation_misfits(k) and formation_misfits(k + 1)


def test_lengthening_the_wide_part_as_the_fix_says_makes_it_fit(tmp_path: Path) -> None:
    """Twelve robots (4 rows of 3, the front row at l = 1.32 m) on the trapezoid with its wide part cut to 1.2 m:
    the fix's lengthening makes it fit, a little less does not."""
    _, text = shipped_scene_text('robotarium_trapezoid')

    def wide_part(length: float) -> Path:
        path = tmp_path / f'{length:.3f}.toml'
        path.write_text(
            text.replace('{ kind = "constant", length_m = 1.4 }', f'{{ kind = "constant", length_m = {length} }}')
        )
        return path

    (misfit,) = robotarium_fit(load_scene(wide_part(1.2), n_robots=12)).misfits
    found = re.search(r'by (\d+\.\d\d) m', misfit.fix)
    assert found is not None
    wide = 1.2 + float(found.group(1))  # rounded to 1 cm: the front row then within 5 mm of the narrowing
    for length, fits in ((wide + 0.005, True), (wide - 0.02, False)):
        assert robotarium_fit(load_scene(wide_part(length), n_robots=12)).fits is fits, length


def test_a_scene_without_a_start_formation_is_refused_with_its_reason(tmp_path: Path) -> None:
    path = tmp_path / 'edge.toml'
    path.write_text(
        '[tube.center]\nstart_xy_m = [-1.45, 0.88]\npieces = [{ kind = "line", length_m = 2.4 }]\n'
        '[tube.width]\nstart_m = 0.06\nparts = [{ kind = "constant" }]\n[robotarium]\nn_robots = 2\n'
    )
    (misfit,) = robotarium_fit(load_scene(path)).misfits
    assert (
        misfit.what
        == 'no start formation: no cross-section of the tube lies inside the box the testbed initializes robots in'
    )
    assert misfit.fix == 'move the tube entrance inwards or widen it'


def bend_scene(tmp_path: Path, start: str, pieces: str, wide_m: float, to_m: float) -> Path:
    """A Robotarium scene of lines and arcs; half-width 0.5 m for ``wide_m``, then over 0.4-0.5 m to ``to_m``."""
    path = tmp_path / 'bend.toml'
    narrowing = f'{{ kind = "smooth", length_m = {0.4 if to_m > 0.25 else 0.5}, to_m = {to_m} }}'
    path.write_text(
        f'[tube.center]\nstart_xy_m = {start}\npieces = [{pieces}]\n[tube.width]\nstart_m = 0.5\n'
        f'parts = [{{ kind = "constant", length_m = {wide_m} }}, {narrowing}, {{ kind = "constant" }}]\n'
        '[robotarium]\nn_robots = 6\n'
    )
    return path


def line(length_m: float) -> str:
    return f'{{ kind = "line", length_m = {length_m} }}'


def thirty_five_degree_bend(tmp_path: Path) -> Path:
    """The issue's new tube: a 35 degree bend, the narrowing (0.4 m, to 0.3 m) from l = 1.3 m; its exit at 35
    degrees towards the arena's top edge."""
    arc = '{ kind = "arc", radius_m = 1.2, angle_deg = 35 }'
    return bend_scene(tmp_path, '[-1.4, -0.3]', f'{line(0.5)}, {arc}, {line(0.9)}', 1.3, 0.3)


def test_a_35_degree_bend_with_the_narrowing_inside_fits_up_to_eleven(tmp_path: Path) -> None:
    """Its formations are built exactly 0.4 m apart on the bend, which the flight data's six significant digits
    carry as 0.399997 m: that must not read as 'closer than 0.4 m'. Up to nine robots stand in three rows that end
    before the narrowing at 1.3 m, ten in staggered rows (3, 2, 3, 2), eleven in a packing, twelve in none (of
    twelve seeded tries; Oler's bound is 13); beyond the exit, heading 35 degrees towards the top edge, the slots
    (0.08 m beyond the exit at least, 0.2 m from the edge) hold four robots in lanes centred on the exit, eight in
    lanes moved across, and nine to eleven in staggered parking rows nearer than 0.3 m (each slot still 0.3 m from
    every other): twelve are refused for their formation alone."""
    path = thirty_five_degree_bend(tmp_path)
    fits = {n: robotarium_fit(load_scene(path, n_robots=n)) for n in range(1, 13)}
    assert [n for n, fit in fits.items() if fit.fits] == list(range(1, 12))
    for n in (9, 10, 11):
        scene = load_scene(path, n_robots=n)
        slots = parking(scene.tube, n)
        beyond = scene.tube.tangent(scene.tube.length_m) @ (slots - scene.tube.center_at(scene.tube.length_m)[:, None])
        rows = np.unique(np.round(beyond, 6))
        assert rows.size >= 2 and np.diff(rows).min() < PARKING_SPACING_M  # staggered: rows nearer than the spacing
        assert np.hypot(*(slots[:, :, None] - slots[:, None, :]))[np.triu_indices(n, 1)].min() >= PARKING_SPACING_M
    assert [m.what.split()[1] for m in fits[12].misfits] == ['start']


def test_on_a_35_degree_bend_the_fix_names_the_k_that_fits(tmp_path: Path) -> None:
    """Plain rows spread on the bend (four rows reach 1.87 m); K is the design's: eleven robots in a packing."""
    assert at_most(robotarium_fit(load_scene(thirty_five_degree_bend(tmp_path), n_robots=12))) == 11


def test_a_row_on_a_bend_is_one_row(tmp_path: Path) -> None:
    """On a bend the sampled tube projects a row's robots a few millimetres apart: still one row, so 9 robots stand
    in 3 rows of 3 (the formation's own rows), and K is at least the whole rows of 3, 0.4 m apart from the back row,
    that end before the narrowing (the design's K, which staggered rows may raise), and its formation ends there."""
    arc = '{ kind = "arc", radius_m = 1.0, angle_deg = 57.3 }'
    path = bend_scene(tmp_path, '[-1.3, -0.35]', f'{line(0.8)}, {arc}, {line(0.6)}', 0.7, 0.25)
    scene = load_scene(path, n_robots=9)
    fit = robotarium_fit(scene)
    (misfit,) = [m for m in fit.misfits if m.what.startswith('the start formation')]
    assert misfit.what.startswith('the start formation (3 row(s) of up to 3) reaches')
    # the oracle: the exact tube's arc lengths of the formation and its first narrowing
    l_m = np.sort(scene.tube.project(start_formation(scene.tube, 9).poses[:2]).l_m)
    narrowing = first_narrowing(scene.tube)
    assert narrowing is not None
    rows = [r for r in (1, 2) if float(l_m[0]) + (r - 1) * 0.4 <= narrowing.start_m]
    k = at_most(fit)  # the design's: at least the whole rows of 3, more where staggered rows end sooner
    assert k >= 3 * max(rows) and start_formation(scene.tube, k).l_front_m <= narrowing.start_m


def test_when_no_row_fits_before_the_narrowing_the_fix_does_not_offer_fewer_robots(data: FlightData) -> None:
    ic = data.initial_conditions.copy()
    ic[0] += 1.5  # the back row at l = 1.6 m, past the narrowing at 1.40 m
    misfit = only_misfit(replace(data, initial_conditions=ic))
    front = float(ic[0].max()) + 1.45
    assert misfit.fix == f'lengthen the wide part before the narrowing by {front - 1.4:.2f} m'


def test_a_generated_tube_is_told_in_the_map_file_s_keys_and_never_beyond_the_arena(tmp_path) -> None:
    """Issue 49: refusals of generated tubes spoke of the generated scene ("lengthen the wide part by 2.00 m",
    "move it"); they name the map file's keys, and a lengthening the arena has no room for is not proposed."""
    from robotarium_exp.fit import GENERATED, Misfit, for_map_file, robotarium_fit
    from robotarium_exp.scene import load_scene
    from vtube.cli.tube import map_examples
    from vtube_planning.geometry.from_maps.map_file import generated_scene

    text = map_examples()['robotarium_gate'].replace('n_robots = 6', 'n_robots = 12')
    assert 'n_robots = 12' in text
    (tmp_path / 'gate.toml').write_text(generated_scene(text, str(tmp_path / 'map.toml'))[0], encoding='utf-8')
    scene = load_scene(tmp_path / 'gate.toml')
    assert GENERATED in scene.text
    fixes = [m.fix for m in robotarium_fit(scene).misfits]
    assert fixes[0].startswith('the arena has no room to move start_m 0.50 m back (to (-1.95, 0.00), outside the box')
    assert fixes[0].endswith(': use at most 8 robots') and 'lengthen the wide part' not in ' '.join(fixes)
    assert (
        fixes[1]
        == 'in the map file, move goal_m away from the arena edge (the slots lie beyond it), or use fewer robots'
    )
    inner = text.replace('start_m = [-1.45, 0.0]', 'start_m = [-1.1, 0.0]')  # room behind the start: 0.275 m
    (tmp_path / 'inner.toml').write_text(generated_scene(inner, str(tmp_path / 'map.toml'))[0], encoding='utf-8')
    inner_scene = load_scene(tmp_path / 'inner.toml')
    moved = for_map_file(Misfit('x', 'lengthen the wide part', 'narrowing', 0.2, 6), inner_scene).fix
    assert (
        moved
        == 'in the map file, move start_m 0.20 m further back from the narrow passage, to (-1.30, 0.00), or use at most 6 robots'
    )
    assert for_map_file(Misfit('x', 'y', 'other'), scene).fix == 'y'  # a rule without a map-file fix keeps its own
    narrow = for_map_file(Misfit('x', 'widen it to at least 0.18 m there', 'width'), scene).fix
    assert narrow == 'in the map file, raise half_width_min_m to at least 0.09 m'  # the generator's narrowest


def test_parking_refused_above_olers_bound_is_said_physical() -> None:
    """The sweep's wide tube ends at (1, 0) facing +x: the room beyond its exit is 0.32 m deep (0.08 m beyond it to
    0.2 m from the edge) and 1.6 m across, where Oler's bound allows (2 / sqrt 3) 0.512 / 0.09 + 3.84 / 0.6 + 1 = 13.97
    robots 0.3 m apart: fourteen are refused as physical, thirteen (lanes hold twelve) are refused as not shown to be."""
    path = Path(__file__).parents[3] / 'docs' / 'sweep' / 'tubes' / 'wide.toml'
    thirteen, fourteen = (robotarium_fit(load_scene(path, n_robots=n)) for n in (13, 14))
    assert parking_bound(load_scene(path).tube) == 13
    assert [m.kind for m in thirteen.misfits] == ['parking'] and 'physically' not in thirteen.reason
    assert "(not shown to be physical: Oler's bound lets up to 13 robots park 0.3 m apart" in thirteen.reason
    assert [m.kind for m in fourteen.misfits] == ['parking']
    assert 'physically: at most 13 robots park 0.3 m apart beyond the exit, in any layout' in fourteen.reason
