"""Build the verification report and the reproducible paper (``make report``).

``python -m reports [--out DIR] [--pdf auto|never]`` (:mod:`reports.cli`) writes into DIR
(default ``reports/build``):

* ``report.html``: every published number and equation with its verdict,
  the findings that differ from the paper first;
* ``verification.json``: the same rows, machine-readable;
* ``paper.html`` and ``paper.tex`` (and ``paper.pdf`` when a LaTeX engine is
  installed): the paper rewritten from computed results;
* ``figures/*.svg`` (+ ``*.pdf`` for LaTeX) and ``table1_respondents.csv``.

Outputs are written to a temporary folder first and moved into place only when
everything succeeded, so a failed build leaves the previous outputs intact.
Bad input ends the build with one line naming the file and place, exit status 2.
"""
from __future__ import annotations

import hashlib
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import jinja2
import sympy as sp
from jinja2 import Environment, FileSystemBytecodeCache, FileSystemLoader, StrictUndefined, select_autoescape
from jinja2.bccache import Bucket
from markupsafe import Markup

from reports import checks as checks_mod
from reports import figures, mathfont, paper, provenance
from reports.cli import cyclic_gc_paused, main, validate_build
from reports.mathml import equation_mathml, latex_display, name_text, to_mathml, transcription_mathml
from solver.mathml import minus_signs
from reports.published import ReportInputError, load_equations
from solver.drawing.svg_ids import inline_svg
from solver.errors import InputError
from solver.expressions import parse_expression
from solver.notation import latex_escape  # (the one LaTeX text escape; re-exported)

__all__ = ["build", "build_cached", "main", "html_environment", "latex_environment", "latex_escape", "LATEX_ENGINES",
           "TemplateCache", "write_template_cache"]

ROOT = Path(__file__).resolve().parent.parent
TEMPLATES = Path(__file__).resolve().parent / "templates"
TEMPLATE_CACHE = Path(__file__).resolve().parent / "__pycache__" / "templates"
"""Where the templates' compiled code is kept (:class:`TemplateCache`): git-ignored, beside the
package's Python bytecode."""
LATEX_ENGINES = ("tectonic", "lualatex", "pdflatex", "xelatex")
"""LaTeX engines tried, in order, for paper.pdf."""


EX1_STEPS = ("accelerations", "omega", "alpha", "inertia", "alpha_solution", "reactions")
EX2_STEPS = ("omega", "alpha", "inertia", "eom", "reactions")
"""The worked steps the paper shows of each example (``ex1.steps`` and ``ex2.steps`` in the templates;
:func:`reports.paper.example_steps` builds only these)."""


# --------------------------------------------------------------------------- environments
_JINJA_OPTIMIZER = False
"""Jinja's compile-time optimizer (constant folding in the generated code) is off: a template is
compiled at most once per build (not at all when :class:`TemplateCache` holds its code) and rendered
once, so the pass costs more than it saves (about 15 % of compiling the three templates); the output
is the same."""


