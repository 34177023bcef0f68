"""The ``vtube`` command line: it only wires the packages together (see :mod:`vtube.cli`)."""
