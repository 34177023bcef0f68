"""The virtual tube and its scenes: centre curve, half-width profile, the tube, scene files."""
