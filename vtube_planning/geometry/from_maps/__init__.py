"""Tubes from maps: a certified tube generated from an obstacle map, and the maps it is generated on.

Its modules, from the top of the room down (each imports only those below it): ``maps`` (seeded random map
families and a scene put on one) and ``map_file`` (a scene file with ``[tube.generate]`` in, the scene file
``vtube tube generate`` writes out); ``generate`` (the generator: clearance grid, path, lines and arcs, a width
under the clearance); ``centre_path`` (the path search and its lines and arcs); ``tube_spec`` (what the generator
is asked for). The tube itself, its obstacles and occupancy images are the rest of ``geometry``, below the room.
"""
