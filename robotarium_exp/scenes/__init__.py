"""The Robotarium scenes shipped with the package (``*.toml``: a tube and a ``[robotarium]`` table)."""
