"""Figures of a study's rows and reports (`vtube_planning.studies.study_report`). matplotlib is imported here only,
when a figure is drawn."""

from __future__ import annotations

from collections.abc import Collection, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from vtube_planning.studies.seeds import seeds_text

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from vtube_planning.studies.judging import Family, Judging


VERDICT_COLORS = {
    'holds': 'tab:blue',
    'reversed': 'tab:red',
    'not shown': 'tab:gray',
    'not replicated': 'tab:orange',
    'no verdict': 'lightgray',
}
"""A claim's colour in the difference figures, by verdict (`vtube_planning.studies.stats`)."""


def _verdict_legend(fig: Figure, verdicts: Collection[str], *, squares: bool = False) -> None:
    """A legend of the verdicts drawn under the figure: their colours, as dots (filled where the claim holds) or as
    the squares of `verdict_matrix_figure`."""
    shown = [v for v in VERDICT_COLORS if v in verdicts]
    handles = [
        fig.axes[0].plot(
            [],
            [],
            's' if squares else 'o',
            color=VERDICT_COLORS[v],
            mfc=VERDICT_COLORS[v] if squares or v == 'holds' else 'white',
        )[0]
        for v in shown
    ]
    words = [_VERDICT_WORDS.get(v, v) for v in shown]
    fig.legend(handles, words, loc='outside lower center', ncols=len(shown), fontsize=8)


_VERDICT_WORDS = {'holds': 'a beats b (holds)', 'reversed': 'b beats a (reversed)'}


