"""Headless Chromium driven over the DevTools protocol on a pipe: screenshots, scripts, requests, console.

Chromium started with ``--remote-debugging-pipe`` reads protocol commands (JSON, each ended by
a NUL byte) from its file descriptor 3 and writes answers and events to its descriptor 4, so no
port is opened and no package beyond the standard library is needed.  The flags are those that
work on a machine with no screen and no network: ``--headless --no-sandbox``, background
networking off, a fresh ``--user-data-dir``; WebGL and the compositor both run on SwiftShader,
Chromium's software renderer, through ANGLE (``--use-angle=swiftshader --enable-unsafe-swiftshader``).
With ``--disable-gpu`` instead, WebGL still falls back to SwiftShader but the page is composited
in software: every frame is read back from the WebGL canvas ("GPU stall due to ReadPixels" in the
log), which halves the frame rate of an animation.  Protocol: https://chromedevtools.github.io/
devtools-protocol/ (Target, Page, Runtime, Network, Log, Emulation).

A `Page` records every request the page makes (``Network.requestWillBeSent``) and every
console message, uncaught exception and browser log entry, for the tests to check that a
view requests nothing and logs nothing.
"""

from __future__ import annotations

import base64
import json
import os
import select
import shutil
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Any

from ..errors import OutputError

__all__ = ["FLAGS", "Browser", "Page", "find_chromium"]

#: Flags for a headless run with no GPU, no sandbox (as root) and no network of its own.
FLAGS = ("--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--disable-quic",
         "--disable-background-networking", "--disable-component-update", "--disable-sync", "--no-first-run",
         "--disable-default-apps", "--disable-extensions", "--mute-audio", "--hide-scrollbars",
         "--no-default-browser-check", "--disable-features=Translate,MediaRouter,OptimizationHints")


def find_chromium() -> str | None:
    """The path of a Chromium (or Chrome) executable on the PATH, or None."""
    for name in ("chromium", "chromium-browser", "google-chrome", "chrome"):
        found = shutil.which(name)
        if found:
            return found
    return None


