"""numpy's SIMD dispatch pinned to the golden file's: the features a machine would dispatch beyond it.

The regression harness's golden file (tests/integration/regression.json) was made where numpy dispatches up to
X86_V3 (AVX2, FMA3). On a machine with AVX-512, numpy's loops for arctan2, hypot, exp and the like take other
kernels whose last bits differ, and the harness's chaotic cases (a min-distance time, late fingerprints) move far
beyond its tolerance although no code changed. The suite therefore runs with those extra features disabled
(``NPY_DISABLE_CPU_FEATURES``), which must be set before numpy is imported: `beyond_golden` asks a child process
which features this machine's numpy dispatches and supports, and returns those the golden environment lacks.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

GOLDEN = Path(__file__).resolve().parents[1] / 'integration' / 'regression.json'
PROBE = (
    'from numpy._core._multiarray_umath import __cpu_features__ as on, __cpu_dispatch__ as dispatched\n'
    'print(" ".join(name for name in dispatched if on.get(name)))'
)


def beyond_golden(golden: Path = GOLDEN) -> str:
    """The dispatched features this machine supports and the golden environment's numpy did not use, space-separated
    ('' where there are none, or where numpy or the golden file cannot say)."""
    try:
        simd = set(json.loads(golden.read_text(encoding='utf-8'))['environment']['numpy_simd'].split())
        probe = subprocess.run([sys.executable, '-c', PROBE], capture_output=True, text=True, timeout=60, check=True)
    except (OSError, ValueError, KeyError, subprocess.SubprocessError):
        return ''
    return ' '.join(name for name in probe.stdout.split() if name not in simd)
