"""The package's curated exports are the defining objects, loaded lazily."""

from __future__ import annotations

import importlib

import submission

ORIGINS = {
    'submission.builder': ('Submission', 'build', 'write'),
    'submission.check': ('CheckReport', 'RunReport'),
    'submission.declaration': ('Declaration', 'declare'),
    'submission.errors': ('CheckError', 'SubmissionError'),
}


def test_the_exports_are_the_defining_objects() -> None:
    assert sorted(submission.__all__) == sorted(name for names in ORIGINS.values() for name in names)
    for module, names in ORIGINS.items():
        for name in names:
            assert getattr(submission, name) is getattr(importlib.import_module(module), name)
    assert set(submission.__all__) <= set(dir(submission))
