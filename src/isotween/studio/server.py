"""The studio's web server: Starlette on uvicorn, an HTTP JSON API and the static page.

Every request needs a ``Host`` naming this machine and no foreign
``Origin``; the page and the API also need the session's token (in the URL
as ``?token=``, then a cookie, or the ``X-Isotween-Token`` header; the
package's static scripts and styles are public, so that the page also loads
inside a notebook's iframe, where the cookie is not sent); request bodies are
limited in size. Errors come
back as one JSON message ``{"error": ...}``; the session keeps its state.
"""

from __future__ import annotations

import hmac
import json
import logging
import tempfile
import threading
from importlib import resources
from pathlib import Path
from typing import Any
from urllib.parse import parse_qs

from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.requests import Request
from starlette.responses import HTMLResponse, JSONResponse, Response
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles

from ..errors import IsotweenError, ParameterError
from .session import METHODS, Session, Superseded
from .view import correspondence_view, pack, sequence_view

__all__ = ["create_app", "MAX_UPLOAD", "EXPORT_KINDS", "LOCAL_HOSTS"]

#: largest request body (bytes)
MAX_UPLOAD = 32 * 2 ** 20
#: export kind -> file name ending (every output kind of `isotween.write_output` that is one file)
EXPORT_KINDS = {"gif": ".gif", "webp": ".webp", "apng": ".apng", "mp4": ".mp4", "svg": ".svg",
                "lottie": ".lottie.json", "html": ".html", "npz": ".npz", "json": ".json", "png": ".png"}
#: host names the server answers to
LOCAL_HOSTS = ("127.0.0.1", "localhost", "[::1]")
COOKIE = "isotween_studio_token"
_MEDIA = {".gif": "image/gif", ".webp": "image/webp", ".apng": "image/apng", ".mp4": "video/mp4",
          ".svg": "image/svg+xml", ".html": "text/html", ".png": "image/png", ".json": "application/json",
          ".npz": "application/octet-stream"}
log = logging.getLogger("isotween.studio")


def _error(message: str, status: int = 400) -> JSONResponse:
    return JSONResponse({"error": message}, status_code=status)


class _Guard:
    """ASGI middleware: token, Host, Origin and body-size checks before anything else runs."""

    def __init__(self, app: Any, token: str, hosts: tuple, port: int | None, max_body: int):
        self.app, self.token, self.hosts, self.port, self.max_body = app, token, hosts, port, max_body

    def _host_ok(self, host: str) -> bool:
        name, _, port = host.rpartition(":") if not host.endswith("]") else (host, "", "")
        if not name:
            name, port = host, ""
        if name not in self.hosts:
            return False
        return self.port is None or not port or port == str(self.port)

    def _origin_ok(self, origin: str) -> bool:
        for name in self.hosts:
            base = f"http://{name}"
            if origin == base or (self.port is not None and origin == f"{base}:{self.port}") \
                    or (self.port is None and origin.startswith(base + ":")):
                return True
        return False

    async def __call__(self, scope: dict, receive: Any, send: Any) -> None:
        if scope["type"] not in ("http", "websocket"):
            return await self.app(scope, receive, send)
        headers = {k.decode("latin-1").lower(): v.decode("latin-1") for k, v in scope.get("headers", [])}
        response = None
        if not self._host_ok(headers.get("host", "")):
            response = _error("forbidden: this server answers only to 127.0.0.1 / localhost", 403)
        elif "origin" in headers and not self._origin_ok(headers["origin"]):
            response = _error("forbidden: requests from other sites are refused", 403)
        elif not scope.get("path", "").startswith("/static/") and not self._token_ok(scope, headers):
            response = _error("forbidden: open the studio with the URL it printed (with ?token=...)", 403)
        elif scope["method"] not in ("GET", "HEAD"):
            length = headers.get("content-length")
            if length is None:
                response = _error("a request body needs a Content-Length", 411)
            elif not length.isdigit() or int(length) > self.max_body:
                response = _error(f"request too large: the studio takes at most {self.max_body // 2 ** 20} MiB", 413)
        if response is not None:
            return await response(scope, receive, send)
        return await self.app(scope, receive, send)

    def _token_ok(self, scope: dict, headers: dict) -> bool:
        given = [headers.get("x-isotween-token", "")]
        given += parse_qs(scope.get("query_string", b"").decode("latin-1")).get("token", [])
        for part in headers.get("cookie", "").split(";"):
            name, _, value = part.strip().partition("=")
            if name == COOKIE:
                given.append(value)
        return any(g and hmac.compare_digest(g.encode(), self.token.encode()) for g in given)


