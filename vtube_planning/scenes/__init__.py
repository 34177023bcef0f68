"""Scene files shipped with the package (TOML, format in `vtube_planning.geometry.scene`)."""
