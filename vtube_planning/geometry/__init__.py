"""The virtual tube and its scenes: centre curve, half-width profile, projection, scene files."""
