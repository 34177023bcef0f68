"""``rps.examples``: the helpers V2 example scripts import (not the scripts themselves)."""
