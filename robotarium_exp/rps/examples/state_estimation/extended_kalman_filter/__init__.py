"""``rps.examples.state_estimation.extended_kalman_filter``: the unicycle EKF V2's EKF example imports."""
