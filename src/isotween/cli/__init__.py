"""The ``isotween`` command line: one click group, one module per command."""

import sys

import click

from .. import __version__
from .._heap import keep_heap
from ..errors import IsotweenError


class _Group(click.Group):
    """Turns library errors into one line on stderr and a non-zero exit."""

    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except IsotweenError as exc:
            click.echo(f"error: {exc}", err=True)
            sys.exit(2)


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(version=__version__, prog_name="isotween")
def main():
    """As-isometric-as-possible interpolation of planar shapes."""
    keep_heap()  # a command is its own process: the process-wide malloc tuning is safe here


# each command lives in its own module and registers itself on `main`
from . import _commands  # noqa: E402,F401
