"""isotween studio inline in Jupyter: an anywidget showing the studio page of a server in this kernel.

`widget` starts a `StudioServer` on 127.0.0.1 in the kernel's process and
shows its page in an iframe, so the notebook's browser must reach the
kernel's machine on that port (a local Jupyter; not a remote JupyterHub
without port forwarding). Needs ``pip install 'isotween[widget]'`` (anywidget).
"""

from __future__ import annotations

from typing import Any

from ..errors import require

__all__ = ["widget", "ESM"]

#: the widget's front-end: an iframe on the studio page (the page is the studio's own static files)
ESM = """
function render({ model, el }) {
  const frame = document.createElement("iframe");
  frame.style.width = "100%";
  frame.style.border = "1px solid #ddd";
  frame.title = "isotween studio";
  const update = () => {
    frame.src = model.get("url");
    frame.style.height = `${model.get("height")}px`;
  };
  update();
  model.on("change:url", update);
  model.on("change:height", update);
  el.appendChild(frame);
  return () => { model.off("change:url", update); model.off("change:height", update); };
}
export default { render };
"""

_CLASS: Any = None


def _widget_class() -> Any:
    """The anywidget class, defined on first use (anywidget is optional)."""
    global _CLASS
    if _CLASS is None:
        anywidget = require("anywidget", "widget")
        traitlets = require("traitlets", "widget")

        class StudioWidget(anywidget.AnyWidget):  # type: ignore[name-defined]
            """isotween studio in a notebook cell; ``server`` is its `StudioServer`."""

            _esm = ESM
            url = traitlets.Unicode("").tag(sync=True)
            height = traitlets.Int(720).tag(sync=True)

            def __init__(self, server: Any, height: int):
                self.server = server
                super().__init__(url=server.url, height=int(height))

            @property
            def sequence(self) -> Any:
                """The morph on screen (an `isotween.Sequence`), or None before two drawings are open."""
                solved = self.server.session.solved
                return None if solved is None else solved.sequence

            def close(self) -> None:
                """Stop the server and close the widget."""
                self.server.stop()
                super().close()

        _CLASS = StudioWidget
    return _CLASS


def widget(files: Any = (), *, height: int = 720, port: int = 0) -> Any:
    """The studio as a Jupyter widget (anywidget): the studio page inline in a notebook cell.

    Parameters
    ----------
    files : list of path-like
        Drawings to open, as for `isotween.studio`.
    height : int
        Height of the cell's view in pixels.
    port : int
        Port on 127.0.0.1 (0: a free one).

    Returns
    -------
    anywidget.AnyWidget
        Display it (last line of a cell); ``w.sequence`` is the morph as
        edited in the cell, ``w.server.session`` the whole session,
        ``w.close()`` stops the server.

    Examples
    --------
    >>> from isotween.studio.widget import widget
    >>> w = widget(["source.svg", "target.svg"])  # doctest: +SKIP
    >>> w  # doctest: +SKIP
    """
    cls = _widget_class()
    from . import StudioServer

    return cls(StudioServer(files, port=port).start(), height)
