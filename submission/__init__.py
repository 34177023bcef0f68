"""Builder and preflight check of the single self-contained file submitted to the remote Robotarium.

[`build`][submission.builder.build] writes the file; ``submission.check.check`` runs it on the bundled simulator (the
function is not exported here, where ``check`` names its module).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from vtube_planning._lazy import lazy_exports

if TYPE_CHECKING:
    from submission.builder import Submission, build, write
    from submission.check import CheckReport, RunReport
    from submission.declaration import Declaration, declare
    from submission.errors import CheckError, SubmissionError

__all__ = [
    'CheckError',
    'CheckReport',
    'Declaration',
    'RunReport',
    'Submission',
    'SubmissionError',
    'build',
    'declare',
    'write',
]

__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        'submission.builder': ('Submission', 'build', 'write'),
        'submission.check': ('CheckReport', 'RunReport'),
        'submission.declaration': ('Declaration', 'declare'),
        'submission.errors': ('CheckError', 'SubmissionError'),
    },
)
