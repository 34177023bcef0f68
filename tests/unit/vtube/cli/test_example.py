"""``vtube campaign example``: the README's campaigns ship with the package and are written where the user is."""

from __future__ import annotations

from pathlib import Path

from vtube.cli.app import main
from vtube.cli.example import ExampleWritten, campaign_examples, example_view
from vtube_planning.studies.campaign import Campaign

ROOT = Path(__file__).resolve().parents[4]


def test_the_shipped_campaigns_are_the_readmes() -> None:
    shipped = campaign_examples()
    assert set(shipped) == {'faults', 'delay', 'replanning'}
    for name, text in shipped.items():
        # the same campaign as the repository's file the README ran, header comment aside
        docs = (ROOT / 'docs' / name / 'campaign.toml').read_text(encoding='utf-8')
        assert text.splitlines()[2:] == docs.splitlines()[1:], name
        assert f'vtube campaign example {name} FILE.toml' in text


def test_an_example_written_reads_as_the_repositorys_campaign_and_is_never_overwritten(tmp_path, capsys) -> None:
    path = tmp_path / 'mine' / 'faults.toml'
    assert main(['campaign', 'example', 'faults', str(path)]) == 0
    assert capsys.readouterr().out == example_view(ExampleWritten('faults', path)).lines[0] + '\n'
    assert Campaign.from_toml(path) == Campaign.from_toml(ROOT / 'docs' / 'faults' / 'campaign.toml')
    path.write_text('mine', encoding='utf-8')
    assert main(['campaign', 'example', 'delay', str(path)]) == 2
    assert path.read_text(encoding='utf-8') == 'mine'
    assert 'exists' in capsys.readouterr().err


def test_the_help_of_campaign_run_names_the_command_that_writes_a_file(capsys) -> None:
    try:
        main(['campaign', 'run', '--help'])
    except SystemExit as done:
        assert done.code == 0
    help_text = ' '.join(capsys.readouterr().out.split())
    assert 'vtube campaign example faults FILE.toml' in help_text and 'docs/' not in help_text