def study_figure(
    summary: list[dict[str, Any]], collision_distance_m: float, seeds: Sequence[int] | None = None
) -> Figure:
    """Bars of passing time and minimum distance per scene and mode at their mean over the seeds, with a black line
    from the smallest to the largest value over the seeds; the title says so (and names ``seeds``)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.0, 3.8), layout='constrained')
    ax_t, ax_d = fig.subplots(1, 2)
    scenes = [e['scene'] for e in summary]
    x = np.arange(len(scenes))
    modes = list(dict.fromkeys(m for e in summary for m in e['modes']))
    colors = {
        'no planning': 'tab:gray',
        'planning': 'tab:blue',
        'flocking': 'tab:orange',
        'flocking (v_min)': 'tab:brown',
        'nmpc': 'tab:red',
    }
    width = 0.8 / len(modes)
    for k, mode in enumerate(sorted(modes, key=lambda m: (m != 'no planning', m != 'planning', m))):
        offset = (k - 0.5 * (len(modes) - 1)) * width
        present = [i for i, e in enumerate(summary) if mode in e['modes']]
        for ax, key, span in (
            (ax_t, 'passing_time_s', 'passing_time_range_s'),
            (ax_d, 'min_distance_m', 'min_distance_range_m'),
        ):
            mean = np.array([summary[i][mode][key] for i in present])
            ax.bar(x[present] + offset, mean, width, color=colors.get(mode, f'C{k}'), label=mode)
            ax.vlines(
                x[present] + offset,
                [summary[i][mode][span][0] for i in present],
                [summary[i][mode][span][1] for i in present],
                color='k',
                lw=1.2,
            )  # the range over seeds
    ax_d.axhline(collision_distance_m, color='tab:red', ls='--', label='2 r_p (collision)')
    ax_d.plot([], [], color='k', lw=1.2, label='min-max over the seeds')  # the legend's entry for the ranges
    which = f'seeds {seeds_text(list(seeds))}' if seeds else 'the seeds'
    fig.suptitle(f'bars: mean over {which}; black lines: from the smallest to the largest value', fontsize=9)
    for ax, label in ((ax_t, 'passing time [s]'), (ax_d, 'minimum distance [m]')):
        ax.set_xticks(x, scenes)
        ax.set_xlabel('scene')
        ax.set_ylabel(label)
    handles, labels = ax_d.get_legend_handles_labels()
    fig.legend(handles, labels, loc='outside lower center', ncols=len(labels), fontsize=8)
    return fig


def paired_differences_figure(rows: list[dict[str, Any]], judging: Judging | None = None) -> Figure:
    """A study's paired differences (a - b on the same seeds; with seeds held out, on the others) with their 95 %
    intervals: one panel per metric, one line per comparison and cell (scene, N, setting); coloured by verdict
    (`paired_table`), filled where the claim holds."""
    from matplotlib.figure import Figure

    from vtube_planning.studies.judging import POOLED
    from vtube_planning.studies.study_report import CLAIMS, COMPARISONS, paired_table, place_text, setting_text

    table = paired_table(rows, judging or POOLED)

    def label(p: dict[str, Any]) -> str:
        return f'{p["a"]} - {p["b"]}  |  {place_text(p)}, N={p["n_robots"]}, {setting_text(p)}'

    present = list(dict.fromkeys(label(p) for p in table))
    labels = [text for a, b, _ in COMPARISONS for text in present if text.startswith(f'{a} - {b}  |')]
    fig = Figure(figsize=(12.0, 1.2 + 0.22 * len(labels)), layout='constrained')
    axes = fig.subplots(1, len(CLAIMS), sharey=True)
    colors = VERDICT_COLORS
    for ax, (metric, _, title) in zip(axes, CLAIMS, strict=True):
        for p in (p for p in table if p['metric'] == metric):
            k = labels.index(label(p))
            e, color = p['estimate'], colors[p['verdict']]
            ax.hlines(k, e.low, e.high, color=color, lw=2)
            ax.plot(e.value, k, 'o', color=color, mfc=color if p['verdict'] == 'holds' else 'white')
        ax.axvline(0.0, color='k', lw=0.8)
        ax.set_xlabel(f'difference in {title}')
    axes[0].set_yticks(range(len(labels)), labels, fontsize=7)
    axes[0].invert_yaxis()
    fig.suptitle('a - b on the same seeds: mean and 95 % interval, coloured by verdict', fontsize=9)
    _verdict_legend(fig, {p['verdict'] for p in table})
    return fig


def verdict_matrix_figure(rows: list[dict[str, Any]], judging: Judging | None = None) -> Figure:
    """The paired comparisons at a glance, at page width: a row per cell (scene, N, setting), a column per
    comparison and metric; each square coloured by its verdict (`paired_table`)
    and marked with the effect (a - b as a share of b's mean)."""
    from matplotlib.figure import Figure

    from vtube_planning.studies.judging import POOLED
    from vtube_planning.studies.study_report import CLAIMS, COMPARISONS, paired_table, place_text, setting_text

    table = paired_table(rows, judging or POOLED)
    cells = list(dict.fromkeys(f'{place_text(p)}, N={p["n_robots"]}, {setting_text(p)}' for p in table))
    columns = [
        (a, b, m)
        for a, b, _ in COMPARISONS
        for m, _, _ in CLAIMS
        if any((p['a'], p['b'], p['metric']) == (a, b, m) for p in table)
    ]
    fig = Figure(figsize=(8.0, 2.6 + 0.24 * len(cells)), layout='constrained')
    ax = fig.add_subplot()
    if not table:
        ax.set_axis_off()
        ax.text(0.5, 0.5, 'no paired comparison: two seeds of both modes are needed', ha='center', va='center')
        return fig
    for p in table:
        i = cells.index(f'{place_text(p)}, N={p["n_robots"]}, {setting_text(p)}')
        j = columns.index((p['a'], p['b'], p['metric']))
        ax.add_patch(_square(j, i, VERDICT_COLORS[p['verdict']]))
        if not np.isnan(p['relative']):
            dark = p['verdict'] in ('holds', 'reversed')
            ax.text(j, i, f'{p["relative"]:+.0%}', ha='center', va='center', fontsize=6, color='w' if dark else 'k')
    letters = {m: t.split(' [')[0] for m, _, t in CLAIMS}
    ax.set_xticks(
        range(len(columns)), [f'{a} - {b}: {letters[m]}' for a, b, m in columns], rotation=60, ha='right', fontsize=6
    )
    ax.set_yticks(range(len(cells)), cells, fontsize=6)
    ax.set_xlim(-0.5, len(columns) - 0.5)
    ax.set_ylim(len(cells) - 0.5, -0.5)
    ax.set_title('a - b on the same seeds: the verdict (colour) and the effect (share of b)', fontsize=9)
    _verdict_legend(fig, {p['verdict'] for p in table}, squares=True)
    return fig


def _square(x: float, y: float, color: str) -> Any:
    from matplotlib.patches import Rectangle

    return Rectangle((x - 0.45, y - 0.45), 0.9, 0.9, color=color)


def _where(row: dict[str, Any]) -> str:
    """Where a cell flies within its scene, for a label: its random map and its narrowest half-width, if any."""
    where = '' if row.get('map') in (None, 'none') else f'{row["map"]} map {row["map_seed"]}, '
    return where + (f'narrowest {row["narrowest_m"]:g} m, ' if row.get('narrowest_m') else '')


def cell_means_figure(rows: list[dict[str, Any]]) -> Figure:
    """A study's means per cell and mode: one row of panels per scene; passing time and minimum distance (mean over
    seeds with its 95 % interval; passing time over the runs that completed, hollow when some did not) and the
    share of runs with a collision; one line per cell (N, setting), one colour per mode."""
    from matplotlib.figure import Figure

    from vtube_planning.studies.stats import mean_interval
    from vtube_planning.studies.study_report import setting_text

    scenes = list(dict.fromkeys(r['scene'] for r in rows))
    modes = list(dict.fromkeys(r['mode'] for r in rows))
    groups: dict[tuple[str, str, str], list[dict[str, Any]]] = {}  # (scene, mode, cell label): rows, in one pass
    for r in rows:
        groups.setdefault((r['scene'], r['mode'], f'{_where(r)}N={r["n_robots"]}, {setting_text(r)}'), []).append(r)
    cells = {s: list(dict.fromkeys(label for scene, _, label in groups if scene == s)) for s in scenes}
    height = sum(0.3 * len(c) + 0.9 for c in cells.values())
    fig = Figure(figsize=(13.0, 1.0 + height), layout='constrained')
    grid = fig.add_gridspec(len(scenes), 3, height_ratios=[len(cells[s]) + 2 for s in scenes], width_ratios=[2, 2, 1])
    colors = {mode: f'C{k}' for k, mode in enumerate(modes)}
    offsets = {mode: (k - 0.5 * (len(modes) - 1)) * 0.7 / max(1, len(modes)) for k, mode in enumerate(modes)}
    for i, scene in enumerate(scenes):
        panels = [fig.add_subplot(grid[i, j]) for j in range(3)]
        for mode in modes:
            for k, label in enumerate(cells[scene]):
                sel = groups.get((scene, mode, label), [])
                if not sel:
                    continue
                y = k + offsets[mode]
                for ax, metric in zip(panels, ('passing_time_s', 'min_distance_m'), strict=False):
                    if metric not in sel[0]:
                        continue
                    values = np.array([r[metric] for r in sel], dtype=float)
                    finite = values[np.isfinite(values)]
                    if finite.size == 0:
                        continue
                    if finite.size > 1:
                        e = mean_interval(finite)
                        ax.hlines(y, e.low, e.high, color=colors[mode], lw=1.5)
                    full = finite.size == values.size
                    ax.plot(finite.mean(), y, 'o', ms=4, color=colors[mode], mfc=colors[mode] if full else 'white')
                share = np.mean([r.get('collision_pairs', 0) > 0 for r in sel])
                panels[2].barh(y, share, height=0.7 / max(1, len(modes)), color=colors[mode])
        for ax, title in zip(panels, ('passing time [s]', 'min distance [m]', 'runs with a collision'), strict=True):
            ax.set_yticks(range(len(cells[scene])), cells[scene] if ax is panels[0] else [], fontsize=7)
            ax.set_ylim(len(cells[scene]) - 0.5, -0.5)
            ax.set_title(f'scene {scene}: {title}', fontsize=9)
            ax.set_xlabel(title, fontsize=8)
            ax.grid(axis='x', color='0.9')
        panels[2].set_xlim(0.0, 1.0)
        panels[2].set_xlabel('share of runs with a collision', fontsize=8)
        if not any(r.get('collision_pairs', 0) for r in rows if r['scene'] == scene):
            panels[2].text(
                0.5, 0.5, 'no collision\nin any run', ha='center', va='center', transform=panels[2].transAxes
            )
    handles = [fig.axes[0].plot([], [], 'o', color=colors[m], label=m)[0] for m in modes]
    hollow = fig.axes[0].plot([], [], 'o', color='0.4', mfc='white', label='some runs did not complete')[0]
    fig.legend(handles=[*handles, hollow], loc='outside lower center', ncols=min(len(modes) + 1, 7), fontsize=8)
    fig.suptitle('each cell: the mean over seeds with its 95 % interval, one colour per mode', fontsize=9)
    return fig


def map_differences_figure(rows: list[dict[str, Any]], families: tuple[Family, ...] = ()) -> Figure:
    """A study over random maps (`map_differences`): one panel per metric, one
    line per comparison and population of maps; a dot per map (its mean paired difference over its seeds) and the
    mean over maps with its 95 % interval, filled where the claim holds."""
    from matplotlib.figure import Figure

    from vtube_planning.studies.study_report import CLAIMS, map_differences, setting_text

    found = map_differences(rows, families)
    labels = list(dict.fromkeys(_map_label(f, setting_text(f)) for f in found))
    fig = Figure(figsize=(12.0, 1.4 + 0.5 * len(labels)), layout='constrained')
    axes = fig.subplots(1, len(CLAIMS), sharey=True)
    colors = VERDICT_COLORS
    spread = np.random.default_rng(0)
    for ax, (metric, _, title) in zip(axes, CLAIMS, strict=True):
        for f in (f for f in found if f['metric'] == metric):
            k, e, color = labels.index(_map_label(f, setting_text(f))), f['estimate'], colors[f['verdict']]
            ax.plot(f['per_map'], k + spread.uniform(-0.25, 0.25, len(f['per_map'])), '.', ms=3, color='0.6')
            ax.hlines(k, e.low, e.high, color=color, lw=3)
            ax.plot(e.value, k, 'o', color=color, mfc=color if f['verdict'] == 'holds' else 'white')
        ax.axvline(0.0, color='k', lw=0.8)
        ax.set_xlabel(f'difference in {title}')
    axes[0].set_yticks(range(len(labels)), labels, fontsize=7)
    axes[0].set_ylim(len(labels) - 0.5, -0.5)
    fig.suptitle("a - b: a dot per map (its seeds' mean), the mean over maps with its 95 % interval", fontsize=9)
    _verdict_legend(fig, {f['verdict'] for f in found})
    return fig


def _map_label(f: dict[str, Any], setting: str) -> str:
    return (
        f'{f["a"]} - {f["b"]}  |  {len(f["per_map"])} {f["map"]} maps, scene {f["scene"]}, N={f["n_robots"]}, {setting}'
    )


def crossover_figure(rows: list[dict[str, Any]], judging: Judging | None = None) -> Figure:
    """The crossover (`vtube_planning.studies.crossover.crossover_cells`): one panel per scene and setting, the
    narrowest half-width down and N across; each cell coloured by planning - best unplanned passing time (blue: the
    plan is faster), marked with it, the verdicts T and D and the collision pairs (planning / best, all seeds),
    framed in black where the plan wins (T holds with 0 collisions)."""
    from matplotlib.figure import Figure

    from vtube_planning.studies.crossover import crossover_cells, sign
    from vtube_planning.studies.judging import POOLED

    cells = crossover_cells(rows, judging or POOLED)
    panels = list(dict.fromkeys((c['scene'], c['setting']) for c in cells))
    scenes = list(dict.fromkeys(scene for scene, _ in panels))
    settings = list(dict.fromkeys(setting for _, setting in panels))
    fig = Figure(figsize=(4.6 * len(settings), 0.6 + 3.0 * len(scenes)), layout='constrained')
    axes = np.array(fig.subplots(len(scenes), len(settings), squeeze=False))
    finite = [abs(c['difference_s']) for c in cells if not np.isnan(c['difference_s'])]
    span = max(finite, default=1.0) or 1.0
    for (scene, setting), ax in ((p, axes[scenes.index(p[0]), settings.index(p[1])]) for p in panels):
        mine = [c for c in cells if (c['scene'], c['setting']) == (scene, setting)]
        widths = sorted({c['narrowest_m'] for c in mine})
        sizes = sorted({c['n_robots'] for c in mine})
        grid = np.full((len(widths), len(sizes)), np.nan)
        for c in mine:
            i, j = widths.index(c['narrowest_m']), sizes.index(c['n_robots'])
            grid[i, j] = c['difference_s']
            text = 'n/a' if np.isnan(c['difference_s']) else f'{c["difference_s"]:+.1f} s'
            text += (
                f'\nT {sign(c["time"])}  D {sign(c["distance"])}\n{c["planned_collisions"]} / {c["best_collisions"]}'
            )
            ax.text(j, i, text, ha='center', va='center', fontsize=7)
            if c['wins']:
                ax.add_patch(_frame(j, i))
        image = ax.imshow(grid, cmap='coolwarm', vmin=-span, vmax=span, aspect='auto')
        ax.set_xticks(range(len(sizes)), [str(n) for n in sizes])
        ax.set_yticks(range(len(widths)), [f'{w:g}' for w in widths])
        ax.set_xlabel('N', fontsize=8)
        ax.set_ylabel('narrowest half-width [m]', fontsize=8)
        ax.set_title(f'scene {scene}, {setting}', fontsize=8)
    for ax in axes.flat:
        if not ax.images:
            ax.set_axis_off()
    if cells:
        fig.colorbar(image, ax=axes.ravel().tolist(), label='planning - best unplanned, passing time [s]')
    fig.suptitle(
        'each cell: planning - best unplanned (mean over seeds), T and D verdicts, collision pairs (planning / '
        'best); black frame: the plan wins (T + with 0 collisions)',
        fontsize=8,
    )
    return fig


def _frame(x: float, y: float) -> Any:
    from matplotlib.patches import Rectangle

    return Rectangle((x - 0.48, y - 0.48), 0.96, 0.96, fill=False, edgecolor='k', lw=2.5)
