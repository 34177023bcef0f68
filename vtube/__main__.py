"""``python -m vtube``: the same as the ``vtube`` console script."""

import sys

from vtube.cli import main

sys.exit(main())
