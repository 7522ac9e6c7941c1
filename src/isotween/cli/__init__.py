"""The ``isotween`` command line: one click group, one module per command.

Commands load lazily: the group lists them in `COMMANDS` and imports a
command's module (``isotween.cli.NAME``, defining ``NAME_command``) only
when that command runs or its help is shown, so ``isotween interpolate``
does not import what ``isotween render`` needs.
"""

import functools
import importlib
import signal
import sys
from pathlib import Path

import click

from .. import __version__
from .._heap import keep_heap
from .._text import safe_text
from ..errors import IsotweenError

#: command name -> the summary line of its help, for ``isotween --help`` without importing every command
#: (checked against the commands by tests/test_cli.py); command NAME is ``NAME_command`` in module ``.NAME``
COMMANDS = {
    "batch": "Run every job of MANIFEST.",
    "compare": "Interpolate SOURCE into TARGET (or a built-in --example) with several methods and compare them.",
    "demo": "Interpolate the built-in example NAME (default: the first one).",
    "edit": "Replace frames of SEQUENCE and carry the change through its motion (Sec. 5.2).",
    "info": "Print what FILE holds: vertices, edges, faces, components, bounding box.",
    "interpolate": "Interpolate SOURCE into TARGET as-isometrically-as-possible.",
    "keyframes": "AIAP through every KEYFRAME file at once (at least two).",
    "prepare": "Make SOURCE and TARGET compatible and write them into OUTDIR.",
    "render": "Render SEQUENCE (.npz/.json, or a folder of frames) to -o without solving again.",
    "studio": "Start isotween studio in the web browser (Ctrl-C stops it).",
    "transfer": "Move TARGET_START the way SOURCE_START moves into SOURCE_END (Sec. 5.1).",
}

#: parameters that name files a command reads, and ones it writes
_INPUTS = ("source", "target", "source_start", "source_end", "target_start", "sequence",
           "keyframes", "shapes", "file", "texture", "manifest")
_OUTPUTS = {"output": "-o", "outdir": "-o", "report_dir": "-o", "plot": "--plot", "report": "--report"}


class _Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread so that every cleanup runs."""


def _on_sigterm(signum, frame):
    raise _Terminated()


def _set_max_memory(ctx, param, value):
    if value is not None:
        from ..resources import _LIMIT, parse_size

        _LIMIT.set(parse_size(value))  # reset by _Group.invoke when the command ends
    return value


def _guarded(callback):
    """The command's callback, after refusing outputs that name its inputs or cannot be written."""

    @functools.wraps(callback)
    def run(**params):
        from .options import check_paths, probe_writable

        inputs = []
        for key in _INPUTS:
            value = params.get(key)
            if key == "manifest" and value is not None and Path(value).is_dir():
                continue  # a folder of pairs may also receive the outputs: `batch` checks each job's
            inputs += list(value) if isinstance(value, (list, tuple)) else [value]
        outputs = [(opt, params.get(key)) for key, opt in _OUTPUTS.items() if params.get(key) is not None]
        check_paths(inputs, outputs)
        for opt, out in outputs:  # a file can be created where each output goes
            if opt == "--report":  # in OUTDIR, which the command creates
                continue
            out = Path(out)
            probe_writable(out if out.is_dir() else out.parent, out)
        return callback(**params)

    return run


