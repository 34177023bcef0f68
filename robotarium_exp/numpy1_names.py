"""numpy 1's names that numpy 2 removed and classic-era Robotarium scripts still use, given back on request.

Several classic scripts build their start poses and goals with ``np.mat('...')``, and others write ``np.float_``,
``np.Inf`` or ``np.NaN``; numpy 2 removed those names (NEP 52), so such a script fails on a fresh install on every
simulator, the official classic included (which cannot run on today's numpy and matplotlib at all). `provide` puts
each missing name back on the ``numpy`` module as what numpy 1 had under it: the same object numpy 2 still has
under its own name (``np.mat`` is ``np.asmatrix``, ``np.float_`` is ``np.float64``...). Nothing else changes: no
numpy behaviour, no other module. ``python -m robotarium_exp.rps_alias --numpy1-names script.py`` does it for one
run and says so on stderr.
"""

from __future__ import annotations

from types import ModuleType

NUMPY1_NAMES: dict[str, str] = {
    'mat': 'asmatrix',
    'float_': 'float64',
    'complex_': 'complex128',
    'Inf': 'inf',
    'Infinity': 'inf',
    'infty': 'inf',
    'PINF': 'inf',
    'NaN': 'nan',
    'round_': 'round',
    'product': 'prod',
    'cumproduct': 'cumprod',
    'sometrue': 'any',
    'alltrue': 'all',
    'string_': 'bytes_',
    'unicode_': 'str_',
}
"""Each removed name and the numpy 2 name of the very object numpy 1 had under it (numpy 1.26's aliases)."""


def missing(numpy: ModuleType) -> dict[str, str]:
    """The names of `NUMPY1_NAMES` that ``numpy`` lacks (all of them on numpy 2, none on numpy 1), with their
    numpy 2 names."""
    return {old: new for old, new in NUMPY1_NAMES.items() if old not in vars(numpy)}


def provide(numpy: ModuleType) -> dict[str, str]:
    """Put every missing name of `NUMPY1_NAMES` on ``numpy`` as the object numpy 1 had under it; what was added."""
    added = missing(numpy)
    for old, new in added.items():
        setattr(numpy, old, getattr(numpy, new))
    return added


def notice(added: dict[str, str], version: str) -> str:
    """The stderr line of ``--numpy1-names``: what was added, as what, and that nothing else changes."""
    if not added:
        return f'rps_alias: --numpy1-names: numpy {version} has numpy 1 names already; nothing added.'
    names = ', '.join(f'np.{old} (= np.{new})' for old, new in added.items())
    return (
        f'rps_alias: --numpy1-names: numpy {version} lacks names numpy 1 had; provided for this run: {names}. '
        'Nothing else changes.'
    )
