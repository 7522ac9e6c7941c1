"""isotween studio: a local web app to morph, correct and edit in-betweens by hand.

``isotween studio [FILE ...]``, ``isotween.studio(...)`` or `studio` starts a Starlette server on
127.0.0.1 (needs ``pip install isotween[studio]``) and opens the page in the
browser; `Session` holds one user's inputs, hints, edits and undo history.
"""

from __future__ import annotations

import secrets
import socket
import sys
import threading
import time
import types
import webbrowser
from typing import Any

from ..errors import ParameterError, require

__all__ = ["studio", "StudioServer"]


class StudioServer:
    """A studio server on a port of this machine (uvicorn in this process).

    Parameters
    ----------
    files : list of path-like
        Drawings named on the command line: the only paths the server reads;
        the first two are opened.
    port : int
        0 picks a free port.
    host : str
        Address to bind (default: this machine only); requests must name it
        (or 127.0.0.1 / localhost) in ``Host``.

    Attributes
    ----------
    url : str
        The page's address with its token.
    session : Session
    """

    def __init__(self, files: Any = (), port: int = 0, host: str = "127.0.0.1"):
        require("starlette", "studio")
        require("uvicorn", "studio")
        require("multipart", "studio")
        import uvicorn

        from .server import create_app
        from .session import Session

        if isinstance(port, bool) or not isinstance(port, int) or not 0 <= port < 65536:
            raise ParameterError(f"port must be a whole number from 0 to 65535, got {port!r}")
        with socket.socket() as s:  # a free port, or the one asked for if it is free
            try:
                s.bind((host, port))
            except OSError as exc:
                raise ParameterError(f"cannot serve on {host}:{port}: {exc.strerror or exc}") from None
            port = s.getsockname()[1]
        self.port, self.host = port, host
        self.token = secrets.token_urlsafe(24)
        self.session = Session(files)
        files = list(files)
        if len(files) >= 2:
            ids = [self.session.add_path(str(f)) for f in files[:2]]
            self.session.apply(self.session.new_document(ids))
        from .server import LOCAL_HOSTS

        hosts = LOCAL_HOSTS if host in LOCAL_HOSTS or host in ("0.0.0.0", "::") else LOCAL_HOSTS + (host,)
        self.app = create_app(self.session, self.token, port=port, hosts=hosts)
        config = uvicorn.Config(self.app, host=host, port=port, log_level="warning", lifespan="off")
        self.server = uvicorn.Server(config)
        name = "127.0.0.1" if host in ("127.0.0.1", "0.0.0.0") else host
        self.url = f"http://{name}:{port}/?token={self.token}"
        self._thread: threading.Thread | None = None

    def serve_forever(self) -> None:
        """Serve until interrupted (Ctrl-C)."""
        self.server.run()

    def start(self) -> StudioServer:
        """Serve from a background thread; returns when the server accepts connections."""
        self._thread = threading.Thread(target=self.server.run, name="isotween-studio", daemon=True)
        self._thread.start()
        deadline = time.monotonic() + 20
        while not self.server.started:
            if time.monotonic() > deadline or not self._thread.is_alive():
                raise RuntimeError("the studio server did not start")
            time.sleep(0.02)
        return self

    def stop(self) -> None:
        """Stop a server started by `start`."""
        self.server.should_exit = True
        if self._thread is not None:
            self._thread.join(timeout=10)


def studio(files: Any = (), *, port: int = 0, open_browser: bool = True, block: bool = True,
           host: str = "127.0.0.1") -> StudioServer:
    """Start isotween studio: a local web app to morph, correct and edit in-betweens.

    Parameters
    ----------
    files : list of path-like
        Drawings to open (SVG, OBJ, OFF, JSON, NPZ); the server reads no other paths.
    port : int
        Port on this machine (0: a free one).
    open_browser : bool
        Open the page in the default web browser.
    block : bool
        Serve until interrupted; otherwise serve from a background thread
        and return at once (stop it with ``server.stop()``).
    host : str
        Address to bind; only this machine by default.

    Returns
    -------
    StudioServer
        Its ``url`` (with the token) and ``session``.
    """
    server = StudioServer(files, port=port, host=host)
    print(f"isotween studio: {server.url}", flush=True)
    if not block:
        server.start()
    if open_browser:
        webbrowser.open(server.url)
    if block:
        server.serve_forever()
    return server


class _CallableModule(types.ModuleType):
    """The studio package, callable: ``isotween.studio(...)`` is `studio` (the package keeps its submodules)."""

    def __call__(self, *args: Any, **kwargs: Any) -> StudioServer:
        return studio(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule
