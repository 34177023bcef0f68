"""The ``vtube`` command line: it only wires the packages together (see `vtube.cli`)."""

from vtube_planning import __version__

__all__ = ['__version__']
