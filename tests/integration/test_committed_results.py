"""The results committed beside the code are what the code as it is produces (`vtube campaign verify` on a slice).

Each committed campaign folder has one run made again (the middle of its table) and its report written again from
its table, both compared with what is committed: a change to the code that changes a committed result fails here,
until the campaign is run again at that commit (the full check: `vtube campaign verify FOLDER`).

The foresight's runs amplify the last bits that numpy's SIMD loops and OpenBLAS's kernels leave (a passing time
0.04 s apart between an AVX-512 machine and one whose numpy stops at X86_V3): its campaigns are made in one machine
kind, `KIND` (the regression harness's golden one), and made again in that kind here, in a process of their own
that emulates it where this machine is another kind."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support.regression import environment
from vtube_planning.studies.campaign_verify import verify

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / 'docs'
VERIFIED = ('maps_study', 'maps_study_limits', 'ablation', 'replanning', 'faults', 'foresight', 'equal_freedom')
VERIFIED += ('crossover_reduced', 'crossover')
"""The committed campaign folders made at a commit whose code gives them (docs/delay predates the verdict rules)."""
MADE_IN_KIND = ('foresight', 'crossover_reduced', 'crossover', 'ablation', 'replanning', 'faults')
"""The folders checked in the machine kind `KIND` (on an AVX-512 machine: `kind_settings`' variables): the ones made
in it (the crossovers: their foresight rows), and ablation, replanning and faults, which AVX-512 SkylakeX and
Haswell give alike but an AMD EPYC's AVX-512 ICL loops do not (a density error 4e-10 relative apart)."""
KIND = {'numpy_simd': 'X86_V2 X86_V3', 'openblas_core': 'Haswell'}
"""numpy's loops up to X86_V3 and OpenBLAS's Haswell kernels."""
VERIFY = """
import json, sys
from pathlib import Path
from vtube_planning.studies.campaign_verify import verify
found = verify(Path(sys.argv[1]), runs=1, workers=1)
print(json.dumps([found.checked, found.report_matches, [repr(d) for d in found.differences]]))
"""


def kind_settings() -> dict[str, str]:
    """The environment variables that make this machine fly `KIND`: numpy's dispatch targets beyond it disabled,
    OpenBLAS's kernels named."""
    here = environment()
    beyond = sorted(set(here['numpy_simd'].split()) - set(KIND['numpy_simd'].split()))
    settings = {'OPENBLAS_CORETYPE': KIND['openblas_core']}
    return settings | ({'NPY_DISABLE_CPU_FEATURES': ' '.join(beyond)} if beyond else {})


def test_the_kind_is_flown_where_it_is_emulated() -> None:
    script = 'from tests.support.regression import environment; import json; print(json.dumps(environment()))'
    flown = subprocess.run(
        [sys.executable, '-c', script],
        check=False,
        env=os.environ | kind_settings(),
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    emulated = json.loads(flown.stdout)
    assert {key: emulated[key] for key in KIND} == KIND, flown.stderr


@pytest.mark.parametrize('folder', VERIFIED)
def test_a_committed_campaign_is_what_the_code_produces(folder: str) -> None:
    here = environment()
    if folder in MADE_IN_KIND and any(here[key] != value for key, value in KIND.items()):
        made = subprocess.run(
            [sys.executable, '-c', VERIFY, str(DOCS / folder)],
            check=False,
            env=os.environ | kind_settings(),
            cwd=ROOT,
            capture_output=True,
            text=True,
        )
        assert made.returncode == 0, made.stderr[-2000:]
        checked, report_matches, differences = json.loads(made.stdout.splitlines()[-1])
    else:
        found = verify(DOCS / folder, runs=1, workers=1)
        checked, report_matches, differences = found.checked, found.report_matches, found.differences
    assert checked == 1 and report_matches is True, f'{folder}/report.md is not what its table gives now'
    assert not differences, f'{folder}: {differences}'
