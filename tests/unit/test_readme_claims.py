"""The README's claims quote the committed reports: every verdict count it quotes (like `T +6 =0 -0`) is in the
report its paragraph links to, in the row it names (`row "paper model, radial sat"`), so a report written again
with other verdicts fails here until the README says what the report says."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CODE = re.compile(r'`([TD] \+\d+ =\d+ -\d+(?: [~?]\d+)*)`')
LINK = re.compile(r'\]\((docs/[\w/]+\.md)\)')
ROW = re.compile(r'row "([^"]+)"')


def section() -> str:
    text = (ROOT / 'README.md').read_text(encoding='utf-8')
    start = text.index('## What the method buys, as measured')
    return text[start : text.index('\n## ', start + 1)]


def quoted() -> list[tuple[str, str | None, str]]:
    """Each verdict count quoted: the report last linked before it, the row last named since that link, the count."""
    found = []
    report, row = None, None
    for match in re.finditer(f'{LINK.pattern}|{ROW.pattern}|{CODE.pattern}', section()):
        link, named, code = match.groups()
        if link:
            report, row = link, None
        elif named:
            row = named
        else:
            assert report is not None, f'{code} is quoted before any report is linked'
            found.append((report, row, code))
    return found


def test_every_verdict_count_the_readme_quotes_is_in_its_report_row() -> None:
    claims = quoted()
    assert len(claims) >= 10 and {report for report, _, _ in claims} >= {'docs/ablation/report.md'}
    for report, row, code in claims:
        lines = (ROOT / report).read_text(encoding='utf-8').splitlines()
        rows = [line for line in lines if line.startswith(f'| {row} |')] if row else lines
        assert rows, f'{report} has no row "{row}"'
        assert any(code in line for line in rows), f'the README quotes {code} from {report} ({row}); it says otherwise'


def test_a_count_the_report_does_not_hold_is_caught() -> None:
    """The check itself: a count changed by one is not in the row."""
    report, row, code = quoted()[0]
    wrong = re.sub(r'\+(\d+)', lambda m: f'+{int(m.group(1)) + 1}', code, count=1)
    lines = (ROOT / report).read_text(encoding='utf-8').splitlines()
    assert not any(wrong in line for line in lines if line.startswith(f'| {row} |'))
