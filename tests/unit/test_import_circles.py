"""No circle of imports among the modules of the five packages.

Every import counts: at the top, inside a function (a lazy import is still an arrow) and under ``TYPE_CHECKING`` (a
type one module needs from another is an arrow too, and the contracts of pyproject.toml, which leave those out,
cannot see it). An import names a module (``from a.b import c`` names ``a.b.c`` when that is a module, else ``a.b``);
a package is its ``__init__``. The circles are the strongly connected components of that graph with more than one
module (Tarjan's algorithm), or a module that imports itself.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from pathlib import Path

from tests.support.imports import import_graph

ROOT = Path(__file__).resolve().parents[2]


def strongly_connected(graph: Mapping[str, set[str]]) -> Iterator[list[str]]:
    """Tarjan's strongly connected components of ``graph``, each sorted; iterative (no recursion limit)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    for start in sorted(graph):
        if start in index:
            continue
        work = [(start, iter(sorted(graph[start])))]
        index[start] = low[start] = len(index)
        stack.append(start)
        on_stack.add(start)
        while work:
            node, edges = work[-1]
            child = next((w for w in edges if w in graph), None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                yield sorted(component)


def circles(graph: Mapping[str, set[str]]) -> list[list[str]]:
    """The import circles: components of more than one module, and modules importing themselves."""
    return [c for c in strongly_connected(graph) if len(c) > 1 or c[0] in graph[c[0]]]


def test_tarjan_finds_the_circles_of_a_known_graph() -> None:
    graph = {
        'a': {'b'},
        'b': {'c'},
        'c': {'a', 'd'},  # a -> b -> c -> a
        'd': {'e'},
        'e': {'d', 'f'},  # d <-> e
        'f': set(),
        'g': {'g'},  # itself
        'h': {'f', 'outside'},  # an arrow out of the graph is not followed
    }
    assert sorted(circles(graph)) == [['a', 'b', 'c'], ['d', 'e'], ['g']]
    assert circles({'x': {'y'}, 'y': set()}) == []
    chain = {f'm{k:05d}': {f'm{k + 1:05d}'} for k in range(5000)} | {'m05000': {'m00000'}}
    assert [len(c) for c in circles(chain)] == [5001]  # deep: no recursion


def test_every_form_of_import_is_an_arrow(tmp_path) -> None:
    package = tmp_path / 'pkg'
    (package / 'sub').mkdir(parents=True)
    (package / '__init__.py').write_text('', encoding='utf-8')
    (package / 'sub' / '__init__.py').write_text('from . import leaf\n', encoding='utf-8')
    (package / 'sub' / 'leaf.py').write_text('def f():\n    from ..top import g\n', encoding='utf-8')
    (package / 'top.py').write_text(
        'from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    import pkg.sub.leaf\nfrom pkg import sub\n',
        encoding='utf-8',
    )
    graph = {name: ours for name, (ours, _) in import_graph(tmp_path, ('pkg',)).items()}
    assert graph == {
        'pkg': set(),
        'pkg.sub': {'pkg.sub.leaf'},
        'pkg.sub.leaf': {'pkg.top'},
        'pkg.top': {'pkg.sub.leaf', 'pkg.sub'},
    }
    assert circles(graph) == [['pkg.sub', 'pkg.sub.leaf', 'pkg.top']]  # top -> sub -> leaf -> top


def test_no_import_circles_among_the_packages() -> None:
    graph = {name: ours for name, (ours, _) in import_graph(ROOT).items()}
    assert {'vtube.cli', 'vtube_planning.onboard.law', 'submission.builder'} <= set(graph)
    found = circles(graph)
    assert not found, (
        f'{len(found)} import circle(s); move what both sides need into a module below them:\n  '
        + '\n  '.join(' <-> '.join(c) for c in found)
    )
