"""Every package of the source tree ships in the distribution (a non-editable install once lacked robotarium_exp.rps)."""

from __future__ import annotations

import fnmatch
import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]


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
