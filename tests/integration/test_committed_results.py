"""The results committed beside the code are what the code as it is produces (`vtube campaign verify` on a slice).

Each committed campaign folder has one run made again (the middle of its table) and its report written again from
its table, both compared with what is committed: a change to the code that changes a committed result fails here,
until the campaign is run again at that commit (the full check: `vtube campaign verify FOLDER`)."""

from __future__ import annotations

from pathlib import Path

import pytest

from vtube_planning.studies.campaign_verify import verify

DOCS = Path(__file__).resolve().parents[2] / 'docs'
VERIFIED = ('maps_study', 'maps_study_limits', 'ablation', 'replanning', 'faults', 'foresight', 'equal_freedom')
VERIFIED += ('crossover_reduced',)
"""The committed campaign folders made at a commit whose code gives them (docs/delay predates the verdict rules)."""


@pytest.mark.parametrize('folder', VERIFIED)
def test_a_committed_campaign_is_what_the_code_produces(folder: str) -> None:
    found = verify(DOCS / folder, runs=1, workers=1)
    assert found.checked == 1 and found.report_matches is True, f'{folder}/report.md is not what its table gives now'
    assert not found.differences, f'{folder}: {found.differences}'
