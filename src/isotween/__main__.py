"""``python -m isotween``: the command line."""

from .cli import main

main()
