"""Chart and HTML report: geometry of the diverging bars, escaping of everything from input,
and the end-to-end command line on the rebuilt Table 1 data."""
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from matplotlib.figure import Figure

from analysis.__main__ import main
from html_ids import page_ids
from analysis.chart import diverging_bar
from analysis.ingest import survey_from_frame
from analysis.likert import summarize
from analysis.report import render_report
from analysis.tables import load_survey_facts

ROOT = Path(__file__).resolve().parents[1]


def test_chart_geometry():
    df = pd.DataFrame({"all neutral": ["Neutral"] * 4,
                       "half": ["Definitely Agree", "Definitely Agree", "Partially Disagree", ""]})
    s = summarize(survey_from_frame(df))
    fig = diverging_bar(s)
    assert isinstance(fig, Figure)
    ax = fig.axes[0]
    bars = [p for p in ax.patches if p.get_width() > 0]
    # questionnaire order top to bottom: first item has the highest y
    top = [b for b in bars if b.get_y() > 0.5]
    low = [b for b in bars if b.get_y() < 0.5]
    assert len(top) == 1 and top[0].get_x() == pytest.approx(-50) and top[0].get_width() == pytest.approx(100)
    # 'half': 1 of 3 valid disagree (left of 0), 2 of 3 agree (right of 0), no neutral
    xs = sorted((b.get_x(), b.get_x() + b.get_width()) for b in low)
    assert xs[0] == pytest.approx((-100 / 3, 0)) and xs[1] == pytest.approx((0, 200 / 3))
    by_y = {round(float(y)): t.get_text() for y, t in zip(ax.get_yticks(), ax.get_yticklabels())}
    assert by_y[1].startswith("all neutral") and "(n = 4)" in by_y[1] and "(n = 3)" in by_y[0]


# Each example renders the report with its two charts (~0.6 s of CPU, matplotlib). The alphabet
# has 10 characters: the explicit example puts every one of them, and an entity-like run, in every
# input place on every run; 6 random strings add orders and repetitions.
@settings(max_examples=6, deadline=None)
@example("<>&\"'$\\ab/&amp;")
@given(st.text(alphabet="<>&\"'$\\ab/", min_size=1, max_size=12))
def test_report_escapes_input(evil):
    head = f"<x-evil>{evil}"
    df = pd.DataFrame({head: ["Definitely Agree", "Neutral", "<x-evil>"],
                       "grp": [f"<x-evil>{evil}"] * 3, "q2": ["Neutral"] * 3})
    data = survey_from_frame(df, group="grp", unknown="missing", source=f"<x-evil>{evil}.csv")
    html = render_report(data, group="grp", min_group=1, title=f"<x-evil>{evil}")
    assert "<x-evil>" not in html and "&lt;x-evil&gt;" in html


def test_report_cli_end_to_end(tmp_path):
    data = tmp_path / "t1.csv"
    out = tmp_path / "report.html"
    assert main(["rebuild-table1", str(data)]) == 0
    first = data.read_text().splitlines()[0]
    assert first.startswith("#") and "REBUILT" in first and "marginals" in first
    assert main(["report", str(data), "-o", str(out), "--claims",
                 str(ROOT / "data/published/claims.toml")]) == 0
    html = out.read_text()
    svg = tmp_path / "chart.svg"
    assert main(["summarize", str(data), "--chart", str(svg)]) == 0
    assert svg.read_text().startswith("<svg")
    facts = load_survey_facts()
    assert "<svg" in html and "holds for this sample only" in html
    assert "Not computed" in html          # no alpha on data whose pairing is unknown
    assert f"{facts.respondents} respondents" in html
    assert 'src="http' not in html and "<link" not in html        # self-contained


def test_report_ids_are_unique_with_both_charts():
    """The items' chart and the groups' chart, both from matplotlib (which numbers the ids of every
    SVG alike: figure_1, axes_1, clip paths): each id of the page is its own, and every
    ``url(#X)`` and ``href="#X"`` reaches one (QA 19 #10 counted 79 repeated ids)."""
    df = pd.DataFrame({"q1": ["Definitely Agree", "Neutral", "Partially Disagree", "Neutral"] * 2,
                       "q2": ["Neutral", "Definitely Agree", "Neutral", "Partially Agree"] * 2,
                       "grp": ["a"] * 4 + ["b"] * 4})
    html = render_report(survey_from_frame(df, group="grp"), group="grp", min_group=1)
    assert html.count("<svg") == 2
    assert page_ids(html) == ([], [])


