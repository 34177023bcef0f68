"""A reduced form of the paper's study: planning passes faster and safer than no planning and the baselines."""

from __future__ import annotations

from vtube_planning.params import SwarmParams
from vtube_planning.studies.campaign import Campaign
from vtube_planning.studies.campaign_runner import run_campaign
from vtube_planning.studies.paper_report import summarise
from vtube_planning.studies.study import MODES


def test_reduced_study_reproduces_the_papers_claim(tmp_path) -> None:
    """The full study (scenes A-D, 5 seeds, flocking on C and D) runs in `vtube study --baselines`; here A and D, seed 0."""
    grids = ({'scene': ('A', 'D'), 'mode': MODES}, {'scene': ('D',), 'mode': ('flocking', 'flocking (v_min)')})
    summary = summarise(run_campaign(Campaign(grids), tmp_path, progress=False).rows)
    assert summary[0]['modes'] == ['planning', 'no planning']  # baselines only on the rapid scenes
    assert summary[1]['modes'] == ['planning', 'no planning', 'flocking', 'flocking (v_min)']
    assert summary[1]['flocking']['collision_pairs'] > 0 and summary[1]['safer_than']['flocking']
    for entry in summary:
        planned, unplanned = entry['planning'], entry['no planning']
        assert planned['completed'] and unplanned['completed']
        assert planned['passing_time_s'] < unplanned['passing_time_s']
        assert planned['min_distance_m'] > unplanned['min_distance_m']
        assert planned['collision_pairs'] == 0 and planned['min_distance_m'] >= 2 * SwarmParams().r_p_m
        assert entry['claim_on_means']
