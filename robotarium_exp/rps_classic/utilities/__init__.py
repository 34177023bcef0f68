"""Classic ``rps.utilities``: transformations, controllers, barrier certificates, graphs, misc."""
