"""The body of a Robotarium submission: the tube experiment with an embedded plan, numpy and rps only.

:mod:`submission.builder` writes a single file: a header, the scene's data (``DATA``), the sources of the package
functions listed in ``INLINED`` (the swarm law's building blocks and the near-identity map, so there is one
implementation of them), then this module's code below the marker line. Imported as a module (tests, benchmarks)
it takes those functions from the package instead.

On the testbed it constructs the Robotarium with the scene's initial conditions, then every step: control points,
the swarm controller on a sampled tube with the planned speed and density, the testbed's own barrier certificate
(either generation's name), the near-identity map with uniform wheel scaling, ``set_velocities``, ``step``. Robots
that leave the tube park beyond its exit. It saves every logged array with ``np.save`` every 100 steps and at the
end, prints a one-line JSON summary (it lands in ``log.txt``), and calls the generation's end-of-script function.
"""

from __future__ import annotations

# ---- inlined by the builder: the package functions named in INLINED replace this import block ----
from unicycle_mapping.errors import MappingError, as_columns, positive  # noqa: F401
from unicycle_mapping.mapping import si_to_uni
from unicycle_mapping.wheels import scale_to_wheel_limits, wheel_speeds  # noqa: F401
from vtube_planning.swarm.control import BARRIER_EPS, barrier_gain, saturate, sigma, smooth_saturation  # noqa: F401

INLINED = (
    ('unicycle_mapping.errors', ('MappingError', 'as_columns', 'positive')),
    ('unicycle_mapping.mapping', ('si_to_uni',)),
    ('unicycle_mapping.wheels', ('wheel_speeds', 'scale_to_wheel_limits')),
    ('vtube_planning.swarm.control', ('BARRIER_EPS', 'sigma', 'smooth_saturation', 'barrier_gain', 'saturate')),
)
# ---- runtime ----
import json
import os
import time

import numpy as np

SAVE_EVERY = 100
WHEEL_RADIUS, BASE_LENGTH, MAX_WHEEL_SPEED = 0.016, 0.11, 12.5


class SampledTube:
    """The tube as samples along its centre line: projection onto the polyline, width, cumulative area."""

    def __init__(self, data: dict) -> None:
        self.l = np.asarray(data['l'], dtype=float)
        self.xy = np.asarray(data['xy'], dtype=float)  # (2, K)
        self.half_width = np.asarray(data['half_width'], dtype=float)
        self.area = np.asarray(data['area'], dtype=float)
        self.length = float(self.l[-1])
        seg = np.diff(self.xy, axis=1)
        self.seg_len = np.hypot(seg[0], seg[1])
        self.seg_dir = seg / self.seg_len

    def project(self, points: np.ndarray) -> dict:
        """Arc length, unit tangent (2, N), left normal, signed offset and half-width of (2, N) points."""
        rel = points[:, :, None] - self.xy[:, None, :-1]  # (2, N, K-1)
        along = np.clip(np.einsum('ink,ik->nk', rel, self.seg_dir), 0.0, self.seg_len)
        foot = self.xy[:, None, :-1] + self.seg_dir[:, None, :] * along
        dist = np.hypot(*(points[:, :, None] - foot))
        k = np.argmin(dist, axis=1)
        n = points.shape[1]
        s = along[np.arange(n), k]
        before = (k == 0) & (s <= 0.0)  # before the entrance / past the exit: the straight extensions
        after = (k == self.seg_len.size - 1) & (s >= self.seg_len[-1])
        tangent = self.seg_dir[:, k]
        base = self.xy[:, k]
        s = np.where(before | after, np.einsum('in,in->n', points - base, tangent), s)
        l_m = self.l[k] + s
        normal = np.vstack([-tangent[1], tangent[0]])
        offset = np.einsum('in,in->n', points - (base + tangent * s), normal)
        return {'l': l_m, 'tangent': tangent, 'normal': normal, 'y': offset,
                'half_width': np.interp(l_m, self.l, self.half_width)}

    def swarm_area(self, l_back: float, l_front: float, pad: float) -> float:
        """Area between l_back - pad and l_front + pad (straight extensions keep the end widths)."""

        def area_at(l_m: float) -> float:
            if l_m < 0.0:
                return 2.0 * self.half_width[0] * l_m
            if l_m > self.length:
                return self.area[-1] + 2.0 * self.half_width[-1] * (l_m - self.length)
            return float(np.interp(l_m, self.l, self.area))

        return area_at(l_front + pad) - area_at(l_back - pad)