class TemplateCache(FileSystemBytecodeCache):
    """The compiled code of the templates, kept on disk: the templates' analogue of Python's bytecode.

    Jinja compiles a template into Python code each time a new environment loads it (about 70 ms
    of a build for the three templates); with this cache a build loads the code compiled by an
    earlier one. A file is used only while the template's text and everything in the environment
    that shapes the compiled code (:func:`_compile_signature`) are the same as when it was written;
    otherwise the template is compiled again and the file replaced. Like Python's bytecode, the
    files are not written when ``sys.dont_write_bytecode`` is set (``PYTHONDONTWRITEBYTECODE``),
    unless ``write`` says so, and a folder that cannot be written leaves the build compiling its
    templates as before.

    Parameters
    ----------
    directory : pathlib.Path
        Folder of the files (default :data:`TEMPLATE_CACHE`).
    write : bool, optional
        Write the compiled code: always (True), never (False), or as Python writes bytecode (None).
    """

    def __init__(self, directory: Path = TEMPLATE_CACHE, write: bool | None = None):
        super().__init__(str(directory), "%s.jinja")
        self.write = write

    def get_bucket(self, environment: Environment, name: str, filename: str | None, source: str) -> Bucket:
        """The bucket of a template, keyed by its name, its file and the environment's compile settings."""
        key = hashlib.sha1(f"{name}|{filename}|{_compile_signature(environment, name)}".encode()).hexdigest()
        bucket = Bucket(environment, key, self.get_source_checksum(source))
        self.load_bytecode(bucket)
        return bucket

    def load_bytecode(self, bucket: Bucket) -> None:
        """Read a template's compiled code when a readable file holds it; anything else (no file,
        the cache's folder replaced by a file, no permission, a truncated or damaged file) leaves
        the template to be compiled."""
        try:
            super().load_bytecode(bucket)
        except Exception:  # noqa: BLE001 - unreadable, truncated or foreign: compiling costs only time
            bucket.reset()

    def dump_bytecode(self, bucket: Bucket) -> None:
        """Write a template's compiled code (atomically, as jinja does), when writing is on."""
        if not (not sys.dont_write_bytecode if self.write is None else self.write):
            return
        try:
            os.makedirs(self.directory, exist_ok=True)
            super().dump_bytecode(bucket)
        except OSError:  # a read-only checkout: the next build compiles the template again
            return


def _compile_signature(environment: Environment, name: str) -> str:
    """Everything in ``environment`` that shapes the code jinja compiles template ``name`` into: the
    jinja version, the lexer's settings (the key of ``jinja2.lexer.get_lexer``), the extensions, the
    optimizer, async mode, autoescaping as decided for this template, finalize, the code generator."""
    env = environment
    autoescape = env.autoescape(name) if callable(env.autoescape) else env.autoescape
    parts = (jinja2.__version__, env.block_start_string, env.block_end_string, env.variable_start_string,
             env.variable_end_string, env.comment_start_string, env.comment_end_string, env.line_statement_prefix,
             env.line_comment_prefix, env.trim_blocks, env.lstrip_blocks, env.newline_sequence,
             env.keep_trailing_newline, sorted(env.extensions), env.optimized, env.is_async, autoescape,
             None if env.finalize is None else getattr(env.finalize, "__qualname__", repr(env.finalize)),
             env.code_generator_class.__qualname__)
    return repr(parts)


def _template_cache(templates: Path) -> TemplateCache | None:
    """The cache of the package's own templates; none for another folder's (a test's own templates)."""
    return TemplateCache() if Path(templates).resolve() == TEMPLATES else None


def write_template_cache() -> list[str]:
    """Compile every template of :data:`TEMPLATES` in its environment and write the compiled code
    (:class:`TemplateCache`), whatever ``sys.dont_write_bytecode`` says, as ``compileall`` writes
    Python's bytecode. Returns the templates' names."""
    html, latex = html_environment(), latex_environment()
    html.bytecode_cache = latex.bytecode_cache = TemplateCache(write=True)
    names = sorted(path.name for path in TEMPLATES.glob("*.j2"))
    for name in names:
        (latex if name.endswith(".tex.j2") else html).get_template(name)
    return names


def html_environment(templates: Path = TEMPLATES) -> Environment:
    """Jinja2 environment for ``*.html.j2``: autoescaped, StrictUndefined; the package's own templates
    are compiled once and kept (:class:`TemplateCache`)."""
    env = Environment(
        loader=FileSystemLoader(str(templates)),
        bytecode_cache=_template_cache(templates),
        undefined=StrictUndefined,
        autoescape=select_autoescape(["html", "html.j2"]),
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        optimized=_JINJA_OPTIMIZER,
    )
    env.filters["num"] = format_number
    env.filters["percent"] = _share_percent  # a share 0..1 in percent by the one rounding rule
    env.filters["unit"] = _unit_shown
    env.filters["same_decimals"] = same_decimals
    env.filters["detail_prose"] = detail_prose
    env.filters["verdict_class"] = lambda v: {"agrees": "ok", "disagrees": "bad"}.get(v, "na")
    env.filters["inline_svg"] = lambda fig: Markup(inline_svg(fig.svg, fig.name))  # ids unique in the page
    env.globals["math_font_css"] = mathfont.font_face_css()  # the embedded maths font (_style.html.j2)
    return env