@pytest.mark.parametrize("name", ["r.pdf", "r.htm.txt", "report"])
def test_report_refuses_a_name_not_ending_in_html(tmp_path, capsys, name):
    """Regression: ``report -o r.pdf`` wrote HTML into a .pdf and exited 0. Like --table and
    --chart, -o is refused by its suffix, in one line naming it, before any work; nothing is
    written."""
    data = tmp_path / "t1.csv"
    assert main(["rebuild-table1", str(data)]) == 0
    capsys.readouterr()
    out = tmp_path / name
    assert main(["report", str(data), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err == (f"error: -o {str(out)!r}: the file name must end in .html (the report is "
                   f"an HTML page)\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["t1.csv"]


def test_bad_input_has_no_traceback(tmp_path):
    f = tmp_path / "x.csv"
    f.write_bytes(b"\xff\xfe\x00garbage")
    r = subprocess.run([sys.executable, "-m", "analysis", "summarize", str(f)], cwd=ROOT,
                       capture_output=True, text=True)
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert r.stderr.count("\n") == 1 and r.stderr.startswith(f"error: {f}")


def test_no_neutral_share_on_a_scale_without_a_neutral_answer():
    """Regression: a four-point scale's report showed "neutral 0.0% [0.0, 11.4]".
    By hand: Never, Often, Always, Always on frequency4 (Often and Always positive):
    agree 3/4 = 75.0 %, disagree 1/4 = 25.0 %; agree5 keeps its neutral column."""
    four = survey_from_frame(pd.DataFrame({"Q1": ["Never", "Often", "Always", "Always"]}),
                             scale="frequency4")
    html = render_report(four, reliability=False)
    head = "<th>Item</th><th>agree</th><th>disagree</th><th>median</th>"
    assert head in html and "<th>neutral</th>" not in html
    assert "<td>75.0% [" in html and "<td>25.0% [" in html
    assert "neutral split" not in html and "has no neutral answer" in html
    five = survey_from_frame(pd.DataFrame({"Q1": ["Disagree", "Agree", "Neutral"]}),
                             scale="agree5")
    assert "<th>agree</th><th>neutral</th><th>disagree</th>" in render_report(five, reliability=False)


def test_report_interval_bounds_follow_the_one_rule(monkeypatch):
    """The HTML report's agreement interval, like the text, rounds half away from zero (analysis.rounding):
    made-up bounds 0.0625 and 0.8125 (exact in binary, ties by design) print 6.3 and 81.3 ('%.1f': 6.2, 81.2)."""
    import pandas as pd

    import analysis.report as report_module
    from analysis.ingest import survey_from_frame
    from analysis.likert import Proportion

    real = report_module.summarize

    def tied(*args, **kwargs):
        s = real(*args, **kwargs)
        s.items[0].agree = Proportion(13, 16, 13 / 16, (0.0625, 0.8125), "wilson", 0.95)
        return s

    monkeypatch.setattr(report_module, "summarize", tied)
    data = survey_from_frame(pd.DataFrame({"q": ["Definitely Agree"] * 13 + ["Neutral"] * 3}))
    assert "81.3% [6.3, 81.3]" in report_module.render_report(data)


def test_group_chart_keeps_a_long_group_label_inside_the_png(tmp_path, capsys):
    """Regression: the layout measured the labels at 100 dpi and the PNG was drawn at 150, where
    the text is wider: the first character of '=HYPERLINK("http://e","x")' fell off the left
    edge. Reference: the PNG's own pixels; the layout keeps 3 pt (6 px at 150 dpi) clear of
    the edge, so the first 3 pixel columns must be background (white)."""
    from matplotlib.image import imread
    f = tmp_path / "g.csv"
    groups = ["-MATH", "@SUM(1)", '=HYPERLINK("http://e","x")', "<b>ENGR</b> &amp;"]
    f.write_text("course,Q1,Q2\n" + "".join(
        f'"{g.replace(chr(34), chr(34) * 2)}",{a},{b}\n' for g in groups
        for a, b in [("Agree", "Disagree"), ("Strongly agree", "Agree"),
                     ("Disagree", "Disagree"), ("Agree", "Agree"), ("Neutral", "Agree")]))
    png = tmp_path / "hg.png"
    assert main(["summarize", str(f), "--scale", "agree5", "--group", "course",
                 "--chart", str(png)]) == 0
    capsys.readouterr()
    pixels = imread(png)
    assert pixels.shape[1] == 1275                  # 8.5 in at 150 dpi
    assert (pixels[:, :3, :3] == 1.0).all(), "something is drawn at the left edge"


def test_count_labels_are_not_crossed_by_the_centre_line_or_the_grid():
    """QA10 item 5: the 0 % line ran through the neutral counts ("14", "9", "9", "27") and, with the
    report's grid, a grid line through every count. Drawn with the texts hidden, each count label's
    box must hold nothing but its segment's fill: every pixel within 2 of that colour (antialiasing
    touches only edges, and the box is shrunk by 1 pixel, the renderer's rounding)."""
    import numpy as np
    from matplotlib import rc_context
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.colors import to_rgba

    answers = (["Neutral"] * 3 + ["Partially Agree"] * 6 + ["Definitely Agree"] * 11
               + ["Partially Disagree"] * 2)
    df = pd.DataFrame({"item1": answers, "item2": answers[::-1]})
    with rc_context({"axes.grid": True, "grid.alpha": 0.3}):  # the report's grid (reports.figures.RC)
        fig = diverging_bar(summarize(survey_from_frame(df)))
        canvas = FigureCanvasAgg(fig)
        canvas.draw()
        ax = fig.axes[0]
        renderer = canvas.get_renderer()
        bars = [p for p in ax.patches if p.get_width() > 0]
        counts = []
        for t in ax.texts:
            x, y = t.get_position()
            under = [b for b in bars if b.get_x() < x < b.get_x() + b.get_width()
                     and b.get_y() < y < b.get_y() + b.get_height()]
            if under:  # a count inside its segment (the totals stand outside the bars)
                counts.append((t.get_window_extent(renderer), under[0].get_facecolor()))
        assert len(counts) >= 6  # three segments of two items, the neutral ones among them
        for t in ax.texts:
            t.set_visible(False)
        canvas.draw()
        image = np.asarray(canvas.buffer_rgba()).astype(int)
    height = image.shape[0]
    for box, colour in counts:
        x0, x1 = int(np.ceil(box.x0)) + 1, int(np.floor(box.x1)) - 1
        top, bottom = height - int(np.floor(box.y1)) + 1, height - int(np.ceil(box.y0)) - 1
        fill = np.round(np.array(to_rgba(colour)[:3]) * 255)
        patch = image[top:bottom, x0:x1, :3]
        assert patch.size and np.abs(patch - fill).max() <= 2, f"a line crosses the count at {box.extents}"


def test_report_shows_the_reading_notes_the_text_output_prints(tmp_path, capsys):
    """QA 11: the HTML report left out the notes reading made, which summarize prints (stderr) and
    its JSON carries: here, which sheet was read and which other sheet holds data, and an answer
    counted under n/a with its reason. The page shows the very lines the command line prints
    (escaped: the empty column is named <x-evil>, and a note names it)."""
    import openpyxl
    from markupsafe import escape

    path = tmp_path / "terms.xlsx"
    wb = openpyxl.Workbook()
    wb.remove(wb.active)
    for name, rows in {"Fall": [["id", "Q1", "Q2", "<x-evil>"], ["a", "Agree", "Prefer not to say", None],
                                ["b", "Disagree", "Agree", None], ["c", "Agree", "Agree", None]],
                       "Spring": [["id", "Q1"], ["d", "Agree"]]}.items():
        ws = wb.create_sheet(name)
        for r in rows:
            ws.append(r)
    wb.save(path)
    out = tmp_path / "report.html"
    assert main(["report", str(path), "-o", str(out)]) == 0
    lines = [x for x in capsys.readouterr().err.splitlines() if x.startswith(("note:", "warning:"))]
    assert any("sheet 'Spring' also holds data" in x for x in lines)
    assert any("'Prefer not to say' (declined to answer): 1 in 'Q2'" in x for x in lines)
    assert any("<x-evil>" in x for x in lines)
    html = out.read_text(encoding="utf-8")
    assert "<x-evil>" not in html
    for line in lines:
        assert f"<li>{escape(line)}</li>" in html, line