class TubeController:
    """The swarm law on control points: forward term from the plan, barrier avoidance and tube keeping, (a3)."""

    def __init__(self, data: dict) -> None:
        self.tube = SampledTube(data['tube'])
        self.plan_l = np.asarray(data['plan']['l'], dtype=float)
        self.plan_w = 1.0 / np.asarray(data['plan']['speed'], dtype=float)
        self.plan_rho = np.asarray(data['plan']['density'], dtype=float)
        self.swarm = data['swarm']
        self.control = data['control']
        self.planned = bool(data['planned'])
        self.slots = np.asarray(data['parking_slots'], dtype=float)
        self.n = int(self.swarm['n_robots'])
        self.r_a = np.full(self.n, float(self.swarm['r_a_m']))
        self.slot_of = np.full(self.n, -1)

    def step(self, points: np.ndarray, dt: float) -> tuple[np.ndarray, dict]:
        """Single-integrator commands (2, N) for control points (2, N), and what was measured."""
        sw, ct, n = self.swarm, self.control, self.n
        proj = self.tube.project(points)
        l_m = proj['l']
        density = n / self.tube.swarm_area(float(l_m.min()), float(l_m.max()), float(sw['r_a_m']))
        if self.planned:
            forward = 1.0 / np.interp(l_m, self.plan_l, self.plan_w)
        else:
            forward = np.full(n, 0.5 * (sw['v_min_mps'] + sw['v_max_mps']))
        r_s = float(sw['r_s_m'])
        push = np.zeros((2, n))
        diff = points[:, :, None] - points[:, None, :]
        dist = np.hypot(diff[0], diff[1]) + np.eye(n) * 1e9
        band = (r_s + self.r_a)[:, None] * np.ones((1, n))
        gain = np.where(dist < band, barrier_gain(np.minimum(dist, 1e3), 2 * r_s, 2 * r_s, band,
                                                  float(ct['avoidance_gain'])), 0.0)
        push += np.sum(gain * diff / dist, axis=2)
        clearance = proj['half_width'] - np.abs(proj['y'])
        keep = barrier_gain(clearance, r_s, r_s, self.r_a, float(ct['keeping_gain']))
        command = forward * proj['tangent'] + push - keep * np.sign(proj['y']) * proj['normal']
        command = saturate(command, float(sw['v_min_mps']), float(sw['v_max_mps']), proj['tangent'])
        for k in np.flatnonzero((l_m > self.tube.length) & (self.slot_of < 0)):
            self.slot_of[k] = int((self.slot_of >= 0).sum())
        parked = self.slot_of >= 0
        to_slot = self.slots[:, self.slot_of[parked]] - points[:, parked]
        reach = np.maximum(np.hypot(to_slot[0], to_slot[1]), 1e-9)
        command[:, parked] = to_slot * np.minimum(1.0, float(sw['v_max_mps']) / reach)
        if self.planned:
            rho_star = np.interp(l_m, self.plan_l, self.plan_rho)
            rate = float(ct['k_ra_m3ps']) * np.maximum(0.0, density - rho_star)
            self.r_a = np.minimum(float(ct['r_a_max_m']), self.r_a + dt * rate)
        done = bool(parked.all()) and bool(np.all(np.hypot(*(self.slots[:, self.slot_of] - points)) < 0.03))
        return command, {'l': l_m, 'density': density, 'done': done}


