"""``rps.examples.state_estimation``: state-estimation helpers."""
