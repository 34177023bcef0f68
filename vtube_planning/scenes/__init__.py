"""Scene files shipped with the package (TOML, format in :mod:`vtube_planning.geometry.scene`)."""
