"""The distribution ships every package of the source tree (a non-editable install once lacked robotarium_exp.rps),
and nothing else (``submissions/`` once shipped as a namespace package)."""

from __future__ import annotations

import ast
import fnmatch
import importlib
import json
import os
import pkgutil
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

if sys.version_info >= (3, 11):
    import tomllib
else:
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = ('vtube', 'vtube_planning', 'unicycle_mapping', 'robotarium_exp', 'submission')


def test_every_package_matches_the_include_patterns() -> None:
    config = tomllib.loads((ROOT / 'pyproject.toml').read_text(encoding='utf-8'))
    patterns = config['tool']['setuptools']['packages']['find']['include']
    packages = sorted(
        '.'.join(p.parent.relative_to(ROOT).parts)
        for p in ROOT.rglob('__init__.py')
        if p.parent.relative_to(ROOT).parts[0] not in ('tests', 'benchmarks', '.venv', 'build')
    )
    assert 'robotarium_exp.rps.utilities' in packages
    missing = [name for name in packages if not any(fnmatch.fnmatch(name, pattern) for pattern in patterns)]
    assert missing == []
    data = config['tool']['setuptools']['package-data']
    assert (ROOT / 'submission' / 'server_libraries.txt').exists() and 'server_libraries.txt' in data['submission']


def test_the_wheel_ships_the_five_packages_and_not_the_generated_files(tmp_path: Path) -> None:
    source = tmp_path / 'source'
    for name in (*SHIPPED, 'submissions'):
        shutil.copytree(ROOT / name, source / name, ignore=shutil.ignore_patterns('__pycache__'))
    for name in ('pyproject.toml', 'README.md'):
        shutil.copy(ROOT / name, source)
    pip = [sys.executable, '-m', 'pip', '--disable-pip-version-check', '--quiet']
    subprocess.run(
        [*pip, 'wheel', '--no-deps', '--wheel-dir', str(tmp_path), str(source)],
        check=True,
        timeout=600,
    )
    (wheel,) = tmp_path.glob('vtube-*.whl')
    with zipfile.ZipFile(wheel) as archive:
        names = set(archive.namelist())
    top_level = {name.split('/')[0] for name in names}
    assert top_level == {*SHIPPED, f'{wheel.name.split("-py")[0]}.dist-info'}
    # `vtube campaign example` reads these: an installed package has no docs/
    assert {f'vtube/examples/{n}.toml' for n in ('faults', 'delay', 'replanning')} <= names
    # and these `vtube tube example`
    assert {f'vtube/maps/robotarium_{n}.toml' for n in ('discs', 'gate', 'staggered')} <= names
    # a first build of a shipped scene takes its formation's initializer durations from here (submission.shipped)
    assert 'submission/shipped_initializer_durations.json' in names

    target = tmp_path / 'installed'
    subprocess.run([*pip, 'install', '--no-deps', '--target', str(target), str(wheel)], check=True, timeout=600)

    def run(code: str) -> subprocess.CompletedProcess[str]:  # -S: no site-packages, so no editable install of ours
        env = {**os.environ, 'PYTHONPATH': str(target)}
        return subprocess.run(
            [sys.executable, '-S', '-c', code], check=False, cwd=tmp_path, env=env, capture_output=True, text=True
        )

    assert run('import submission, vtube_planning; print(vtube_planning.__version__)').returncode == 0
    listed = (
        'from importlib import resources; '
        'print(sorted(p.name for p in (resources.files("vtube") / "examples").iterdir()))'
    )
    examples = run(listed)  # what vtube.cli.example.campaign_examples reads, in the installed package
    assert examples.stdout.strip() == "['delay.toml', 'faults.toml', 'replanning.toml']", examples.stderr
    missing = run('import submissions')
    assert missing.returncode != 0 and 'ModuleNotFoundError' in missing.stderr


API = (
    'vtube_planning',
    'vtube_planning.geometry',
    'vtube_planning.planning',
    'vtube_planning.swarm',
    'robotarium_exp',
    'robotarium_exp.analysis',
    'submission',
    'unicycle_mapping',
)
"""The packages with a curated public API (``__all__``)."""


@pytest.mark.parametrize('name', API)
def test_a_package_exports_what_its_imports_name(name: str) -> None:
    package = importlib.import_module(name)
    source = Path(package.__file__ or '').read_text(encoding='utf-8')
    origins = {
        alias.asname or alias.name: node.module
        for node in ast.walk(ast.parse(source))
        if isinstance(node, ast.ImportFrom) and node.module and node.module.split('.')[0] in SHIPPED
        if node.module != 'vtube_planning._lazy'
        for alias in node.names
    }
    assert set(origins) == set(package.__all__) - {'__version__'}
    for exported, module in origins.items():
        assert getattr(package, exported) is getattr(importlib.import_module(module), exported)
    submodules = {info.name for info in pkgutil.iter_modules(package.__path__)}
    assert not submodules & set(package.__all__)  # a submodule's import would rebind the name


def test_importing_the_packages_imports_none_of_their_modules() -> None:
    code = 'import json, sys, robotarium_exp, submission, vtube_planning; print(json.dumps(list(sys.modules)))'
    result = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True, check=True)
    loaded = set(json.loads(result.stdout))
    assert {'vtube_planning', 'robotarium_exp', 'submission'} <= loaded
    assert not loaded & {'cvxpy', 'matplotlib', 'scipy', 'numpy', 'vtube_planning.geometry', 'robotarium_exp.rps'}