async def _json(request: Request) -> dict:
    try:
        body = json.loads(await request.body() or b"{}")
    except (ValueError, UnicodeDecodeError):
        raise ParameterError("malformed request: the body is not JSON") from None
    if not isinstance(body, dict):
        raise ParameterError("malformed request: the body must be a JSON object")
    return body


def _handles(body: dict) -> tuple[int, dict, int | None]:
    try:
        frame = body["frame"]
        handles = {int(h[0]): (float(h[1]), float(h[2])) for h in body["handles"]}
        anchor = body.get("anchor")
        anchor = None if anchor is None else int(anchor)
    except (KeyError, TypeError, ValueError, IndexError):
        raise ParameterError("malformed request: give frame and handles [[vertex, x, y], ...]") from None
    if isinstance(frame, bool) or not isinstance(frame, int):
        raise ParameterError(f"malformed request: frame must be a whole number, got {frame!r}")
    return frame, handles, anchor


def create_app(session: Session, token: str, *, port: int | None = None, max_upload: int = MAX_UPLOAD,
               hosts: tuple = LOCAL_HOSTS) -> Any:
    """The studio's ASGI application.

    Parameters
    ----------
    session : Session
    token : str
        The secret every request must carry.
    port : int, optional
        The port served on; ``Host`` and ``Origin`` must name it (any port when None).
    max_upload : int
        Largest request body in bytes.
    hosts : tuple of str
        Host names accepted in ``Host`` and ``Origin``.

    Returns
    -------
    ASGI application (Starlette, wrapped by the checks)
    """
    from .. import __version__
    from ..examples import describe, names
    from ..optimisation import backend

    backend.long_lived()  # every edit solves again: numba's kernels, loaded once, for all of them
    seen: dict = {}  # the correspondence view of the last solve's correspondence (edits do not change it)
    seen_lock = threading.Lock()

    def corr_view(solved: Any) -> dict:
        key = (id(solved.report), id(solved.source), tuple(map(id, solved.inputs)))
        with seen_lock:
            if seen.get("key") == key:
                return seen["view"]
        view = correspondence_view(solved)
        with seen_lock:
            seen.update(key=key, view=view, keep=(solved.report, solved.source, solved.inputs))
        return view

    def state(extra: dict | None = None) -> JSONResponse:
        doc, solved = session.doc, session.solved
        out: dict[str, Any] = {
            "version": __version__, "examples": [{"name": n, "description": describe(n)} for n in names()],
            "methods": list(METHODS), "export_kinds": list(EXPORT_KINDS),
            "files": sorted(session.allowed), "generation": session.generation,
            "undo": len(session.undo_stack), "redo": len(session.redo_stack), "document": None,
        }
        if doc is not None and solved is not None:
            edits = [int(k) for k in doc["edits"]]
            out.update({
                "document": {k: v for k, v in doc.items() if k != "edits"} | {"edited": sorted(edits)},
                "names": [session.blobs[k].name for k in doc["inputs"]],
                "third_name": session.blobs[doc["third"]].name if doc.get("third") else None,
                "sequence": sequence_view(solved.sequence, edits + solved.base.info.get("keyframe_indices", [])),
                "transfer": sequence_view(solved.transfer) if solved.transfer is not None else None,
                "correspondence": corr_view(solved), "notes": solved.notes,
                "energy": float(solved.sequence.energy[-1]) if solved.sequence.energy else None,
                "preview": solved.preview,
            })
        if extra:
            out.update(extra)
        return JSONResponse(out)

    async def run(fn: Any, *args: Any) -> JSONResponse:
        def work() -> JSONResponse:  # the answer is packed and encoded here too, off the event loop
            fn(*args)
            return state()

        try:
            return await run_in_threadpool(work)
        except Superseded:
            return JSONResponse({"superseded": True, "generation": session.generation})

    async def index(request: Request) -> Response:
        page = resources.files("isotween.studio").joinpath("static/index.html").read_text(encoding="utf-8")
        response = HTMLResponse(page, headers={"Cache-Control": "no-store"})
        response.set_cookie(COOKIE, token, httponly=True, samesite="strict")
        return response

    async def get_state(request: Request) -> Response:
        return state()

    async def progress(request: Request) -> Response:
        return JSONResponse(session.progress)

    async def upload(request: Request) -> Response:
        try:
            form = await request.form(max_files=8, max_fields=8)
        except Exception as exc:  # multipart parse errors
            raise ParameterError(f"malformed upload: {exc}") from None
        ids, names_ = [], []
        for _, value in form.multi_items():
            if isinstance(value, str) or not hasattr(value, "read"):
                continue
            data = await value.read()
            ids.append(await run_in_threadpool(session.add_blob, value.filename or "drawing", data))
            names_.append(value.filename)
        await form.close()
        if not ids:
            raise ParameterError("malformed upload: no file in the form (field 'file')")
        return JSONResponse({"ids": ids, "names": names_})

    async def open_(request: Request) -> Response:
        body = await _json(request)
        ids: Any
        if "example" in body:
            ids = session.add_example(str(body["example"]))
        elif "paths" in body:
            if not isinstance(body["paths"], list):
                raise ParameterError("malformed request: paths must be a list")
            ids = [await run_in_threadpool(session.add_path, str(p)) for p in body["paths"]]
        else:
            ids = body.get("inputs")
            if not isinstance(ids, list):
                raise ParameterError("malformed request: give inputs (upload ids), paths or example")
        quick = body.get("quick") is True
        if body.get("role") == "third":
            if len(ids) != 1:
                raise ParameterError("give one drawing to transfer the motion onto")
            return await run(lambda: session.change(third=str(ids[0])))
        doc = session.new_document([str(i) for i in ids])
        return await run(lambda: session.apply(doc, quick=quick))

    async def options(request: Request) -> Response:
        body = await _json(request)
        return await run(session.set_options, body)

    async def hints(request: Request) -> Response:
        body = await _json(request)
        parts = {}
        for key in ("pairs", "landmarks"):
            if key in body:
                if not isinstance(body[key], list):
                    raise ParameterError(f"malformed request: {key} must be a list")
                parts[key] = body[key]
        return await run(lambda: session.set_hints(quick=body.get("quick") is True, **parts))

    async def refine(request: Request) -> Response:
        return await run(session.refine)

    async def third(request: Request) -> Response:
        body = await _json(request)
        return await run(lambda: session.change(third=body.get("input")))

    async def deform(request: Request) -> Response:
        frame, handles, anchor = _handles(await _json(request))
        vertices = await run_in_threadpool(session.deform, frame, handles, anchor)
        return JSONResponse({"frame": frame, "vertices": pack(vertices)})

    async def edit(request: Request) -> Response:
        frame, handles, anchor = _handles(await _json(request))
        return await run(session.edit_frame, frame, handles, anchor)

    async def clear_edits(request: Request) -> Response:
        return await run(lambda: session.change(edits={}))

    async def undo(request: Request) -> Response:
        return await run(session.undo)

    async def redo(request: Request) -> Response:
        return await run(session.redo)

    async def get_project(request: Request) -> Response:
        project = session.project()
        return Response(json.dumps(project), media_type="application/json",
                        headers={"Content-Disposition": 'attachment; filename="isotween-project.json"'})

    async def put_project(request: Request) -> Response:
        try:
            project = json.loads(await request.body())
        except (ValueError, UnicodeDecodeError):
            raise ParameterError("not a project file: it is not JSON") from None
        return await run(session.open_project, project)

    async def export(request: Request) -> Response:
        body = await _json(request)
        kind = body.get("kind")
        if kind not in EXPORT_KINDS:
            raise ParameterError(f"unknown export kind {kind!r}; use one of {', '.join(EXPORT_KINDS)}")
        solved = session.solved
        if solved is None:
            raise ParameterError("nothing to export: open two drawings first")
        if solved.preview:
            raise ParameterError("the morph is an outline preview while its meshes are solved; export in a moment")
        seq = solved.transfer if body.get("which") == "transfer" and solved.transfer is not None else solved.sequence
        # the timing is the studio's, not the library's rendered-output defaults (1 s of motion held 0.25 s):
        # the sequence's own frames, one per tick at ``fps``, unless the request gives ``duration`` seconds of
        # motion (the page sends its playback duration) or a ``hold``
        render: dict[str, Any] = {"duration": 0, "hold": 0}
        for key, kinds in (("fps", (int, float)), ("size", (int,)), ("duration", (int, float)),
                           ("hold", (int, float)), ("bounce", (bool,)),
                           ("loop", (bool,)), ("background", (str,)), ("title", (str,))):
            value = body.get(key)
            if value is None or value == "":
                continue
            if not isinstance(value, kinds) or (bool not in kinds and isinstance(value, bool)):
                raise ParameterError(f"malformed request: {key} must be a {kinds[0].__name__}, got {value!r}")
            render[key] = value
        name = "isotween" + EXPORT_KINDS[kind]
        data = await run_in_threadpool(_export, seq, name, render)
        return Response(data, media_type=_MEDIA[Path(name).suffix],
                        headers={"Content-Disposition": f'attachment; filename="{name}"'})

    def guarded(endpoint: Any) -> Any:
        async def wrapped(request: Request) -> Response:
            try:
                return await endpoint(request)
            except IsotweenError as exc:
                return _error(str(exc), 400)
            except Exception as exc:  # a failed solve or a bug: one message, the session unchanged
                log.exception("studio request failed")
                return _error(f"internal error ({type(exc).__name__}: {exc}); the session is unchanged", 500)

        return wrapped

    api = [
        Route("/", index), Route("/api/state", get_state), Route("/api/progress", progress),
        Route("/api/upload", upload, methods=["POST"]), Route("/api/open", open_, methods=["POST"]),
        Route("/api/options", options, methods=["POST"]), Route("/api/hints", hints, methods=["POST"]),
        Route("/api/third", third, methods=["POST"]), Route("/api/deform", deform, methods=["POST"]),
        Route("/api/edit", edit, methods=["POST"]), Route("/api/clear_edits", clear_edits, methods=["POST"]),
        Route("/api/refine", refine, methods=["POST"]),
        Route("/api/undo", undo, methods=["POST"]), Route("/api/redo", redo, methods=["POST"]),
        Route("/api/project", get_project, methods=["GET"]), Route("/api/project", put_project, methods=["POST"]),
        Route("/api/export", export, methods=["POST"]),
    ]
    routes = [Route(r.path, guarded(r.endpoint), methods=list(r.methods or ())) for r in api] + [
        Mount("/static", StaticFiles(packages=[("isotween.studio", "static")]), name="static"),
    ]
    app = Starlette(routes=routes)
    return _Guard(app, token, hosts, port, max_upload)


def _export(seq: Any, name: str, render: dict) -> bytes:
    from ..outputs import write_output

    with tempfile.TemporaryDirectory(prefix="isotween-studio-") as tmp:
        out = Path(tmp) / name
        write_output(seq, out, quiet=True, **render)
        return out.read_bytes()
