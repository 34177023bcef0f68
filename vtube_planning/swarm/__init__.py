"""The swarm: the controller's parameters, the simulator, metrics, trajectory logs (the step: ``onboard``)."""