def latex_environment(templates: Path = TEMPLATES) -> Environment:
    r"""Jinja2 environment for ``*.tex.j2`` with LaTeX-safe delimiters.

    ``\VAR{...}`` for values, ``\BLOCK{...}`` for statements, ``\#{...}`` for
    comments; values pass through the ``latex`` escape filter explicitly, and
    math produced by sympy's LaTeX printer is inserted as is. The package's own templates are
    compiled once and kept (:class:`TemplateCache`).
    """
    env = Environment(
        loader=FileSystemLoader(str(templates)),
        bytecode_cache=_template_cache(templates),
        undefined=StrictUndefined,
        autoescape=False,
        block_start_string=r"\BLOCK{",
        block_end_string="}",
        variable_start_string=r"\VAR{",
        variable_end_string="}",
        comment_start_string=r"\#{",
        comment_end_string="}",
        line_statement_prefix="%%",
        line_comment_prefix="%#",
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        optimized=_JINJA_OPTIMIZER,
    )
    env.filters["latex"] = latex_escape
    env.filters["display"] = latex_display  # an unnumbered display, broken into lines when too wide
    env.filters["num"] = format_number
    env.filters["percent"] = _share_percent
    return env


_SUPERSCRIPT = str.maketrans("0123456789-", "\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079\u207b")


def _dimension_dict(m: re.Match) -> str:
    """``{'[mass]': 1, '[time]': -2}`` (a dimension as a Python dict) as ``[mass]·[time]⁻²``."""
    parts = re.findall(r"'(\[\w+\])': (-?\d+)", m.group(1))
    return "\u00b7".join(name + ("" if power == "1" else power.translate(_SUPERSCRIPT)) for name, power in parts)


def detail_prose(text) -> str:
    """A check's detail with pint's dimension text and sympy's products and powers written as
    formulas, not code: ``[length] * [mass] / [time] ** 2`` -> ``[length]·[mass]/[time]²``,
    ``2*F_a*r_d`` -> ``2·F_a·r_d``. Only the text shown in report.html; verification.json keeps the
    detail as it is."""
    text = re.sub(r"\{('\[\w+\]': -?\d+(?:, '\[\w+\]': -?\d+)*)\}", _dimension_dict, str(text))
    text = re.sub(r"(\]) \*\* (-?\d+)", lambda m: m.group(1) + m.group(2).translate(_SUPERSCRIPT), text)
    text = re.sub(r"(?<=[A-Za-z)])\^(-?\d+)", lambda m: m.group(1).translate(_SUPERSCRIPT), text)  # s^2 -> s²
    text = re.sub(r"(?<=[\]\u00b9\u00b2\u00b3\u2070-\u2079]) \* (?=\[)", "\u00b7", text)
    text = re.sub(r"(?:(?<=[\]\u00b9\u00b2\u00b3\u2070-\u2079])|(?<=\b1)) / (?=\[)", "/", text)
    # sympy's text of a term: F_a*r_d -> F_a·r_d, theta_dot**2 -> theta_dot²
    text = re.sub(r"(?<=[\w)])\*\*(\d+)\b", lambda m: m.group(1).translate(_SUPERSCRIPT), text)
    return name_text(re.sub(r"(?<=[\w)])\*(?=[\w(])", "\u00b7", text))  # theta_ddot -> θ̈


def same_decimals(value, printed: str) -> str:
    """A computed table percentage with as many decimals as the printed one beside it ("50.0" next to
    a printed "50.0", not "50"); without a printed decimal text, :func:`format_number`'s 8 digits."""
    if not isinstance(value, (int, float)) or isinstance(value, bool) or not printed:
        return format_number(value, 8)
    decimals = len(printed.partition(".")[2]) if "." in printed else 0
    return f"{value:.{decimals}f}"


