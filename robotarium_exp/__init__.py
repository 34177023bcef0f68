"""The tube experiment on the Robotarium: a compatible simulator, the experiment loop, trajectory analysis.

Arrives with issues 6 and 8.
"""
