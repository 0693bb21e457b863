"""``python -m symdyn``: the command line (as the ``symdyn`` script)."""

from .cli import run

run()
