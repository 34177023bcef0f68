"""The swarm: one control step (numpy and scipy only), its parameters, the simulator, metrics, trajectory logs."""
