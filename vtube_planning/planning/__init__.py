"""Speed and density planning: the density model of (p7), the convex and polynomial planners, the Plan."""
