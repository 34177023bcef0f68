"""The paper's baselines: optimized flocking and distributed NMPC."""
