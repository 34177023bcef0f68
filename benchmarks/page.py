"""Run benchmarks and write each one's page of the documentation site: what it measures, what made it, what it printed.

    python -m benchmarks.page bench_projection sim_bench [--args "sim_bench=--sizes 20,200"] [--out docs/benchmarks]

Each NAME runs as ``python -m benchmarks.NAME [ARGS]`` in a child process from the repository root. Its page,
``OUT/NAME.md``, holds the module's docstring (what it measures and how), the command, the vtube version, the git
commit of the code (``-dirty`` when it differs from that commit), the date, the machine's cores and its load average
when the benchmark ended (above the cores, other work shared them: ratios measured in one process hold, absolute
times do not), then what the benchmark printed, verbatim. ``OUT/index.md`` lists every page in OUT with its first
line and when it was made; ``--rewrite`` writes every page again from the run it records (after a docstring
changed), without running anything.
The pages are never edited by hand: run the command again. A benchmark that fails writes no page, its output is
printed, and the command exits 1.
"""

from __future__ import annotations

import argparse
import ast
import datetime
import os
import shlex
import subprocess
import sys
from pathlib import Path

from vtube_planning.files import write_atomically
from vtube_planning.provenance import source_commit

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / 'docs' / 'benchmarks'
MADE = '<!-- made by python -m benchmarks.page: '
"""The first line of every page: the index reads the command and the date from it."""


def docstring(name: str) -> str:
    """The benchmark module's docstring, read without importing it; refused when there is no such benchmark."""
    path = ROOT / 'benchmarks' / f'{name}.py'
    if not path.is_file() or name.startswith('_') or name == 'page':
        known = sorted(p.stem for p in path.parent.glob('*.py') if not p.stem.startswith('_') and p.stem != 'page')
        msg = f'no benchmark {name!r}; give one of: {", ".join(known)}.'
        raise SystemExit(msg)
    return ast.get_docstring(ast.parse(path.read_text(encoding='utf-8'))) or ''


def page_text(name: str, args: list[str], printed: str, made: str) -> str:
    """The page of one benchmark run: its docstring, what made it, and its output as a block of text."""
    command = shlex.join(['python', '-m', f'benchmarks.{name}', *args])
    doc = docstring(name)
    title, _, rest = doc.partition('\n')
    fence = '````' if '```' in printed else '```'
    return (
        f'{MADE}{command} | {made} -->\n# {name}: {title.strip()}\n\n{rest.strip(chr(10)).rstrip()}\n\n'
        f'Made by `{command}` ({made}). What it printed:\n\n{fence}text\n{printed.rstrip()}\n{fence}\n'
    )


def recorded(page: Path) -> tuple[list[str], str, str]:
    """What a page records of its run: the benchmark's arguments, what it printed and what made it (`page_text`'s
    layout read back), so that the page can be written again around a newer docstring without running again."""
    text = page.read_text(encoding='utf-8')
    first = text.split('\n', 1)[0]
    if not first.startswith(MADE):
        msg = f'{page} was not written by benchmarks.page (its first line is not {MADE!r}...); run the benchmark.'
        raise SystemExit(msg)
    command, made = first.removeprefix(MADE).removesuffix(' -->').split(' | ', 1)
    fence = '````' if '\n````text\n' in text else '```'
    printed = text.split(f'\n{fence}text\n', 1)[1].rsplit(f'\n{fence}\n', 1)[0]
    return shlex.split(command)[3:], printed, made


def index_text(out: Path) -> str:
    """The index of the pages in ``out``: each with its title and the line saying what made it."""
    lines = [
        '# Benchmarks',
        '',
        'Each page was written by `python -m benchmarks.page NAME`: what the benchmark measures,',
    ]
    lines += ['what made the page, and what the benchmark printed. Run the command again to make it anew.', '']
    for page in sorted(out.glob('*.md')):
        if page.name == 'index.md':
            continue
        first, title = page.read_text(encoding='utf-8').split('\n', 2)[:2]
        made = first.removeprefix(MADE).removesuffix(' -->').split(' | ', 1)[-1]
        lines.append(f'- [{title.removeprefix("# ")}]({page.name}) ({made})')
    if not lines[-1].startswith('- '):
        lines.append('No benchmark has a page yet.')
    return '\n'.join(lines) + '\n'


def made_now() -> str:
    from vtube import __version__

    stamp = datetime.datetime.now(datetime.timezone.utc).strftime('%Y-%m-%d %H:%M UTC')
    load = os.getloadavg()[0]
    return (
        f'vtube {__version__}, commit {source_commit() or "unknown"}, {stamp}, {os.cpu_count()} cores, load {load:.1f}'
    )


def run(name: str, args: list[str]) -> subprocess.CompletedProcess[str]:
    command = [sys.executable, '-m', f'benchmarks.{name}', *args]
    return subprocess.run(command, cwd=ROOT, capture_output=True, text=True, check=False)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.partition('\n')[0])
    parser.add_argument(
        'names', nargs='*', help='benchmarks to run (module names under benchmarks/; none: the index only)'
    )
    parser.add_argument('--args', action='append', default=[], help='NAME=ARGS: arguments for one benchmark')
    parser.add_argument('--out', type=Path, default=OUT, help='the folder of the pages (default: docs/benchmarks)')
    parser.add_argument(
        '--rewrite', action='store_true', help='write every page in OUT again from what it records, without running'
    )
    options = parser.parse_args(argv)
    if options.rewrite:
        for page in sorted(options.out.glob('*.md')):
            if page.name != 'index.md':
                args, printed, made = recorded(page)
                write_atomically(page, page_text(page.stem, args, printed, made))
    extra = dict(item.split('=', 1) for item in options.args)
    for name in options.names:
        docstring(name)  # refuse an unknown name before anything runs
    options.out.mkdir(parents=True, exist_ok=True)
    failed = 0
    for name in options.names:
        args = shlex.split(extra.get(name, ''))
        done = run(name, args)
        if done.returncode != 0:
            print(f'benchmarks.{name} failed (exit {done.returncode}); no page written:\n{done.stdout}{done.stderr}')
            failed += 1
            continue
        made = made_now()
        write_atomically(options.out / f'{name}.md', page_text(name, args, done.stdout, made))
        print(f'written {options.out / f"{name}.md"}')
    write_atomically(options.out / 'index.md', index_text(options.out))
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
