"""Draw ``warehouse.png``, the occupancy image of ``warehouse.toml``: a 40 x 20 m floor and a 30 m yard east of it, at
0.1 m per pixel (700 x 200 pixels), as a SLAM map saved by ROS ``map_server`` would be (black occupied, white free,
row 0 the top).

Outer walls 0.3 m thick, an 8 m loading door in the east one onto the yard (where the robots run out beyond the
goal), two inner walls with a 4 m doorway each, racks of shelves and a few crates; run
``python docs/maps/warehouse.py`` to write it again (the same pixels every time: nothing random)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.image import imsave

RESOLUTION_M = 0.1
WIDTH_M, HEIGHT_M = 70.0, 20.0
BOXES_M = [  # x_min, x_max, y_min, y_max: each an occupied rectangle
    (0.0, 40.0, 0.0, 0.3),  # outer walls
    (0.0, 40.0, 19.7, 20.0),
    (0.0, 0.3, 0.0, 20.0),
    (39.7, 40.0, 0.0, 2.0),  # east wall, a loading door y in [2, 10] onto the yard (x from 40 to 70 m)
    (39.7, 40.0, 10.0, 20.0),
    (13.0, 13.3, 0.0, 12.0),  # first inner wall, doorway y in [12, 16]
    (13.0, 13.3, 16.0, 20.0),
    (27.0, 27.3, 0.0, 4.0),  # second inner wall, doorway y in [4, 8]
    (27.0, 27.3, 8.0, 20.0),
    (3.0, 10.0, 14.0, 15.0),  # racks in the first hall
    (3.0, 10.0, 17.5, 18.5),
    (17.0, 18.0, 1.5, 6.0),  # racks in the second hall
    (22.0, 23.0, 13.0, 19.0),
    (31.0, 37.0, 14.0, 15.0),  # racks in the third hall
    (5.5, 6.7, 5.0, 6.2),  # crates
    (9.0, 9.8, 8.5, 9.3),
    (20.0, 20.6, 1.0, 1.6),
    (33.0, 34.2, 6.0, 7.2),
]


def occupancy() -> np.ndarray:
    """The occupied pixels (rows, columns), row 0 the top (y = 20 m)."""
    cols, rows = round(WIDTH_M / RESOLUTION_M), round(HEIGHT_M / RESOLUTION_M)
    x = (np.arange(cols) + 0.5) * RESOLUTION_M
    y = HEIGHT_M - (np.arange(rows) + 0.5) * RESOLUTION_M
    occupied = np.zeros((rows, cols), dtype=bool)
    for x_min, x_max, y_min, y_max in BOXES_M:
        occupied |= ((y[:, None] > y_min) & (y[:, None] < y_max)) & ((x[None, :] > x_min) & (x[None, :] < x_max))
    return occupied


def main() -> None:
    grey = np.where(occupancy(), 0.0, 1.0)
    imsave(Path(__file__).with_name('warehouse.png'), grey, cmap='gray', vmin=0.0, vmax=1.0)


if __name__ == '__main__':
    main()
