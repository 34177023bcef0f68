"""The documentation site builds with ``mkdocs build --strict`` (every warning an error: a broken link, a missing
API reference, a tutorial's code block that raises), and a tutorial that breaks fails the build."""

from __future__ import annotations

import html
import os
import re
import subprocess
import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[2]


def page_text(site: Path, page: str) -> str:
    """A built page's text, without its tags."""
    source = (site / page / 'index.html').read_text(encoding='utf-8')
    return html.unescape(re.sub(r'<[^>]+>', '', source))


def mkdocs_build(folder: Path, site: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, 'NO_MKDOCS_2_WARNING': '1', 'MPLBACKEND': 'Agg'}
    return subprocess.run(
        [sys.executable, '-m', 'mkdocs', 'build', '--strict', '-d', str(site)],
        check=False,
        cwd=folder,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )


def test_the_site_builds_strictly_with_its_tutorials_run(tmp_path: Path) -> None:
    built = mkdocs_build(ROOT, tmp_path / 'site')
    assert built.returncode == 0, built.stderr[-4000:]
    assert 'WARNING' not in built.stderr
    site = tmp_path / 'site'
    api = page_text(site, 'tutorials/python_api')  # the blocks ran: their output is on the page
    assert 'traversal time' in api and 'certified: True' in api and 'with the plan: passing time' in api
    assert '<svg' in (site / 'tutorials' / 'python_api' / 'index.html').read_text(encoding='utf-8')
    assert "robots: ('r1', 'r2', 'r3')" in page_text(site, 'tutorials/bag_analysis')
    reference = page_text(site, 'api/vtube_planning')
    assert 'plan_convex' in reference and 'convex-concave procedure' in reference  # the docstring, rendered
    campaign = page_text(site, 'tutorials/campaign')  # the campaign ran, and its report is on the page
    assert '$ vtube campaign run small.toml' in campaign and '4 runs, 0 already done, 4 run now' in campaign
    assert '4 runs, 4 already done, 0 run now' in campaign and 'Scene C, N = 6' in campaign
    assert 'vtube robotarium compare' in page_text(site, 'howto/cli')
    assert_no_sphinx_roles(site)


def assert_no_sphinx_roles(site: Path) -> None:
    """The API pages show no Sphinx role: the docstrings are markdown, and the roles of the modules the builder
    inlines verbatim are rewritten by docs/hooks/griffe_roles.py."""
    pages = sorted(path.stem for path in (ROOT / 'docs' / 'api').glob('*.md'))
    assert 'vtube_planning' in pages and 'submission' in pages
    for page in pages:
        text = page_text(site, f'api/{page}')
        roles = re.findall(r'.{0,40}:(?:func|class|meth|mod|attr|data|exc|obj|const):`.{0,40}', text)
        assert not roles, (page, roles[:5])
    reference = page_text(site, 'api/vtube_planning')  # SwarmStep's docstring, from a verbatim module
    assert 'StepTube' in reference and 'With params.compensates the step acts' in reference


def test_a_tutorial_block_that_raises_fails_the_build(tmp_path: Path) -> None:
    (tmp_path / 'docs').mkdir()
    (tmp_path / 'docs' / 'index.md').write_text(
        '# Broken\n\n```python exec="on" session="t"\nraise RuntimeError("this tutorial broke")\n```\n',
        encoding='utf-8',
    )
    config = 'site_name: broken\nplugins:\n  - markdown-exec\nmarkdown_extensions:\n  - pymdownx.superfences\n'
    (tmp_path / 'mkdocs.yml').write_text(config, encoding='utf-8')
    built = mkdocs_build(tmp_path, tmp_path / 'site')
    assert built.returncode != 0
    assert 'this tutorial broke' in built.stderr


def test_the_test_extra_holds_what_the_docs_build_needs() -> None:
    extras = tomllib.loads((ROOT / 'pyproject.toml').read_text(encoding='utf-8'))['project']['optional-dependencies']
    assert extras['docs'] and set(extras['docs']) <= set(extras['test'])