class Browser:
    """One headless Chromium process; `open` a page in it, `close` it (or use it as a context manager)."""

    def __init__(self, executable: str | None = None, *, timeout: float = 90.0) -> None:
        executable = executable or find_chromium()
        if executable is None:
            raise OutputError("No Chromium is installed to render the view.",
                              fix="install Chromium (Debian: apt install chromium), or use the matplotlib drawing")
        self.timeout = timeout
        self.profile = tempfile.mkdtemp(prefix="lagrangian-chromium-")
        self.log = open(Path(self.profile) / "stderr.txt", "wb")  # noqa: SIM115 - closed in close()
        to_child, self._write = os.pipe()
        self._read, from_child = os.pipe()

        def descriptors() -> None:  # the child's fd 3 reads our commands, its fd 4 writes to us
            os.dup2(to_child, 3)
            os.dup2(from_child, 4)

        self.process = subprocess.Popen(
            [executable, *FLAGS, f"--user-data-dir={self.profile}", "--remote-debugging-pipe", "about:blank"],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=self.log, close_fds=False,
            preexec_fn=descriptors)  # noqa: PLW1509 - os.dup2 only
        os.close(to_child)
        os.close(from_child)
        self._buffer = b""
        self._id = 0
        self.events: list[dict[str, Any]] = []

    # -- the protocol ---------------------------------------------------------------------------------------------
    def send(self, method: str, params: dict[str, Any] | None = None, session: str | None = None,
             timeout: float | None = None) -> dict[str, Any]:
        """Send a command and wait for its answer (events met meanwhile are kept in ``events``)."""
        self._id += 1
        message: dict[str, Any] = {"id": self._id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(self._write, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + (timeout or self.timeout)
        while True:
            reply = self._next(deadline)
            if reply.get("id") == self._id:
                if "error" in reply:
                    raise OutputError(f"Chromium refused `{method}`: {reply['error'].get('message')}",
                                      fix="check the page and the Chromium version")
                return reply.get("result", {})
            self.events.append(reply)

    def _next(self, deadline: float) -> dict[str, Any]:
        while b"\0" not in self._buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                raise OutputError("Chromium did not answer in time.", fix="try again on a less busy machine")
            ready, _, _ = select.select([self._read], [], [], left)
            if ready:
                chunk = os.read(self._read, 1 << 20)
                if not chunk:
                    raise OutputError("Chromium stopped.", fix="see its messages: " + self.messages()[-500:])
                self._buffer += chunk
        line, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(line)

    def wait_event(self, method: str, session: str, timeout: float | None = None) -> dict[str, Any]:
        """Wait for event ``method`` of ``session`` (or return one already received)."""
        deadline = time.monotonic() + (timeout or self.timeout)
        while True:
            for k, e in enumerate(self.events):
                if e.get("method") == method and e.get("sessionId") == session:
                    return self.events.pop(k)
            self.events.append(self._next(deadline))

    def pump(self, seconds: float = 0.0) -> None:
        """Read the events that arrive within ``seconds``."""
        deadline = time.monotonic() + seconds
        while True:
            left = deadline - time.monotonic()
            ready, _, _ = select.select([self._read], [], [], max(left, 0))
            if not ready:
                if b"\0" not in self._buffer:
                    return
            else:
                chunk = os.read(self._read, 1 << 20)
                if not chunk:
                    return
                self._buffer += chunk
            while b"\0" in self._buffer:
                line, self._buffer = self._buffer.split(b"\0", 1)
                self.events.append(json.loads(line))
            if left <= 0:
                return

    def messages(self) -> str:
        self.log.flush()
        return (Path(self.profile) / "stderr.txt").read_text(errors="replace")

    # -- pages ----------------------------------------------------------------------------------------------------
    def open(self, url: str | Path, *, width: int = 800, height: int = 600) -> Page:
        """A new tab of ``width`` × ``height`` CSS pixels showing ``url`` (a path is opened as a file URL)."""
        if isinstance(url, Path) or (not str(url).startswith(("file:", "http:", "https:", "about:", "data:"))):
            url = Path(url).resolve().as_uri()
        target = self.send("Target.createTarget", {"url": "about:blank"})["targetId"]
        session = self.send("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        page = Page(self, session, str(url))
        for domain in ("Page", "Runtime", "Network", "Log"):
            self.send(f"{domain}.enable", session=session)
        self.send("Emulation.setDeviceMetricsOverride", {"width": width, "height": height, "deviceScaleFactor": 1,
                                                         "mobile": False}, session=session)
        self.send("Page.navigate", {"url": str(url)}, session=session)
        self.wait_event("Page.loadEventFired", session)
        return page

    def close(self) -> None:
        try:
            if self.process.poll() is None:
                try:
                    self.send("Browser.close", timeout=10)
                except (OutputError, OSError):
                    pass
                try:
                    self.process.wait(10)
                except subprocess.TimeoutExpired:
                    self.process.kill()
                    self.process.wait(10)
        finally:
            for fd in (self._write, self._read):
                try:
                    os.close(fd)
                except OSError:
                    pass
            self.log.close()
            shutil.rmtree(self.profile, ignore_errors=True)

    def __enter__(self) -> Browser:  # noqa: PYI034 - a final class
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class Page:
    """A tab: evaluate JavaScript, take screenshots, read what it requested and logged."""

    def __init__(self, browser: Browser, session: str, url: str) -> None:
        self.browser, self.session, self.url = browser, session, url

    def evaluate(self, expression: str, *, await_promise: bool = False, timeout: float | None = None) -> Any:
        """The value of ``expression`` (JSON-able), a page exception being an `OutputError`."""
        result = self.browser.send("Runtime.evaluate", {"expression": expression, "returnByValue": True,
                                                         "awaitPromise": await_promise}, self.session, timeout)
        if "exceptionDetails" in result:
            details = result["exceptionDetails"]
            text = details.get("exception", {}).get("description") or details.get("text")
            raise OutputError(f"The page's script failed: {text}", fix="see the browser's console")
        return result["result"].get("value")

    def wait_for(self, expression: str, timeout: float = 30.0) -> Any:
        """Poll ``expression`` until it is truthy; its value."""
        deadline = time.monotonic() + timeout
        while True:
            value = self.evaluate(expression)
            if value:
                return value
            if time.monotonic() > deadline:
                raise OutputError(f"The page never made `{expression}` true.", fix="see the browser's console")
            time.sleep(0.05)

    def front(self) -> None:
        """Make this the visible tab (a hidden one gets no animation frames)."""
        self.browser.send("Page.bringToFront", session=self.session)

    def screenshot(self) -> bytes:
        """The page as PNG bytes."""
        data = self.browser.send("Page.captureScreenshot", {"format": "png"}, self.session)["data"]
        return base64.b64decode(data)

    def _events(self, *methods: str) -> list[dict[str, Any]]:
        self.browser.pump(0.05)
        return [e for e in self.browser.events if e.get("sessionId") == self.session and e.get("method") in methods]

    def requests(self) -> list[str]:
        """The URL of every request the page made (its own file included)."""
        return [e["params"]["request"]["url"] for e in self._events("Network.requestWillBeSent")]

    def console(self) -> list[str]:
        """Console messages, uncaught exceptions and the browser's log entries about the page."""
        out = []
        for e in self._events("Runtime.consoleAPICalled", "Runtime.exceptionThrown", "Log.entryAdded"):
            p = e["params"]
            if e["method"] == "Runtime.consoleAPICalled":
                out.append(f"console.{p['type']}: " + " ".join(str(a.get("value", a.get("description", "")))
                                                             for a in p.get("args", [])))
            elif e["method"] == "Runtime.exceptionThrown":
                d = p["exceptionDetails"]
                out.append("exception: " + str(d.get("exception", {}).get("description") or d.get("text")))
            else:
                out.append(f"log.{p['entry'].get('level')}: {p['entry'].get('text')}")
        return out
