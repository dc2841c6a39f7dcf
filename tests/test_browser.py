"""The report, the paper and a worked solution open cleanly in a real browser (headless Chromium).

Each page is loaded through the DevTools protocol over a pipe
(``--remote-debugging-pipe``: JSON messages separated by NUL bytes on file
descriptors 3 and 4, no network port, no extra package). The test fails on
console errors or uncaught exceptions, resources that fail to load, images or
SVG figures that do not render, MathML that the browser does not lay out, and
leftover TeX source (``$...$``, ``\\frac``) in the page text. A screenshot of
each page is saved next to the build for a person to look at. The worked solution is Example 1's
(``solver explain data/scenes/sliding_bar.toml -o ...html``): its MathML, dots and free-body diagram
are held to the same checks as the paper's.

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
  out.pageWidth = document.documentElement.scrollWidth;
  out.viewWidth = document.documentElement.clientWidth;
  // a table of checks whose columns run past its scrolling box hides the verdict and detail columns
  out.cutTables = Array.from(document.querySelectorAll('div.wide')).filter(
    d => d.querySelector('td.verdict') && d.scrollWidth > d.clientWidth + 1).length;
  out.splitVerdicts = Array.from(document.querySelectorAll('td.verdict')).filter(c => {
    const r = document.createRange(); r.selectNodeContents(c);
    return r.getClientRects().length !== 1 || c.scrollWidth > c.clientWidth + 1; }).length;
  out.verdictCells = document.querySelectorAll('td.verdict').length;
  out.rawDocMarkup = (text.match(/:func:`|:class:`|``/g) || []).length;
  return JSON.stringify(out);
})()
"""


