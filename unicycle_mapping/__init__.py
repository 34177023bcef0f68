"""Single-integrator velocities mapped to unicycle speeds through a near-identity diffeomorphism.

Pure numpy; poses (3, N), unicycle commands (2, N) as [v; omega]. The mapping itself arrives with issue 5.
"""
