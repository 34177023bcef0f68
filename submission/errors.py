"""Exceptions of `submission`: one base, [`SubmissionError`][submission.errors.SubmissionError]."""

from __future__ import annotations

from vtube_planning.errors import VtubeError


class SubmissionError(VtubeError, ValueError):
    """A scene that cannot become a valid submission, or a file that cannot be checked."""


class CheckError(SubmissionError):
    """A file that cannot be checked (missing, not Python)."""
