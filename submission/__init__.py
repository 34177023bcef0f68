"""Builder and preflight check of the single self-contained file submitted to the remote Robotarium.

Arrives with issue 7.
"""
