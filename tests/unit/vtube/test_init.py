"""The package's one export: the version, from the package metadata."""

from __future__ import annotations

from importlib.metadata import version

import vtube
import vtube_planning


def test_the_version_is_the_package_metadata() -> None:
    assert vtube.__all__ == ['__version__']
    assert vtube.__version__ == version('vtube') == vtube_planning.__version__
