"""``main``: the parser built from the commands, dispatch, JSON on stdout alone, errors as exit codes."""

from __future__ import annotations

import dataclasses
import json
import sys
from importlib.metadata import version
from pathlib import Path

import pytest

import vtube
from robotarium_exp.errors import RobotariumExpError
from robotarium_exp.rps.errors import RobotariumError
from tests.support.imports import import_graph
from unicycle_mapping.errors import MappingError
from vtube.cli.app import COMMANDS, GROUPS, command_words, main, parser
from vtube.cli.command import BadInput, Command, Interrupted, View
from vtube_planning.errors import VtubeError

ROOT = Path(__file__).resolve().parents[4]


def fake(run, *, json_: bool = True) -> Command:
    """A command 'fake' that adds --value and runs ``run(args)``; its view prints and returns the result."""

    def arguments(p) -> None:
        p.add_argument('--value', type=int, default=1)

    return Command('fake', 'a test command', arguments, run, lambda r: View((f'got {r}',), {'got': r}), json=json_)


@pytest.fixture
def with_fake(monkeypatch):
    def install(run, **options) -> None:
        monkeypatch.setitem(COMMANDS, 'fake', fake(run, **options))

    return install


def test_every_command_is_reachable_by_its_words(capsys) -> None:
    top = parser()
    for words, command in COMMANDS.items():
        assert command.words == words
        with pytest.raises(SystemExit) as stop:
            top.parse_args([*words.split(), '--help'])
        assert stop.value.code == 0 and capsys.readouterr().out.startswith(f'usage: vtube {words} ')
    first_words = {words.split()[0] for words in COMMANDS}
    assert {words.split()[0] for words in COMMANDS if ' ' in words} == set(GROUPS)
    assert first_words == {
        'scene',
        'tube',
        'plan',
        'simulate',
        'study',
        'ablation',
        'campaign',
        'robotarium',
        'submission',
        'analyze',
        'export',
        'replay',
        'demo',
    }


def test_a_command_runs_and_its_view_is_rendered(with_fake, capsys) -> None:
    seen = []
    with_fake(lambda args: seen.append(args.value) or args.value * 2)
    assert main(['fake', '--value', '4']) == 0
    assert seen == [4] and capsys.readouterr().out == 'got 8\n'


def test_with_json_what_the_command_prints_goes_to_stderr(with_fake, capsys) -> None:
    def run(args) -> int:
        print('working...')
        return 5

    with_fake(run)
    assert main(['fake', '--json']) == 0
    captured = capsys.readouterr()
    assert json.loads(captured.out) == {'got': 5, 'exit_code': 0}
    assert captured.err == 'working...\ngot 5\n'


def test_a_command_without_json_has_no_json_option(with_fake, capsys) -> None:
    with_fake(lambda args: 1, json_=False)
    with pytest.raises(SystemExit) as stop:
        main(['fake', '--json'])
    assert stop.value.code == 2 and 'unrecognized arguments: --json' in capsys.readouterr().err


@pytest.mark.parametrize(
    'error',
    [VtubeError('v'), RobotariumExpError('r'), RobotariumError('rps'), MappingError('m'), OSError('o'), BadInput('b')],
)
def test_refusals_are_one_error_line_and_exit_2(with_fake, capsys, error: Exception) -> None:
    def run(args):
        raise error

    with_fake(run)
    assert main(['fake']) == 2
    captured = capsys.readouterr()
    assert captured.out == '' and captured.err == f'error: {error}\n'


def test_other_errors_are_bugs_and_propagate(with_fake) -> None:
    def run(args):
        raise TypeError('a bug')

    with_fake(run)
    with pytest.raises(TypeError, match='a bug'):
        main(['fake'])


def test_ctrl_c_is_exit_130_with_what_was_kept(with_fake, capsys) -> None:
    def run(args):
        raise Interrupted('interrupted: the rows so far are in x.csv')

    with_fake(run)
    assert main(['fake']) == 130
    assert capsys.readouterr().err == 'interrupted: the rows so far are in x.csv\n'

    def bare(args):
        raise KeyboardInterrupt

    with_fake(bare)
    assert main(['fake']) == 130 and capsys.readouterr().err == 'interrupted.\n'


def test_the_command_line_is_recorded_while_the_command_runs(with_fake, capsys) -> None:
    from vtube_planning.provenance import provenance

    with_fake(lambda args: provenance()['command'])
    assert main(['fake', '--value', '2']) == 0
    assert capsys.readouterr().out == 'got vtube fake --value 2\n'


def test_version_is_the_package_metadata(capsys) -> None:
    with pytest.raises(SystemExit) as exit_info:
        main(['--version'])
    assert exit_info.value.code == 0 and capsys.readouterr().out.strip() == f'vtube {version("vtube")}'
    assert vtube.__version__ == version('vtube')


def test_help_shows_defaults_and_exit_codes(capsys) -> None:
    with pytest.raises(SystemExit):
        main(['simulate', '--help'])
    text = ' '.join(capsys.readouterr().out.split())
    assert 'seed of the initial formation jitter, >= 0 (default: 0)' in text
    assert 'exit codes: 0 done, every check held; 1 a check or claim failed; 2 bad input' in text
    assert '(default: None)' not in text and '(default: False)' not in text


def test_the_command_line_imports_nothing_heavy_before_a_command_runs() -> None:
    """What ``import vtube.cli`` runs (module bodies, parents included; not functions, not TYPE_CHECKING) imports
    the standard library only: numpy, scipy, cvxpy and matplotlib wait until a command runs (`vtube --version`)."""
    graph = import_graph(ROOT, at_import_only=True)
    reached, todo = set(), ['vtube.cli']
    while todo:
        name = todo.pop()
        if name in reached:
            continue
        reached.add(name)
        parts = name.split('.')
        todo += [*graph[name][0], *('.'.join(parts[:k]) for k in range(1, len(parts)))]
    assert {'vtube', 'vtube.cli.app', 'vtube.cli.plan', 'vtube_planning'} <= reached
    assert 'vtube.pipeline' not in reached and 'vtube_planning.planning.planner' not in reached
    outside = {name: sorted(graph[name][1] - set(sys.stdlib_module_names)) for name in reached}
    assert not {name: found for name, found in outside.items() if found}


def test_the_words_on_the_command_line_name_one_command() -> None:
    assert command_words(['plan', 'A', '--out', 'x']) == 'plan'
    assert command_words(['scene', 'show', 'A']) == 'scene show'
    assert command_words(['robotarium', 'sweep', 'robotarium_curve']) == 'robotarium sweep'
    for nothing in ([], ['--version'], ['--help'], ['scene'], ['scene', '--help'], ['nope', 'x'], ['scene', 'nope']):
        assert command_words(nothing) is None


def test_only_the_named_commands_options_are_built(capsys, monkeypatch) -> None:
    built = []

    def counted(name: str, arguments):
        def counting(p) -> None:
            built.append(name)
            arguments(p)

        return counting

    for name, command in list(COMMANDS.items()):
        monkeypatch.setitem(COMMANDS, name, dataclasses.replace(command, arguments=counted(name, command.arguments)))
    with pytest.raises(SystemExit):
        main(['plan', 'A', '--grid-step', '-1', '--out', 'x'])
    assert built == ['plan'] and "argument --grid-step: '-1' is not a number > 0" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(['--help'])
    assert built == ['plan'] and 'plan speed and density' in capsys.readouterr().out
    parser()
    assert sorted(built) == sorted(['plan', *COMMANDS])  # the CLI reference builds them all
