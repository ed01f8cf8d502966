"""``evoplan report DIR --watch``: serve the report on 127.0.0.1 and rebuild it as the folder's
data grow; the page reloads itself when the served version changes (it polls ``/version``).

Bounded: it stops once the run has ended (``best.json`` written; a study: ``report.md``
written), after one last build, or after ``timeout`` seconds.
"""

from __future__ import annotations

import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

__all__ = ["signature", "finished", "serve"]

WATCHED = ("history.csv", "best.json", "pareto.csv", "toolpath.apt", "runs.csv", "report.md",
           "simulation.json", "summary.json")


def signature(folder: Path) -> tuple:
    """What changes when the folder's data grow (size and mtime of the watched files, cell count)."""
    sig = []
    for name in WATCHED:
        p = folder / name
        if p.is_file():
            st = p.stat()
            sig.append((name, st.st_size, st.st_mtime_ns))
    cells = folder / "cells"
    if cells.is_dir():
        sig.append(("cells", sum(1 for _ in cells.iterdir())))
    return tuple(sig)


def finished(folder: Path) -> bool:
    if (folder / "study.yaml").is_file() or (folder / "cells").is_dir():
        return (folder / "report.md").is_file()
    return (folder / "best.json").is_file() or (folder / "simulation.json").is_file() or \
        (folder / "summary.json").is_file()


RELOAD = ("<script>let v=null;setInterval(()=>fetch('/version').then(r=>r.text()).then(t=>{"
          "if(v!==null&&t!==v)location.reload();v=t;}).catch(()=>{}),1000);</script>")


def page_html(folder: Path) -> str:
    """The report with a script that reloads it when ``/version`` changes (or a waiting page)."""
    import html

    from ..errors import EvoplanError
    from . import build

    try:
        text = build(folder)
    except EvoplanError as e:
        cells = folder / "cells"
        done = sum(1 for _ in cells.iterdir()) if cells.is_dir() else 0
        text = (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>evoplan report</title></head><body>"
                f"<p>waiting for data: {html.escape(str(e))}{f' ({done} study cells done)' if done else ''}</p>"
                "</body></html>")
    return text.replace("</body>", RELOAD + "</body>", 1)


def serve(folder: Path, port: int = 0, timeout: float = 3600.0, poll: float = 0.5,
          out: Path | None = None, announce=print) -> str:
    """Serve until the run ends or ``timeout``; returns why it stopped (``finished``, ``timeout``)."""
    from ..engine import write_atomic
    from ..errors import ConfigError

    try:
        server = ThreadingHTTPServer(("127.0.0.1", port), None)
    except (OSError, OverflowError) as e:  # in use, not permitted, out of range
        why = getattr(e, "strerror", None) or " ".join(str(e).split())
        raise ConfigError(f"--port {port}: cannot serve on 127.0.0.1:{port} ({why})") from None
    try:
        state = {"html": page_html(folder), "version": 0}
    except BaseException:
        server.server_close()
        raise
    lock = threading.Lock()

    class Handler(BaseHTTPRequestHandler):
        def do_GET(self):  # noqa: N802 - http.server's name
            with lock:
                body = (str(state["version"]) if self.path == "/version" else state["html"]).encode()
            kind = "text/plain" if self.path == "/version" else "text/html; charset=utf-8"
            if self.path not in ("/", "/index.html", "/version"):
                self.send_response(404)
                self.end_headers()
                return
            self.send_response(200)
            self.send_header("Content-Type", kind)
            self.send_header("Content-Length", str(len(body)))
            self.send_header("Cache-Control", "no-store")
            self.end_headers()
            self.wfile.write(body)

        def log_message(self, *args):  # quiet
            pass

    server.RequestHandlerClass = Handler
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    url = f"http://127.0.0.1:{server.server_address[1]}/"
    announce(f"evoplan: serving the report of {folder} at {url} (it refreshes as the data grow; "
             f"stops when the run ends or after {timeout:g} s)")
    t0, sig, reason = time.monotonic(), signature(folder), "timeout"
    try:
        while time.monotonic() - t0 < timeout:
            time.sleep(poll)
            now = signature(folder)
            if now != sig:
                sig = now
                html = page_html(folder)
                with lock:
                    state["html"], state["version"] = html, state["version"] + 1
            if finished(folder):
                reason = "finished"
                time.sleep(min(2.0, max(0.0, timeout - (time.monotonic() - t0))))  # let the page reload once
                break
    finally:
        server.shutdown()
        server.server_close()
    if out is not None:
        write_atomic(out, build_final(folder).encode())
    return reason


def build_final(folder: Path) -> str:
    from . import build

    return build(folder)
