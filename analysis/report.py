"""Self-contained HTML report of one survey (``python -m analysis report FILE -o OUT.html``).

The page holds the per-item table (percent and count per label, n, missing, not
applicable), the agreement / neutral / disagreement shares with intervals, the
median and IQR of the codes, the diverging bar chart as inline SVG, the notes reading
the file made (the same lines the command line prints), and, when asked, claims,
Cronbach's alpha and group comparisons. It is rendered with Jinja2
(``analysis/templates/survey_report.html.j2``) with autoescaping on, so every
text that came from the input (headers, question text, labels of custom scales,
group names, unknown answers) is escaped; only the SVG produced by matplotlib
(whose text matplotlib escapes itself) is inserted as markup. The file is written
atomically.

Public API: :func:`render_report` -> ``str``, :func:`build_report` -> ``Path``.
"""
from __future__ import annotations

from functools import cache
from pathlib import Path

from jinja2 import Environment, FileSystemLoader, StrictUndefined
from markupsafe import Markup
from solver.drawing.svg_ids import inline_svg  # standard library only: each figure's ids, unique in the page

from ._io import atomic_write
from .chart import diverging_bar, figure_svg
from .claims import evaluate_claims
from .ingest import SurveyData
from .likert import PERCENT_METHODS, REVERSE_NOTE, summarize
from .respondents import PAIRING_UNKNOWN
from .rounding import number_text, quartile_texts, share_percent_text, significant_text

__all__ = ["render_report", "build_report", "template_environment"]

_TEMPLATES = Path(__file__).resolve().parent / "templates"


def template_environment() -> Environment:
    """The Jinja2 environment (autoescape on for every template)."""
    env = Environment(loader=FileSystemLoader(str(_TEMPLATES)), autoescape=True,
                      undefined=StrictUndefined, trim_blocks=False, lstrip_blocks=False)
    env.filters["percent"] = share_percent_text  # a share 0..1 in percent by the one rounding rule
    env.filters["num"] = number_text             # a statistic to N places, by the same rule
    env.filters["sig"] = significant_text        # to N significant digits, by the same rule
    return env


@cache
def _report_environment() -> Environment:
    """The one environment the reports of a process render with: Jinja2 compiles a template
    once per environment (some 30 ms), and checks the file's time stamp on each use."""
    return template_environment()


def _fmt(x, digits: int = 1) -> str:
    return number_text(x, digits, none="–")   # half away from zero, as percentages


def _validate_report(data, decimals, percent_method):
    if not isinstance(data, SurveyData):
        raise TypeError(f"`data` must be SurveyData, got {type(data).__name__}")
    if not isinstance(decimals, int) or not 0 <= decimals <= 4:
        raise ValueError(f"`decimals` must be an integer 0..4, got {decimals!r}")
    if percent_method not in PERCENT_METHODS:
        raise ValueError(f"`percent_method` must be one of {list(PERCENT_METHODS)}, "
                         f"got {percent_method!r}")


def render_report(data: SurveyData, claims=None, group: str | None = None, min_group: int = 5,
                  group_order: "list[str] | None" = None, paired: "bool | None" = None,
                  title: str | None = None, confidence_level: float = 0.95,
                  method: str = "wilson", decimals: int = 1, percent_method: str = "round",
                  reliability: bool = True) -> str:
    """HTML text of the survey report.

    Parameters
    ----------
    data : SurveyData
    claims : str, Path or list of Claim, optional
        Claims to evaluate.
    group : str, optional
        Grouping column (the survey must have been read with ``group=``).
    min_group : int
        Smallest group shown.
    group_order : list of str, optional
        Order of the groups (default: first appearance).
    paired : bool or None
        Pairing of two groups by respondent id, as
        :func:`~analysis.groups.compare_groups` takes it (None: the automatic rule).
    title : str, optional
    confidence_level : float
    method : {"wilson", "beta"}
    decimals : int
        Printed decimals of percentages.
    percent_method : {"round", "largest_remainder"}
    reliability : bool
        Add Cronbach's alpha of all items (when there are two or more), unless the
        file says it was rebuilt from marginals (pairing of answers unknown).

    Returns
    -------
    str
    """
    _validate_report(data, decimals, percent_method)
    s = summarize(data, confidence_level, method)
    svg = inline_svg(figure_svg(diverging_bar(s)), "chart")
    claims_rep = evaluate_claims(claims, s, confidence_level, method) if claims else None
    groups = None
    group_svg = None
    if group:
        from .chart import faceted_bar
        from .groups import compare_groups
        groups = compare_groups(data, group, min_group, order=group_order, paired=paired)
        if groups.shown:
            group_svg = Markup(inline_svg(figure_svg(faceted_bar(groups)), "groups"))
    rel = None
    pairing_unknown = any(PAIRING_UNKNOWN in c for c in data.comments)
    if reliability and len(data.items) >= 2 and not pairing_unknown:
        from .reliability import cronbach_alpha_for
        rel = cronbach_alpha_for(data, None, confidence_level)
    rounding = ("half away from zero to %d decimal(s)" % decimals if percent_method == "round"
                else "by largest remainder so that every row adds up to exactly 100")
    return _report_environment().get_template("survey_report.html.j2").render(
        title=title or f"Survey report: {Path(data.source).name}", s=s,
        printed=[it.printed_percent(decimals, percent_method) for it in s.items],
        decimals=decimals, percent_method=percent_method, rounding_note=rounding,
        reverse_note=REVERSE_NOTE if any(it.reverse for it in s.items) else "",
        ci_name={"wilson": "Wilson", "beta": "Clopper-Pearson"}[method],
        fmt=_fmt, quartiles=lambda q1, q3: quartile_texts(q1, q3, none="–"), svg=Markup(svg), claims=claims_rep, groups=groups, group_svg=group_svg,
        reliability=rel,
        comments=data.comments, notes=data.note_lines(), pairing_unknown=pairing_unknown)


def report_path(path: "str | Path") -> Path:
    """The report's output path, refused (ValueError naming ``-o``) unless it ends in
    ``.html``: the report is HTML, and a ``.pdf`` holding HTML would open as a broken PDF."""
    p = Path(str(path))
    if p.suffix.lower() != ".html":
        raise ValueError(f"-o {str(path)!r}: the file name must end in .html (the report "
                         f"is an HTML page)")
    return p


def build_report(data: SurveyData, out_path: "str | Path", **kwargs) -> Path:
    """Render the report (see :func:`render_report`) and write it atomically to ``out_path``
    (a name ending in ``.html``, :func:`report_path`)."""
    report_path(out_path)
    html = render_report(data, **kwargs)
    return atomic_write(out_path, html)
