"""The import contracts of pyproject.toml hold for the tree, and each one fails on an import that breaks its rule."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[2]
CONFIG = tomllib.loads((ROOT / 'pyproject.toml').read_text(encoding='utf-8'))
CONTRACTS = {contract['name']: contract for contract in CONFIG['tool']['importlinter']['contracts']}
PACKAGES = CONFIG['tool']['importlinter']['root_packages']

BREAKS = {
    'The packages: vtube > submission > robotarium_exp > vtube_planning | unicycle_mapping': (
        'vtube_planning/geometry/width.py',
        'import robotarium_exp',
    ),
    "vtube_planning's rooms: geometry < planning < swarm < baselines < the studies, plots": (
        'vtube_planning/geometry/centerline.py',
        'import vtube_planning.planning.plan',
    ),
    "The studies' room: stats, seeds < judging < study < campaign, reports < store, executors < runner < verify": (
        'vtube_planning/studies/stats.py',
        'import vtube_planning.studies.campaign',
    ),
    "geometry's rooms: the tube < its obstacles < scene < tubes from maps": (
        'vtube_planning/geometry/regularity.py',
        'import vtube_planning.geometry.scene',
    ),
    "robotarium_exp's rooms: rps < rps_classic < the experiment's modules": (
        'robotarium_exp/rps_classic/utilities/misc.py',
        'import robotarium_exp.spec',
    ),
    'rps and rps_classic stand alone: nothing of vtube_planning, submission, vtube': (
        'robotarium_exp/rps_classic/utilities/graph.py',
        'import vtube_planning.geometry.tube',
    ),
    'Tubes from maps: maps, map_file > generate > centre_path > tube_spec': (
        'vtube_planning/geometry/from_maps/tube_spec.py',
        'import vtube_planning.geometry.from_maps.centre_path',
    ),
    "The analysis's report: report > plots > metrics": (
        'robotarium_exp/analysis/metrics.py',
        'import robotarium_exp.analysis.plots',
    ),
    'The analysis and the experiment are independent': (
        'robotarium_exp/analysis/distances.py',
        'import robotarium_exp.experiment',
    ),
    'The modules the submission inlines import only numpy, scipy and each other': (
        'vtube_planning/onboard/projection.py',
        'import matplotlib',
    ),
}
"""For each contract, a module and an import that breaks it (and no other contract)."""


def lint_imports(tree: Path) -> subprocess.CompletedProcess[str]:
    """``lint-imports`` on the packages under ``tree`` (first on the path) with ``tree``'s pyproject.toml."""
    command = 'import sys; from importlinter.cli import lint_imports_command; sys.exit(lint_imports_command())'
    return subprocess.run(
        [sys.executable, '-c', command, '--no-cache'],
        check=False,
        cwd=tree,
        env={**os.environ, 'PYTHONPATH': str(tree), 'PYTHONDONTWRITEBYTECODE': '1'},
        capture_output=True,
        text=True,
        timeout=120,
    )


def verdicts(output: str) -> dict[str, str]:
    """Each contract's KEPT or BROKEN from the report (names may wrap over lines)."""
    flat = ' '.join(output.split())
    return {
        name: match.group(1) for name in CONTRACTS if (match := re.search(re.escape(name) + r' (KEPT|BROKEN)', flat))
    }


def test_the_tree_keeps_every_contract() -> None:
    result = lint_imports(ROOT)
    assert result.returncode == 0, result.stdout + result.stderr
    assert verdicts(result.stdout) == dict.fromkeys(CONTRACTS, 'KEPT')


def test_each_contract_breaks_on_a_forbidden_import(tmp_path: Path) -> None:
    assert set(BREAKS) == set(CONTRACTS)
    for package in PACKAGES:
        shutil.copytree(ROOT / package, tmp_path / package, ignore=shutil.ignore_patterns('__pycache__'))
    shutil.copy(ROOT / 'pyproject.toml', tmp_path)
    for module, line in BREAKS.values():
        with (tmp_path / module).open('a', encoding='utf-8') as file:
            file.write(f'\n{line}\n')
    result = lint_imports(tmp_path)
    assert result.returncode != 0
    assert verdicts(result.stdout) == dict.fromkeys(CONTRACTS, 'BROKEN'), result.stdout
    flat = ' '.join(result.stdout.split())  # the report wraps long lines
    for module, line in BREAKS.values():
        importer = module.removesuffix('.py').replace('/', '.')
        assert f'{importer} -> {line.split()[1]}' in flat


def test_the_inlined_modules_may_import_no_dependency_but_numpy_and_scipy() -> None:
    project = CONFIG['project']
    extras = [
        req for name, reqs in project['optional-dependencies'].items() if name not in ('test', 'docs') for req in reqs
    ]
    dependencies = {re.split(r'[<>=!~;\[ ]', req, maxsplit=1)[0].lower() for req in project['dependencies'] + extras}
    forbidden = CONTRACTS['The modules the submission inlines import only numpy, scipy and each other']
    assert dependencies - {'numpy', 'scipy'} <= set(forbidden['forbidden_modules'])
