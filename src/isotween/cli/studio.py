"""``isotween studio [FILE ...]``: the local web app to morph, correct and edit in-betweens."""

import click


@click.command("studio")
@click.argument("files", nargs=-1)
@click.option("--port", type=click.IntRange(0, 65535), default=0, show_default=True,
              help="Port on 127.0.0.1 (0: a free one).")
@click.option("--no-browser", is_flag=True, help="Print the URL without opening a web browser.")
def studio_command(files, port, no_browser):
    """Start isotween studio in the web browser (Ctrl-C stops it).

    FILES are drawings (.svg .obj .off .json .npz); the first two are opened
    as source and target, and the server reads no other paths (drop or open
    more files in the page). The URL holds a secret token; the server
    answers only on this machine. Needs: pip install 'isotween[studio]'.
    """
    from pathlib import Path

    from ..errors import FileFormatError
    from ..studio import studio

    for f in files:
        if not Path(f).is_file():
            raise FileFormatError(f"{f}: no such file")
    studio(list(files), port=port, open_browser=not no_browser)
