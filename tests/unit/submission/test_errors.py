"""One base class for the package's errors, under vtube's and ValueError."""

from __future__ import annotations

from submission.errors import CheckError, SubmissionError
from vtube_planning.errors import VtubeError


def test_every_error_is_a_vtube_error_and_a_value_error() -> None:
    assert issubclass(SubmissionError, VtubeError) and issubclass(SubmissionError, ValueError)
    assert issubclass(CheckError, SubmissionError)
