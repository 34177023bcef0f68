"""The smallest scene file the CLI accepts: a straight 10 m tube of constant half-width 2 m, every other value the
defaults."""

from __future__ import annotations

LINE_SCENE = """
[tube.center]
pieces = [{ kind = "line", length_m = 10.0 }]
[tube.width]
start_m = 2.0
parts = [{ kind = "constant" }]
"""