def _unit_shown(unit) -> str:
    """A unit as a table shows it after a number: none for a dimensionless quantity (pint's "1"), a
    power as a superscript (a printed "(lbf·s^2)/ft" as "(lbf·s²)/ft", like pint's "ft/s²" beside it)."""
    if unit in (None, "1", "dimensionless"):
        return ""
    return re.sub(r"\^(-?\d+)", lambda m: m.group(1).translate(_SUPERSCRIPT), str(unit))


def _share_percent(share: float, decimals: int = 1) -> str:
    """A share 0..1 in percent as every output prints it (:func:`analysis.rounding.share_percent_text`)."""
    from analysis.rounding import share_percent_text

    return share_percent_text(share, decimals)


def format_number(value, digits: int = 4) -> str:
    """Significant-figure text of a number ("-" for None, integers as integers)."""
    if value is None:
        return "–"
    if isinstance(value, bool):
        return str(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            return str(value)
        return f"{value:.{digits}g}"
    return str(value)


# --------------------------------------------------------------------------- helpers
def _eval_text(text: str, where: str) -> float:
    """A numeric expression from a data file (e.g. "pi/6"), through the whitelist parser."""
    return float(parse_expression(text, {}, where=where))


def _engine() -> str | None:
    for name in LATEX_ENGINES:
        path = shutil.which(name)
        if path:
            return path
    return None


def _benchmarks(bench_dir: Path) -> list[dict]:
    """Summaries of the benchmark JSON files that exist (other helpers' `make bench`)."""
    found = []
    if not bench_dir.is_dir():
        return found
    for path in sorted(bench_dir.glob("*.json")):
        if path.name == "report.json":
            continue
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError) as err:
            found.append({"name": path.stem, "error": f"unreadable: {err}", "scalars": []})
            continue
        scalars = []

        def walk(prefix, obj, depth=0):
            if len(scalars) >= 40 or depth > 3:
                return
            if isinstance(obj, dict):
                for k, v in obj.items():
                    walk(f"{prefix}.{k}" if prefix else str(k), v, depth + 1)
            elif isinstance(obj, (int, float, str, bool)) and not isinstance(obj, str) or (
                isinstance(obj, str) and len(obj) < 80
            ):
                scalars.append({"key": prefix, "value": ("yes" if obj else "no") if isinstance(obj, bool) else obj})

        walk("", data)
        found.append({"name": path.stem, "error": "", "scalars": scalars, "data": data})
    return found


