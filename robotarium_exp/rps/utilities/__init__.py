"""``rps.utilities``: transformations, barrier certificates, controllers, misc."""