def make_barrier(data: dict):
    """The testbed's single-integrator certificate with the arena boundary, under either generation's name."""
    import rps.utilities.barrier_certificates as certificates

    boundary = np.array([-1.6, 1.6, -1.0, 1.0])
    radius, limit = float(data['barrier']['safety_radius_m']), float(data['swarm']['v_max_mps'])
    if hasattr(certificates, 'create_si_barrier_certificate_with_boundary'):  # V2
        certificate = certificates.create_si_barrier_certificate_with_boundary(
            safety_radius=radius, magnitude_limit=limit, boundary_points=boundary)
    else:  # classic: rescales its argument in place, so it gets a copy
        certificate = certificates.create_single_integrator_barrier_certificate_with_boundary(
            safety_radius=radius, magnitude_limit=limit, boundary_points=boundary)
    return lambda dxi, x: certificate(np.array(dxi, copy=True), x)


def draw_tube(r, data: dict) -> None:
    """Draw the tube on the arena figure (projected onto the testbed), if the Robotarium has a figure."""
    axes = getattr(r, '_axes_handle', None) or getattr(r, 'axes', None)
    if axes is None or isinstance(axes, list):
        return
    edges = np.asarray(data['tube']['edges'], dtype=float)  # (2, 2, K): left and right boundary
    for side in edges:
        axes.plot(side[0], side[1], color='tab:blue', linewidth=2, zorder=0)


def save_log(log: dict, prefix: str = 'vtube_') -> None:
    """np.save every logged array (the testbed returns files the script writes)."""
    for name, rows in log.items():
        np.save(prefix + name + '.npy', np.array(rows))


def run(data: dict, robotarium_module, *, max_steps: int | None = None) -> dict:
    """The experiment loop; returns (and prints) the summary."""
    n = int(data['swarm']['n_robots'])
    show = os.environ.get('VTUBE_HEADLESS', '') != '1'
    r = robotarium_module.Robotarium(number_of_robots=int(n), show_figure=show, sim_in_real_time=show,
                                     initial_conditions=np.array(data['initial_conditions'], dtype=float))
    if show:
        draw_tube(r, data)
    dt = float(getattr(r, 'TIME_STEP', getattr(r, 'time_step', 0.033)))
    controller = TubeController(data)
    barrier = make_barrier(data)
    d = float(data['projection_distance_m'])
    log: dict = {name: [] for name in ('t', 'wall', 'poses', 'dxu', 'r_a', 'l', 'density', 'barrier_correction')}
    min_distance = np.inf
    started = time.time()
    done = False
    steps = int(max_steps if max_steps is not None else data['max_steps'])
    for step in range(steps):
        poses = r.get_poses()
        points = poses[:2] + d * np.vstack([np.cos(poses[2]), np.sin(poses[2])])
        nominal, info = controller.step(points, dt)
        safe = barrier(nominal, points)
        dxu, _ = scale_to_wheel_limits(si_to_uni(safe, poses, d), BASE_LENGTH, WHEEL_RADIUS, MAX_WHEEL_SPEED)
        gaps = np.hypot(*(poses[:2, :, None] - poses[:2, None, :])) + np.eye(n) * 1e9
        min_distance = min(min_distance, float(gaps.min()))
        for name, value in (('t', step * dt), ('wall', time.time() - started), ('poses', poses), ('dxu', dxu),
                            ('r_a', controller.r_a),
                            ('l', info['l']), ('density', info['density']),
                            ('barrier_correction', np.hypot(*(safe - nominal)))):
            log[name].append(np.array(value, copy=True))
        if info['done']:
            done = True
            break
        r.set_velocities(np.arange(n), dxu)
        r.step()
        if step % SAVE_EVERY == SAVE_EVERY - 1:
            save_log(log)
    save_log(log)
    iterations = getattr(r, 'iterations', None) or getattr(r, '_iteration', None) or getattr(r, '_iterations', 0)
    errors = dict(getattr(r, 'errors', None) or getattr(r, '_errors', None) or {})
    summary = {'vtube_summary': 1, 'scene': data['scene'], 'planned': data['planned'], 'robots': n, 'dt_s': dt,
               'steps': step + 1, 'completed': done, 'iterations': int(iterations),
               'min_center_distance_m': round(min_distance, 4),
               'barrier_correction_max_mps': round(float(np.max(log['barrier_correction'])), 4),
               'errors': {k: v for k, v in errors.items() if isinstance(v, int)}}
    print(json.dumps(summary))
    if hasattr(r, 'debug'):
        r.debug()
    else:
        r.call_at_scripts_end()
    return summary
