"""A headless Chromium driven over the DevTools protocol (websocket-client): open a page,
collect console errors and network requests, screenshot, move and click the mouse.

Chromium is Debian's package (``.ci/run`` installs it when missing); the tests that need it
skip with the reason when no ``chromium`` is on PATH.
"""

from __future__ import annotations

import base64
import io
import json
import os
import shutil
import subprocess
import tempfile
import time
import urllib.request
from pathlib import Path


def chromium() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")


class Browser:
    """One headless Chromium with one page; use as a context manager."""

    def __init__(self, width: int = 1280, height: int = 900):
        import websocket

        self.profile = tempfile.mkdtemp(prefix="evoplan-chromium-")
        self.proc = subprocess.Popen(
            [chromium(), "--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--no-first-run",
             "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--remote-debugging-port=0",
             f"--user-data-dir={self.profile}", f"--window-size={width},{height}", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        port_file = Path(self.profile) / "DevToolsActivePort"
        deadline = time.monotonic() + 30
        while not port_file.is_file() or not port_file.read_text().strip():
            if time.monotonic() > deadline or self.proc.poll() is not None:
                self.close()
                raise RuntimeError("chromium did not start")
            time.sleep(0.05)
        port = int(port_file.read_text().split()[0])
        targets = json.load(urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=10))
        page = next(t for t in targets if t["type"] == "page")
        self.ws = websocket.create_connection(page["webSocketDebuggerUrl"], timeout=30,
                                              suppress_origin=True)
        self.next_id = 0
        self.events: list[dict] = []
        self.page = Path(self.profile) / "report.html"  # the one file show() opens
        for domain in ("Page", "Runtime", "Log", "Network"):
            self.call(f"{domain}.enable")

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self) -> None:
        try:
            self.ws.close()
        except Exception:  # noqa: BLE001 - closing down anyway
            pass
        self.proc.terminate()
        try:
            self.proc.wait(10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
        shutil.rmtree(self.profile, ignore_errors=True)

    def call(self, method: str, **params):
        self.next_id += 1
        mid = self.next_id
        self.ws.send(json.dumps({"id": mid, "method": method, "params": params}))
        while True:
            msg = json.loads(self.ws.recv())
            if msg.get("id") == mid:
                if "error" in msg:
                    raise RuntimeError(f"{method}: {msg['error']}")
                return msg.get("result", {})
            self.events.append(msg)

    def js(self, expression: str):
        r = self.call("Runtime.evaluate", expression=expression, returnByValue=True, awaitPromise=True)
        if "exceptionDetails" in r:
            raise RuntimeError(f"{expression[:60]}: {r['exceptionDetails']}")
        return r["result"].get("value")

    #: a report page is ready when every plotly figure has been laid out and given its data
    DRAWN = ("(()=>{const g=[...document.querySelectorAll('.js-plotly-plot')];"
             "return g.length>0 && g.every(d=>d._fullLayout && d._fullData);})()")

    def open(self, url: str, timeout: float = 30.0, ready: str = DRAWN) -> float:
        """Navigate and wait until the new page is loaded and ``ready`` (a JS expression; by
        default its figures are drawn); returns the seconds.

        The page being left is marked first, so a document still showing while the next one
        loads (the same URL, or a slow commit) is never taken for it."""
        t0 = time.monotonic()
        self.js("window.__left = true")
        self.call("Page.navigate", url=url)
        while time.monotonic() - t0 < timeout:
            if self.js(f"!window.__left && document.readyState === 'complete' && {ready}"):
                return time.monotonic() - t0
            time.sleep(0.05)
        raise TimeoutError(f"{url}: not ready after {timeout:g} s")

    def viewport(self, width: int | None = None, height: int | None = None) -> None:
        """Lay pages out in a ``width`` x ``height`` viewport (both None: the window's again)."""
        if width is None:
            self.call("Emulation.clearDeviceMetricsOverride")
        else:
            self.call("Emulation.setDeviceMetricsOverride", width=width, height=height, deviceScaleFactor=1,
                      mobile=False)

    def show(self, html: str, timeout: float = 60.0) -> float:
        """Open the page ``html``, always from the same file: Chromium keeps a page's compiled
        inline scripts by URL, so every report after the first one skips compiling plotly.js's
        4.8 MB again (about 5 s a page on a shared 2-core host). Returns the seconds to draw."""
        self.page.write_text(html, encoding="utf-8")
        return self.open(self.page.as_uri(), timeout)

    def wait_for(self, expression: str, timeout: float = 10.0) -> bool:
        """Poll ``expression`` until it is true (True) or ``timeout`` seconds pass (False)."""
        deadline = time.monotonic() + timeout
        while not self.js(expression):
            if time.monotonic() > deadline:
                return False
            time.sleep(0.05)
        return True

    def errors(self) -> list[str]:
        """Console errors, uncaught exceptions and error log entries seen so far."""
        self.js("0")  # flush pending events
        out = []
        for e in self.events:
            m, p = e.get("method"), e.get("params", {})
            if m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
                out.append(" ".join(str(a.get("value", a.get("description"))) for a in p["args"]))
            elif m == "Runtime.exceptionThrown":
                out.append(p["exceptionDetails"].get("exception", {}).get("description", "exception"))
            elif m == "Log.entryAdded" and p["entry"]["level"] == "error":
                out.append(p["entry"]["text"])
        return out

    def requests(self) -> list[str]:
        self.js("0")
        return [e["params"]["request"]["url"] for e in self.events
                if e.get("method") == "Network.requestWillBeSent"]

    def box(self, selector: str) -> dict:
        return self.js(f"(()=>{{const e=document.querySelector({json.dumps(selector)});"
                       "e.scrollIntoView({block:'center'});const r=e.getBoundingClientRect();"
                       "return {x:r.x,y:r.y,w:r.width,h:r.height,px:r.x+window.scrollX,py:r.y+window.scrollY};})()")

    def screenshot(self, selector: str | None = None, path: Path | None = None):
        """The viewport (or one element) as an RGB numpy array; saved as PNG to ``path``."""
        import numpy as np
        from PIL import Image

        params = {"format": "png"}
        if selector:
            b, previous = self.box(selector), None
            deadline = time.monotonic() + 3
            while b != previous and time.monotonic() < deadline:  # where it stays over two frames
                self.js("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
                previous, b = b, self.box(selector)
            params["clip"] = {"x": b["px"], "y": b["py"], "width": b["w"], "height": b["h"], "scale": 1}
            params["captureBeyondViewport"] = True
        data = base64.b64decode(self.call("Page.captureScreenshot", **params)["data"])
        if path is not None:
            Path(path).write_bytes(data)
        return np.asarray(Image.open(io.BytesIO(data)).convert("RGB"))

    def mouse(self, kind: str, x: float, y: float, **extra) -> None:
        self.call("Input.dispatchMouseEvent", type=kind, x=x, y=y, **extra)

    def click(self, x: float, y: float) -> None:
        self.mouse("mouseMoved", x, y)
        self.mouse("mousePressed", x, y, button="left", clickCount=1)
        self.mouse("mouseReleased", x, y, button="left", clickCount=1)


def shots_dir() -> Path:
    """Where the tests keep their screenshots (EVOPLAN_SHOTS, else a temporary folder)."""
    d = Path(os.environ.get("EVOPLAN_SHOTS") or tempfile.gettempdir()) / "evoplan-report-shots"
    d.mkdir(parents=True, exist_ok=True)
    return d
