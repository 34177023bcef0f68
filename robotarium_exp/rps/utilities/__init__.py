"""``rps.utilities``: transformations, barrier certificates, controllers, graphs, misc."""