class DevTools:
    """A minimal DevTools-protocol client over Chromium's debugging pipe."""

    def __init__(self, user_data_dir: Path, env: dict | None = None):
        to_chrome_r, self._to_chrome = os.pipe()
        self._from_chrome, from_chrome_w = os.pipe()

        def wire():  # in the child: fd 3 = commands in, fd 4 = replies out
            os.dup2(to_chrome_r, 3)
            os.dup2(from_chrome_w, 4)

        self.proc = subprocess.Popen(
            [CHROMIUM, *FLAGS, f"--user-data-dir={user_data_dir}", "about:blank"],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            preexec_fn=wire, pass_fds=(3, 4), close_fds=True, env=env,
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

    def wait_for(self, method: str, session: str | None = None) -> dict:
        """The first event ``method`` (of target ``session`` when given; one browser may show several pages)."""
        def wanted(event):
            return event.get("method") == method and (session is None or event.get("sessionId") == session)

        for event in self.events:
            if wanted(event):
                return event
        deadline = time.monotonic() + TIMEOUT_S
        while True:
            event = self._read_message(deadline)
            self.events.append(event)
            if wanted(event):
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


EXPLAINED = "explain_sliding_bar.html"
"""The worked solution's page among the pages tested (written by ``solver explain``, not the report build)."""


@pytest.fixture(scope="module")
def explained(tmp_path_factory) -> Path:
    """Example 1's worked solution as ``python -m solver explain ... -o FILE.html`` writes it."""
    from solver.__main__ import main  # in this process: the command's own code path, without a second interpreter

    out = tmp_path_factory.mktemp("explain") / EXPLAINED
    assert main(["explain", str(ROOT / "data" / "scenes" / "sliding_bar.toml"), "-o", str(out)]) == 0
    return out


@pytest.fixture(scope="module")
def pages(request):
    """Page name -> its file (the report's pages are built only by the tests that show them)."""
    def path(page: str) -> Path:
        if page == EXPLAINED:
            return request.getfixturevalue("explained")
        return request.getfixturevalue("built") / page
    return path


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    """One Chromium (with the machine's fonts) for the pages of :func:`test_page_renders_in_chromium`:
    each page opens in a target of its own, so the pages share only the start-up (about 0.7 s of
    CPU per launch) and the profile folder; each page's errors are the events of its own session."""
    tools = DevTools(tmp_path_factory.mktemp("chromium") / "profile")
    yield tools
    tools.close()


@pytest.mark.parametrize("page", ["report.html", "paper.html", EXPLAINED])
def test_page_renders_in_chromium(pages, page, browser):
    path = pages(page)
    built = path.parent
    assert path.is_file(), f"{page} was not built"
    tools = browser
    tools.events.clear()  # events of an earlier page (they carry its session) are not this page's
    target = tools.send("Target.createTarget", {"url": "about:blank"})["targetId"]
    try:
        session = tools.send("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        for domain in ("Runtime", "Log", "Page", "Network"):
            tools.send(f"{domain}.enable", session=session)
        tools.send("Page.navigate", {"url": path.as_uri()}, session=session)
        tools.wait_for("Page.loadEventFired", session=session)
        probe = json.loads(
            tools.send("Runtime.evaluate", {"expression": PROBE, "returnByValue": True}, session=session)["result"]["value"]
        )
        shot = tools.send("Page.captureScreenshot", {"format": "png"}, session=session)["data"]
        (built / f"{Path(page).stem}.png").write_bytes(base64.b64decode(shot))
        errors = _console_errors([e for e in tools.events if e.get("sessionId") == session])
    finally:
        tools.send("Target.closeTarget", {"targetId": target})

    assert not errors, f"{page}: browser errors: {errors}"
    assert probe["math"] >= 10, f"{page}: expected the equations as MathML, found {probe['math']} <math> elements"
    assert probe["mathNotMathML"] == 0, f"{page}: {probe['mathNotMathML']} <math> elements not recognised as MathML"
    assert probe["mathZeroSize"] == 0, f"{page}: {probe['mathZeroSize']} equations render with no size"
    assert probe["mathNotLaidOut"] == 0, f"{page}: {probe['mathNotLaidOut']} equations not laid out as math"
    assert probe["brokenImages"] == [], f"{page}: images that did not load: {probe['brokenImages']}"
    figures = 1 if page == EXPLAINED else 2  # Example 1 has one body: one free-body diagram
    assert probe["svgs"] >= figures and probe["emptySvgs"] == 0, f"{page}: figures missing or empty: {probe}"
    assert probe["texLeftovers"] == 0, f"{page}: raw TeX left in the text"
    assert probe["scripts"] == 0 and probe["external"] == [], f"{page}: scripts or network resources: {probe}"
    # at the 1280 px window nothing is wider than the page (a wide table of equations scrolls by itself)
    assert probe["pageWidth"] <= probe["viewWidth"], f"{page}: wider than the window: {probe['pageWidth']} px"
    # every column of the tables of checks shows on the page at 1280 px: the verdict on one line, whole
    assert probe["cutTables"] == 0, f"{page}: {probe['cutTables']} tables of checks wider than the page"
    assert probe["splitVerdicts"] == 0, f"{page}: {probe['splitVerdicts']} verdicts wrapped or clipped"
    assert page != "report.html" or probe["verdictCells"] > 100, f"{page}: the verdict cells are not marked"
    assert probe["rawDocMarkup"] == 0, f"{page}: reST markup (``x``, :func:`x`) shown raw"
    assert len(base64.b64decode(shot)) > 20_000, f"{page}: screenshot suspiciously small (blank page?)"


# --------------------------------------------------------------------------- the maths font
# A machine without a maths font: fontconfig limited to the system's fonts with every maths
# font rejected, for the browser started by the test (CI's fresh machines have none either).
NO_MATHS_FONTS = """<?xml version="1.0"?>
<!DOCTYPE fontconfig SYSTEM "fonts.dtd">
<fontconfig>
  <dir>/usr/share/fonts</dir>
  <cachedir>{cache}</cachedir>
  <selectfont><rejectfont><glob>*Math*</glob><glob>*math*</glob></rejectfont></selectfont>
</fontconfig>
"""

# Marks the dotted rates (theta_dot, theta_ddot) and the sums with limits, for the test to find.
MARK = r"""
(async () => {
  await document.fonts.ready;
  const accents = Array.from(document.querySelectorAll('mover')).filter(m => m.children.length === 2 &&
      m.children[1].localName === 'mo' && ['\u02d9', '\u00a8'].includes(m.children[1].textContent));
  accents.forEach((m, i) => m.setAttribute('data-accent', i));
  const sums = Array.from(document.querySelectorAll('munderover, munder')).filter(m => m.children[0].textContent === '\u2211');
  sums.forEach((m, i) => m.setAttribute('data-sum', i));
  return JSON.stringify({accents: accents.map(m => [m.children[1].textContent, getComputedStyle(m.children[1]).fontSize]),
                         sums: sums.length});
})()
"""


def _place(selector: str, hide: int | None = None) -> str:
    """JS: scroll the element into view, hide child ``hide`` (or show all), return its and its children's boxes."""
    return f"""(() => {{
      const m = document.querySelector('{selector}');
      m.scrollIntoView({{block: 'center'}});
      Array.from(m.children).forEach((c, i) => c.style.visibility = (i === {-1 if hide is None else hide}) ? 'hidden' : 'visible');
      const box = e => {{ const r = e.getBoundingClientRect(); return [r.left + scrollX, r.top + scrollY, r.width, r.height]; }};
      return JSON.stringify({{box: box(m), children: Array.from(m.children).map(box)}});
    }})()"""


class Page:
    """One page loaded in the test's Chromium, with pixel access to parts of it."""

    def __init__(self, tools: DevTools, path: Path):
        self.tools = tools
        self.target = tools.send("Target.createTarget", {"url": "about:blank"})["targetId"]
        self.session = tools.send("Target.attachToTarget", {"targetId": self.target, "flatten": True})["sessionId"]
        for domain in ("Runtime", "Page", "DOM", "CSS"):
            tools.send(f"{domain}.enable", session=self.session)
        tools.send("Page.navigate", {"url": path.as_uri()}, session=self.session)
        tools.wait_for("Page.loadEventFired", session=self.session)

    def js(self, expression: str):
        reply = self.tools.send("Runtime.evaluate", {"expression": expression, "returnByValue": True,
                                                      "awaitPromise": True}, session=self.session)
        return json.loads(reply["result"]["value"])

    def pixels(self, clip) -> "np.ndarray":
        import io

        import numpy as np
        from PIL import Image

        x, y, w, h = clip
        data = self.tools.send("Page.captureScreenshot", {"format": "png", "clip": {
            "x": x, "y": y, "width": w, "height": h, "scale": 1}}, session=self.session)["data"]
        return np.asarray(Image.open(io.BytesIO(base64.b64decode(data))).convert("L")).astype(int)

    def ink_of_children(self, selector: str, count: int) -> tuple[list, list]:
        """For each child of the element: the pixels that change when it alone is hidden (its ink).

        Returns (ink masks in the clip's pixels, the children's layout boxes relative to the clip).
        """
        import numpy as np

        shown = self.js(_place(selector))
        pad = 4  # px around the element: room for ink that overflows its layout box
        x, y, w, h = shown["box"]
        clip = (x - pad, y - pad, w + 2 * pad, h + 2 * pad)
        whole = self.pixels(clip)
        inks = []
        for k in range(count):
            self.js(_place(selector, hide=k))
            # a change of more than 60 of 255 grey levels: the anti-aliased edge of real ink, not rounding noise
            inks.append(np.abs(whole - self.pixels(clip)) > 60)
        self.js(_place(selector))
        boxes = [(bx - clip[0], by - clip[1], bw, bh) for bx, by, bw, bh in shown["children"]]
        return inks, boxes, whole

    def font_of(self, selector: str) -> list[dict]:
        root = self.tools.send("DOM.getDocument", {"depth": 0}, session=self.session)["root"]["nodeId"]
        node = self.tools.send("DOM.querySelector", {"nodeId": root, "selector": selector},
                               session=self.session)["nodeId"]
        return self.tools.send("CSS.getPlatformFontsForNode", {"nodeId": node}, session=self.session)["fonts"]




@pytest.fixture(scope="module")
def browser_without_maths_fonts(tmp_path_factory):
    """One Chromium whose fontconfig rejects every maths font (:data:`NO_MATHS_FONTS`), for the pages of
    :func:`test_accents_and_sum_limits_are_visible_without_a_system_maths_font` (a target each)."""
    folder = tmp_path_factory.mktemp("chromium_no_maths_fonts")
    conf = folder / "fonts.conf"
    conf.write_text(NO_MATHS_FONTS.format(cache=folder / "fc-cache"), encoding="utf-8")
    tools = DevTools(folder / "profile", env={**os.environ, "FONTCONFIG_FILE": str(conf)})
    yield tools
    tools.close()


@pytest.mark.parametrize("page", ["paper.html", "report.html", EXPLAINED])
def test_accents_and_sum_limits_are_visible_without_a_system_maths_font(pages, page, browser_without_maths_fonts):
    """The dots of theta_dot and theta_ddot, and the limits of a sum, measured on the screen.

    Each accent's ink is found by hiding it and comparing pixels: it must exist, be dark
    (at least mid-grey where it is darkest), lie above the letter's ink and over it, and be
    drawn with the embedded maths font, whatever fonts the machine has. A sum's limits must
    not touch the sigma.
    """
    import numpy as np

    from reports.mathfont import FAMILY

    tools = browser_without_maths_fonts
    view = Page(tools, pages(page))
    try:
        marked = view.js(MARK)
        kinds = [kind for kind, _ in marked["accents"]]
        assert {"\u02d9", "\u00a8"} <= set(kinds), f"{page}: expected dotted and double-dotted rates, found {kinds}"
        fonts = view.font_of('[data-accent="0"] > mo')
        assert [f["familyName"] for f in fonts] == [FAMILY] and fonts[0]["isCustomFont"], \
            f"{page}: the accent is drawn with {fonts}, not the embedded maths font"
        # the first accent of each kind at each size: in the text, in fractions and in scripts
        chosen = sorted({tuple(a): i for i, a in reversed(list(enumerate(marked["accents"])))}.values())
        for i in chosen:
            (base_ink, accent_ink), (base_box, _), whole = view.ink_of_children(f'[data-accent="{i}"]', 2)
            what = f"{page}: accent {i} ({kinds[i]!r})"
            assert accent_ink.sum() >= 2, f"{what}: no visible ink ({accent_ink.sum()} pixels)"
            assert whole[accent_ink].min() <= 128, f"{what}: too faint (darkest grey level {whole[accent_ink].min()})"
            ay, ax = np.nonzero(accent_ink)
            by, bx = np.nonzero(base_ink)
            assert by.size, f"{what}: the letter has no ink"
            assert ay.max() < by.min(), f"{what}: the dots are not above the letter (rows {ay.max()} >= {by.min()})"
            # 1 px: anti-aliasing of the dots' edges
            assert bx.min() - 1 <= ax.min() and ax.max() <= bx.max() + 1, f"{what}: the dots are not over the letter"
        for i in range(marked["sums"]):
            inks, _, _ = view.ink_of_children(f'[data-sum="{i}"]', 3)
            op_rows = np.nonzero(inks[0].any(axis=1))[0]
            under_rows = np.nonzero(inks[1].any(axis=1))[0]
            assert op_rows.size and under_rows.size and op_rows.max() < under_rows.min(), \
                f"{page}: sum {i}: the lower limit touches the sigma"
            if len(inks) > 2 and inks[2].any():
                over_rows = np.nonzero(inks[2].any(axis=1))[0]
                assert over_rows.max() < op_rows.min(), f"{page}: sum {i}: the upper limit touches the sigma"
    finally:
        tools.send("Target.closeTarget", {"targetId": view.target})


# Each label of a drawing: its font size on the screen [CSS px], from the SVG's own size and its scale.
LABEL_SIZES = r"""
(() => {
  const texts = Array.from(document.querySelectorAll('figure.fbd svg text'));
  const body = parseFloat(getComputedStyle(document.querySelector('p')).fontSize);
  return JSON.stringify({body: body, labels: texts.map(t => parseFloat(t.style.fontSize) * t.getScreenCTM().a),
                         width: document.querySelector('figure.fbd svg').getBoundingClientRect().width,
                         text: document.querySelector('p').getBoundingClientRect().width});
})()
"""


def test_worked_solution_free_body_diagram_reads_at_the_page_width(explained, browser):
    """The free-body diagram of the HTML worked solution is drawn wide enough that its labels
    (forces and their sizes) are at least 85 % of the text's size: matplotlib's 331 pt figure at its
    own size wrote them at 8 pt (10.7 px) beside 16 px text. 85 %: a label a little smaller than the
    text still reads; 10.7/16 = 67 % did not."""
    tools = browser
    view = Page(tools, explained)
    try:
        sizes = view.js(LABEL_SIZES)
    finally:
        tools.send("Target.closeTarget", {"targetId": view.target})
    assert sizes["labels"], "no labels found in the free-body diagram"
    assert min(sizes["labels"]) >= 0.85 * sizes["body"], sizes
    assert sizes["width"] <= sizes["text"] + 1, f"the diagram is wider than the text column: {sizes}"


# Each term's note of the worked solution's term-by-term equations: how far it runs past the visible
# part of its equation's box (a box wider than the page scrolls sideways, hiding what lies beyond).
HIDDEN_NOTES = r"""
(() => {
  const notes = Array.from(document.querySelectorAll('div.eq span.note'));
  const hidden = notes.filter(n => {
    const box = n.closest('div.eq'), r = n.getBoundingClientRect(), b = box.getBoundingClientRect();
    return r.right > b.left + box.clientWidth + 1; }).map(n => n.textContent);
  return JSON.stringify({notes: notes.length, hidden: hidden});
})()
"""


def test_worked_solution_term_notes_show_beside_wide_equations(tmp_path, browser):
    """The four-bar's coupler has terms too wide for a note beside them at the page's width (its
    a_G = a_A/2 + a_B/2 and its Euler equation's inertial term): every term's note (which term is
    the moment of which force, which is the inertial term) shows without scrolling, at the 1280 px
    window. Before, they sat right of the widest term, past the scrolling box's edge."""
    from solver.__main__ import main

    page = tmp_path / "four_bar.html"
    assert main(["explain", str(ROOT / "data" / "scenes" / "four_bar.toml"), "-o", str(page)]) == 0
    view = Page(browser, page)
    try:
        found = view.js(HIDDEN_NOTES)
    finally:
        browser.send("Target.closeTarget", {"targetId": view.target})
    assert found["notes"] > 50, f"the term notes were not found: {found}"
    assert found["hidden"] == [], f"notes hidden past the equation's visible width: {found['hidden']}"
