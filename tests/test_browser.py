"""The report and the paper open cleanly in a real browser (headless Chromium).

Each page is loaded through the DevTools protocol over a pipe
(``--remote-debugging-pipe``: JSON messages separated by NUL bytes on file
descriptors 3 and 4, no network port, no extra package). The test fails on
console errors or uncaught exceptions, resources that fail to load, images or
SVG figures that do not render, MathML that the browser does not lay out, and
leftover TeX source (``$...$``, ``\\frac``) in the page text. A screenshot of
each page is saved next to the build for a person to look at.

Skipped, with the reason, when Chromium is not installed (.ci/run installs it).
"""
from __future__ import annotations

import base64
import json
import os
import select
import shutil
import subprocess
import time
from pathlib import Path

import pytest

from reports.make_report import ROOT, build_cached

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="chromium is not installed (.ci/run installs Debian's chromium)")

FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-dev-shm-usage",
    "--window-size=1280,1600",
    "--remote-debugging-pipe",
]
TIMEOUT_S = 60.0
"""Longest wait for one DevTools answer or the load event (a cold Chromium start on 2 busy cores)."""

# Evaluated in the page by the test only; the pages themselves run no script.
PROBE = r"""
(() => {
  const out = {};
  const maths = Array.from(document.querySelectorAll('math'));
  out.math = maths.length;
  out.mathNotMathML = maths.filter(m => !(window.MathMLElement && m instanceof MathMLElement)).length;
  out.mathZeroSize = maths.filter(m => { const r = m.getBoundingClientRect(); return !(r.width > 0 && r.height > 0); }).length;
  out.mathNotLaidOut = maths.filter(m => !/math/.test(getComputedStyle(m).display)).length;
  const imgs = Array.from(document.images);
  out.images = imgs.length;
  out.brokenImages = imgs.filter(i => !(i.complete && i.naturalWidth > 0)).map(i => i.src);
  const svgs = Array.from(document.querySelectorAll('figure svg'));
  out.svgs = svgs.length;
  out.emptySvgs = svgs.filter(s => { const r = s.getBoundingClientRect(); return !(r.width > 50 && r.height > 50 && s.querySelector('path, use, text')); }).length;
  const text = document.body.innerText;
  out.texLeftovers = (text.match(/\$\$|\\frac|\\left|\\begin\{|\\\(|\\\[/g) || []).length;
  out.scripts = document.querySelectorAll('script').length;
  out.external = Array.from(document.querySelectorAll('[src], link[href]')).map(e => e.src || e.href).filter(u => /^https?:/.test(u));
  return JSON.stringify(out);
})()
"""


class DevTools:
    """A minimal DevTools-protocol client over Chromium's debugging pipe."""

    def __init__(self, user_data_dir: Path):
        to_chrome_r, self._to_chrome = os.pipe()
        self._from_chrome, from_chrome_w = os.pipe()

        def wire():  # in the child: fd 3 = commands in, fd 4 = replies out
            os.dup2(to_chrome_r, 3)
            os.dup2(from_chrome_w, 4)

        self.proc = subprocess.Popen(
            [CHROMIUM, *FLAGS, f"--user-data-dir={user_data_dir}", "about:blank"],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            preexec_fn=wire, pass_fds=(3, 4), close_fds=True,
        )
        os.close(to_chrome_r)
        os.close(from_chrome_w)
        self._buffer = b""
        self._next_id = 0
        self.events: list[dict] = []

    def _read_message(self, deadline: float) -> dict:
        while b"\0" not in self._buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError("no answer from chromium")
            ready, _, _ = select.select([self._from_chrome], [], [], left)
            if ready:
                chunk = os.read(self._from_chrome, 1 << 20)
                if not chunk:
                    raise RuntimeError("chromium closed the debugging pipe")
                self._buffer += chunk
        raw, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(raw)

    def send(self, method: str, params: dict | None = None, session: str | None = None) -> dict:
        self._next_id += 1
        message = {"id": self._next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(self._to_chrome, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + TIMEOUT_S
        while True:
            reply = self._read_message(deadline)
            if reply.get("id") == self._next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            self.events.append(reply)

    def wait_for(self, method: str) -> dict:
        for event in self.events:
            if event.get("method") == method:
                return event
        deadline = time.monotonic() + TIMEOUT_S
        while True:
            event = self._read_message(deadline)
            self.events.append(event)
            if event.get("method") == method:
                return event

    def close(self) -> None:
        try:
            self.send("Browser.close")
        except Exception:  # noqa: BLE001 - the browser may already be gone
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        os.close(self._to_chrome)
        os.close(self._from_chrome)


def _console_errors(events: list[dict]) -> list[str]:
    errors = []
    for e in events:
        method, params = e.get("method"), e.get("params", {})
        if method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
            errors.append("console: " + " ".join(str(a.get("value", a.get("description", ""))) for a in params.get("args", [])))
        elif method == "Runtime.exceptionThrown":
            errors.append("exception: " + params.get("exceptionDetails", {}).get("text", ""))
        elif method == "Log.entryAdded" and params.get("entry", {}).get("level") == "error":
            entry = params["entry"]
            errors.append(f"log ({entry.get('source')}): {entry.get('text')} {entry.get('url', '')}")
        elif method == "Network.loadingFailed":
            errors.append(f"failed to load: {params.get('errorText')}")
    return errors


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> Path:
    """The report built once per test session (same code path as `make report`)."""
    out = tmp_path_factory.getbasetemp() / "report_build"
    build_cached(out, ROOT)
    return out


@pytest.mark.parametrize("page", ["report.html", "paper.html"])
def test_page_renders_in_chromium(built, page, tmp_path):
    path = built / page
    assert path.is_file(), f"{page} was not built"
    tools = DevTools(tmp_path / "profile")
    try:
        target = tools.send("Target.createTarget", {"url": "about:blank"})["targetId"]
        session = tools.send("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        for domain in ("Runtime", "Log", "Page", "Network"):
            tools.send(f"{domain}.enable", session=session)
        tools.send("Page.navigate", {"url": path.as_uri()}, session=session)
        tools.wait_for("Page.loadEventFired")
        probe = json.loads(
            tools.send("Runtime.evaluate", {"expression": PROBE, "returnByValue": True}, session=session)["result"]["value"]
        )
        shot = tools.send("Page.captureScreenshot", {"format": "png"}, session=session)["data"]
        (built / f"{Path(page).stem}.png").write_bytes(base64.b64decode(shot))
        errors = _console_errors(tools.events)
    finally:
        tools.close()

    assert not errors, f"{page}: browser errors: {errors}"
    assert probe["math"] >= 10, f"{page}: expected the equations as MathML, found {probe['math']} <math> elements"
    assert probe["mathNotMathML"] == 0, f"{page}: {probe['mathNotMathML']} <math> elements not recognised as MathML"
    assert probe["mathZeroSize"] == 0, f"{page}: {probe['mathZeroSize']} equations render with no size"
    assert probe["mathNotLaidOut"] == 0, f"{page}: {probe['mathNotLaidOut']} equations not laid out as math"
    assert probe["brokenImages"] == [], f"{page}: images that did not load: {probe['brokenImages']}"
    assert probe["svgs"] >= 2 and probe["emptySvgs"] == 0, f"{page}: figures missing or empty: {probe}"
    assert probe["texLeftovers"] == 0, f"{page}: raw TeX left in the text"
    assert probe["scripts"] == 0 and probe["external"] == [], f"{page}: scripts or network resources: {probe}"
    assert len(base64.b64decode(shot)) > 20_000, f"{page}: screenshot suspiciously small (blank page?)"