def _work_precision_series(bench: list[dict]) -> dict:
    """(time, error) series per method from a dynamics benchmark, when one has them."""
    series: dict[str, list[tuple[float, float]]] = {}
    for entry in bench:
        data = entry.get("data")
        rows = None
        if isinstance(data, dict):
            for key in ("work_precision", "work-precision", "workprecision"):
                if isinstance(data.get(key), list):
                    rows = data[key]
                    break
                if isinstance(data.get(key), dict) and isinstance(data[key].get("rows"), list):
                    rows = data[key]["rows"]
                    break
        if not rows:
            continue
        # One point per (method, tolerance setting): the median time and the worst error over the
        # amplitudes run, so each method traces one line from loose to tight tolerance.
        groups: dict[tuple[str, object], list[tuple[float, float]]] = {}
        for row in rows:
            if not isinstance(row, dict):
                continue
            name = row.get("method") or row.get("model") or row.get("name")
            t = row.get("time_s", row.get("seconds", row.get("time")))
            err = row.get("error", row.get("rel_error", row.get("relative_error")))
            if name is None or not isinstance(t, (int, float)) or not isinstance(err, (int, float)):
                continue
            groups.setdefault((str(name), row.get("tol")), []).append((float(t), float(err)))
        for (name, _tol), points in groups.items():
            times = sorted(p[0] for p in points)
            series.setdefault(name, []).append((times[len(times) // 2], max(p[1] for p in points)))
    return series


# --------------------------------------------------------------------------- build
def build(root: Path = ROOT, out: Path | None = None, pdf: str = "auto", log=print) -> dict:
    """Build every output into ``out``.

    Parameters
    ----------
    root : pathlib.Path
        Project root (inputs are read from its ``data/``).
    out : pathlib.Path, optional
        Output folder (default ``root / "reports/build"``).
    pdf : {"auto", "never"}
        Build paper.pdf when a LaTeX engine exists ("auto"), or not at all.
    log : callable
        Progress messages.

    Returns
    -------
    dict
        Paths written, verdict counts and timings.

    Raises
    ------
    InputError
        Bad input files (one line).

    Notes
    -----
    Python's cyclic garbage collector is paused during the build (:func:`reports.cli.cyclic_gc_paused`).
    """
    validate_build(root, pdf)
    with cyclic_gc_paused():
        return _build(Path(root), out, pdf, log)


def _build(root: Path, out: Path | None, pdf: str, log) -> dict:
    """:func:`build`, with the collector paused by the caller."""
    out = Path(out) if out is not None else root / "reports" / "build"
    out.parent.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    timings = {}

    from solver.derivation import as_system, derive, natural_frequency, solve_instant
    from solver.io.scenes import load_system
    from solver.scenefile import load_scene

    staging = Path(tempfile.mkdtemp(prefix=".report-", dir=str(out.parent)))
    try:
        prov = provenance.collect(root)
        eqset = load_equations(root / "data" / "published" / "equations.toml")
        scenes = {key: load_scene(path) for key, path in eqset.scenes.items()}
        derivations = {key: derive(scene) for key, scene in scenes.items()}
        # One System per scene file for the whole build: the checks, the worked steps and the drawings
        # share its cached derivations and numeric models instead of deriving them again.
        systems = {Path(path).resolve(): as_system(scenes[key]) for key, path in eqset.scenes.items()}

        def system_of(path):
            path = Path(path).resolve()
            if path not in systems:
                systems[path] = load_system(path)
            return systems[path]

        timings["load"] = time.perf_counter() - started

        # ---------------- checks
        t0 = time.perf_counter()
        rows = checks_mod.equation_checks(eqset, scenes, derivations)
        timings["equations"] = time.perf_counter() - t0
        system = next(iter(eqset.systems.values()), None)
        ex1_key = system["scene"] if system else None
        values_path = root / "data" / "published" / "example1.toml"
        # Example 1's solution at its state: one for the value checks, the paper's results and Figure 2
        ex1_solution = solve_instant(scenes[ex1_key]) if ex1_key else None
        if ex1_key and values_path.exists():
            rows += checks_mod.example1_value_checks(values_path, eqset, scenes[ex1_key],
                                                     derivations[ex1_key], ex1_solution)
        else:
            rows.append(checks_mod.not_checkable("eq30-alpha", "value", None,
                                                 "data/published/example1.toml or [systems] missing"))
        t0 = time.perf_counter()
        (staging / "data").mkdir()
        try:
            survey_rows, survey = checks_mod.survey_checks(staging / "data" / "table1_respondents.csv")
        except ImportError as err:  # the analysis package has not landed
            survey_rows, survey = [checks_mod.not_checkable(
                "table1", "table-cell", None, f"survey analytics unavailable ({err})")], None
        rows += survey_rows
        timings["survey"] = time.perf_counter() - t0

        # ---------------- figures
        t0 = time.perf_counter()
        figs = {}
        ex2_key = next((k for k in eqset.scenes if k != ex1_key), None)
        figs["example1"] = figures.example1_release_sweep(scenes[ex1_key], derivations[ex1_key])
        eq45 = eqset.ranges.get("eq45", {})
        amplitude = _eval_text(eq45.get("amplitude_max", "0"), f"{eqset.path}: ranges.eq45.amplitude_max")
        from solver.period import OneDofSystem

        # one one-degree-of-freedom model of Example 2 for its frequency, figure, period and friction
        ex2_one_dof = OneDofSystem.from_derivation(derivations[ex2_key])
        freq = natural_frequency(scenes[ex2_key], one_dof=ex2_one_dof)
        omega_n = float(freq.omega_n.to("rad/s").magnitude)
        figs["example2"] = figures.example2_free_motion(scenes[ex2_key], derivations[ex2_key], amplitude, omega_n,
                                                        one_dof=ex2_one_dof)
        ex2_solution = solve_instant(scenes[ex2_key])  # at the scene's state: the paper's results and Figure 3
        solved = {as_system(scenes[ex1_key]): ex1_solution, as_system(scenes[ex2_key]): ex2_solution}
        for name, scene_file, body, number in figures.PAPER_SCENE_FIGURES:  # the paper's Figures 1-3
            path = root / "data" / "scenes" / scene_file
            drawn = system_of(path)
            figs[name] = figures.scene_figure(path, name, number, body, system=drawn, solution=solved.get(drawn))
        if survey is not None:
            figs["likert"] = figures.likert_chart(survey.summary)
        bench = _benchmarks(root / "reports" / "build" / "bench")
        series = _work_precision_series(bench)
        if series:
            figs["benchmark"] = figures.benchmark_figure(
                series, "Example 2 period: worst error over the amplitudes against run time (make bench)",
                "median wall time per period [s]", "largest relative error of the period")
        timings["figures"] = time.perf_counter() - t0

        # ---------------- paper content
        t0 = time.perf_counter()
        from solver.friction import least_friction
        from solver.period import exact_period

        result = exact_period(ex2_one_dof, amplitude)
        period_cross = {"period": result.period, "linear": result.period_linear, "ratio": result.ratio,
                        "model": result.model}
        least = least_friction(ex2_one_dof, amplitude)
        friction = paper.friction_peak(ex2_one_dof, least)
        lin_mass, lin_stiff, lin_w2 = paper.linearisation(
            derivations[ex2_key],
            about={},
            assume={sp.Symbol("F_a", real=True): 0} if "F_a" in scenes[ex2_key].parameters else {},
        )
        examples = {
            "ex1": {
                "scene": scenes[ex1_key],
                "point": derivations[ex1_key].point,
                "parameters": paper.parameter_rows(scenes[ex1_key]),
                "steps": paper.example_steps(scenes[ex1_key], derivations[ex1_key], at_rest=True, parts=EX1_STEPS),
                "solution": ex1_solution,
            },
            "ex2": {
                "scene": scenes[ex2_key],
                "point": derivations[ex2_key].point,
                "parameters": paper.parameter_rows(scenes[ex2_key]),
                "steps": paper.example_steps(scenes[ex2_key], derivations[ex2_key], at_rest=False, parts=EX2_STEPS),
                "frequency": freq,
                "omega_n_formula": paper.shown(sp.Symbol("omega_n") ** 2, lin_w2, "Linearised", ""),
                "amplitude_deg": math.degrees(amplitude),
                "period_cross": period_cross,
                "friction": friction,
            },
        }
        ex1_system, ex2_system = system_of(eqset.scenes[ex1_key]), system_of(eqset.scenes[ex2_key])
        examples["ex1"]["explained"] = paper.explained(
            ex1_system, derivations[ex1_key].point, at_rest=True,
            inertia_number=paper.printed_number(eqset, ex1_key, "inertia_about", derivations[ex1_key].point))
        ex2_ranked = paper.ranked_points(ex2_system)  # one ranking for both workings of Example 2
        examples["ex2"]["explained"] = paper.explained(ex2_system, derivations[ex2_key].point, at_rest=False,
                                                     shows_alternative=True,  # shown below, when it differs
                                                     ranked=ex2_ranked, inertia_number=paper.printed_number(
                                                         eqset, ex2_key, "inertia_about", derivations[ex2_key].point))
        examples["ex2"]["alpha_number"] = paper.printed_number(eqset, ex2_key, "alpha")  # alpha = -theta_ddot
        best = examples["ex2"]["explained"]["advisor_best"]
        if best != derivations[ex2_key].point:  # the one-step alternative the advisor finds (about C)
            examples["ex2"]["alternative"] = paper.explained(ex2_system, best, at_rest=False, ranked=ex2_ranked)
        conversion = paper.unit_conversion(scenes[ex1_key])  # lbm*ft/s^2 to lbf (g_c), from pint
        examples["ex1"]["conversion"] = conversion
        examples["ex1"]["results"] = paper.result_rows(examples["ex1"]["solution"], scenes[ex1_key], conversion)
        examples["ex2"]["solution"] = ex2_solution
        examples["ex2"]["results"] = paper.result_rows(examples["ex2"]["solution"], scenes[ex2_key])
        timings["paper"] = time.perf_counter() - t0

        # ---------------- verdicts and findings
        counts = {v: sum(1 for r in rows if r.verdict == v) for v in checks_mod.VERDICTS}
        findings = [r for r in rows if r.verdict == "disagrees"]
        caveats = [r for r in rows if r.verdict != "disagrees" and r.caveat]
        missing = [r for r in rows if r.verdict == "not-checkable"]
        sections = [
            ("example1-equations", "Example 1: printed equations",
             [r for r in rows if r.section == "example1" and r.kind == "equation"]),
            ("example1-values", "Example 1: printed numbers and units",
             [r for r in rows if r.section == "example1" and r.kind != "equation"]),
            ("example2-equations", "Example 2: printed equations",
             [r for r in rows if r.section == "example2"]),
            ("survey", "Survey: Table 1, response facts and claims",
             [r for r in rows if r.section == "survey"]),
            ("other", "Other", [r for r in rows if r.section not in ("example1", "example2", "survey")]),
        ]
        equation_views = {}
        for r in rows:
            if r.outcome is not None:
                o = r.outcome
                sign = checks_mod.RELATION.get(o.transcription.kind, "=")  # Eq. 45 is printed with ≈
                equation_views[r.id] = {
                    # as transcribed: drawn from the text, not from sympy's evaluated form
                    "printed": transcription_mathml(o.transcription.lhs, o.transcription.rhs, relation=sign),
                    "printed_inline": transcription_mathml(o.transcription.lhs, o.transcription.rhs, "inline", sign),
                    "residual": to_mathml(o.residual) if o.residual is not None else Markup(""),
                    "derived": (equation_mathml(o.derived_lhs, o.derived_rhs)
                                if o.derived_lhs is not None and r.kind == "equation" and
                                o.transcription.kind in ("eom", "frequency") else None),
                }
        context = {
            "title": "Alternative form of Euler's equation: verification report",
            "rows": rows,
            "counts": counts,
            "findings": findings,
            "caveats": caveats,
            "missing": missing,
            "sections": [s for s in sections if s[2]],
            "equation_views": equation_views,
            "figures": figs,
            "provenance": prov,
            "method": paper.method_equations(),
            "method_prose": paper.method_prose(),  # the words around Eqs. 10, 11, 14, shared by both renderings
            "examples": examples,
            "prose": paper.PROSE,
            "survey": survey,
            "unreachable_cells": paper.unreachable_cells(findings, survey.facts.respondents) if survey else "",
            "rounding_ties": paper.rounding_ties(survey) if survey else "",
            "survey_table": paper.survey_table(survey) if survey else None,
            "claim_texts": paper.claim_texts(rows, survey),
            "benchmarks": bench,
            "tolerance_notes": _doc_bullets(checks_mod.__doc__.split("Tolerances (documented once, applied "
                                                                     "everywhere)")[1].split("\n", 2)[2]),
            "engine": None,
        }

        # ---------------- render
        t0 = time.perf_counter()
        html = html_environment()
        for page in ("report.html", "paper.html"):  # every minus shown as U+2212, as the worked solution's
            (staging / page).write_text(minus_signs(html.get_template(f"{page}.j2").render(**context)), encoding="utf-8")
        fig_dir = staging / "figures"
        fig_dir.mkdir()
        for fig in figs.values():
            (fig_dir / f"{fig.name}.svg").write_text(fig.svg, encoding="utf-8")
            (fig_dir / f"{fig.name}.pdf").write_bytes(fig.pdf)
        latex = latex_environment()
        (staging / "paper.tex").write_text(latex.get_template("paper.tex.j2").render(**context), encoding="utf-8")
        payload = {"checks": [r.to_json() for r in rows]}
        (staging / "verification.json").write_text(json.dumps(payload, indent=2, ensure_ascii=False) + "\n",
                                                   encoding="utf-8")
        timings["render"] = time.perf_counter() - t0

        engine = _engine() if pdf == "auto" else None
        if engine:
            t0 = time.perf_counter()
            _run_latex(engine, staging)
            timings["pdf"] = time.perf_counter() - t0
        elif pdf == "auto":
            log("paper.pdf: skipped, no LaTeX engine found (tried " + ", ".join(LATEX_ENGINES) + ")")

        # ---------------- move into place
        out.mkdir(parents=True, exist_ok=True)
        written = []
        for path in sorted(staging.rglob("*")):
            if path.is_dir():
                continue
            rel = path.relative_to(staging)
            target = out / rel
            target.parent.mkdir(parents=True, exist_ok=True)
            os.replace(path, target)
            written.append(str(rel))
        if not engine and (out / "paper.pdf").exists():
            (out / "paper.pdf").unlink()  # a stale PDF would no longer match paper.tex
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    timings["total"] = time.perf_counter() - started
    return {"out": str(out), "written": written, "counts": counts, "timings": timings, "context": context}


_SESSION_CACHE: dict[tuple[str, str], dict] = {}


def _doc_bullets(text: str) -> list[list[tuple[str, bool]]]:
    """A docstring's ``* `` bullet list as items of (text, is code) parts for the HTML: the lines
    of each item joined, and reST's inline literals and roles (````x````, ``:func:`x```) marked as
    code instead of shown raw (the template escapes every part)."""
    items: list[str] = []
    for line in text.strip().splitlines():
        if line.startswith("* "):
            items.append(line[2:].strip())
        elif items and line.strip():
            items[-1] += " " + line.strip()
    pattern = re.compile(r"``(.+?)``|:\w+:`(.+?)`")
    out = []
    for item in items:
        parts, at = [], 0
        for m in pattern.finditer(item):
            parts += [(item[at:m.start()], False), (m.group(1) or m.group(2), True)]
            at = m.end()
        out.append(parts + [(item[at:], False)])
    return out


def build_cached(out: Path, root: Path = ROOT) -> dict:
    """:func:`build` once per process and output folder (the test suite shares one build)."""
    key = (str(Path(root).resolve()), str(Path(out).resolve()))
    if key not in _SESSION_CACHE:
        _SESSION_CACHE[key] = build(root, out, pdf="never", log=lambda *_: None)
    return _SESSION_CACHE[key]


def _run_latex(engine: str, folder: Path) -> None:
    name = Path(engine).name
    cmd = [engine, "paper.tex"] if name == "tectonic" else [engine, "-interaction=nonstopmode", "-halt-on-error",
                                                            "paper.tex"]
    for _ in range(1 if name == "tectonic" else 2):
        done = subprocess.run(cmd, cwd=folder, capture_output=True, text=True, timeout=300, check=False)
        if done.returncode != 0:
            tail = (done.stdout + done.stderr).strip().splitlines()[-5:]
            raise ReportInputError(f"paper.tex: {name} failed: " + " | ".join(tail))
    for junk in ("paper.aux", "paper.log", "paper.out"):
        (folder / junk).unlink(missing_ok=True)