class _Group(click.Group):
    """Turns errors into one line on stderr and a non-zero exit.

    Library errors (`IsotweenError`) exit with 2, an interrupt (Ctrl-C) with
    130, SIGTERM with 143; files being written are removed first (every
    writer writes through a temporary file). Every command also takes
    ``--max-memory SIZE``: the most memory a run may need (default: the
    memory available now), checked against estimates before allocating.
    """

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True, **extra):
        """Click's entry point; usage errors, too, become one ``error:`` line (exit 2)."""
        if not standalone_mode:
            return super().main(args, prog_name, complete_var, standalone_mode, **extra)
        try:
            rv = super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
        except click.exceptions.ClickException as exc:
            hint = f" (see '{exc.ctx.command_path} --help')" if getattr(exc, "ctx", None) is not None else ""
            _fail(" ".join(exc.format_message().split()) + hint, exc.exit_code)
        except click.exceptions.Abort:
            _fail("interrupted; no output was written", 130)
        sys.exit(rv if isinstance(rv, int) else 0)

    def list_commands(self, ctx):
        """The command names, sorted (click's order): `COMMANDS` and any added directly."""
        return sorted(set(COMMANDS) | set(self.commands))

    def get_command(self, ctx, cmd_name):
        """The command ``cmd_name``, its module imported (and the command registered) on first use."""
        if cmd_name in COMMANDS and cmd_name not in self.commands:
            module = importlib.import_module(f".{cmd_name}", __name__)
            self.add_command(getattr(module, f"{cmd_name}_command"), cmd_name)
        return super().get_command(ctx, cmd_name)

    def format_commands(self, ctx, formatter):
        """The commands section of ``isotween --help``: summaries from `COMMANDS` for commands not loaded yet."""
        names = self.list_commands(ctx)
        rows = []
        if names:
            limit = formatter.width - 6 - max(len(name) for name in names)
            for name in names:
                cmd = self.commands.get(name)
                if cmd is None:
                    rows.append((name, click.utils.make_default_short_help(COMMANDS[name], limit)))
                elif not cmd.hidden:
                    rows.append((name, cmd.get_short_help_str(limit)))
        if rows:
            with formatter.section("Commands"):
                formatter.write_dl(rows)

    def add_command(self, cmd, name=None):
        cmd.params.append(click.Option(
            ["--max-memory"], default=None, metavar="SIZE", expose_value=False, callback=_set_max_memory,
            help="Refuse runs estimated to need more memory than SIZE (e.g. 4G) [default: the memory available].",
        ))
        if cmd.callback is not None:
            cmd.callback = _guarded(cmd.callback)
        super().add_command(cmd, name)

    def invoke(self, ctx):
        import warnings

        from ..resources import memory_limit

        previous = None
        try:
            previous = signal.signal(signal.SIGTERM, _on_sigterm)
        except ValueError:  # not the main thread: leave signals alone
            pass
        try:
            # warnings become one 'warning:' line each, printed when the command succeeds
            # (a failing command prints its one 'error:' line only)
            with memory_limit(None), warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("default")
                result = super().invoke(ctx)
            for seen in {str(w.message): None for w in caught}:
                click.echo(f"warning: {safe_text(seen)}", err=True)
            return result
        except IsotweenError as exc:
            _fail(str(exc), 2)
        except _Terminated:
            _fail("terminated; no output was written", 143)
        except KeyboardInterrupt:
            _fail("interrupted; no output was written", 130)
        except MemoryError:
            _fail("out of memory; use fewer frames or vertices, or a smaller --max-memory to be refused earlier", 2)
        except RecursionError:
            _fail("input nested too deeply", 2)
        except RuntimeError as exc:  # a signal that arrived inside an import comes wrapped (e.g. in __set_name__)
            cause = exc.__cause__ or exc.__context__
            if isinstance(cause, _Terminated):
                _fail("terminated; no output was written", 143)
            if isinstance(cause, KeyboardInterrupt):
                _fail("interrupted; no output was written", 130)
            raise
        except OSError as exc:
            where = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
            _fail(f"{where}{exc.strerror or exc}", 2)
        finally:
            if previous is not None:
                signal.signal(signal.SIGTERM, previous)


def _fail(message, code):
    click.echo(f"error: {safe_text(message)}", err=True)
    sys.exit(code)


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(version=__version__, prog_name="isotween")
def main():
    """As-isometric-as-possible interpolation of planar shapes."""
    keep_heap()  # a command is its own process: the process-wide malloc tuning is safe here
