"""Figures of the report and the paper: matplotlib (Agg), vector SVG, deterministic.

Every figure is computed here from the solver or the survey analytics; the SVG
text is embedded inline in the HTML (no files fetched) and also written next to
the LaTeX source (``figures/*.svg``), with its PDF twin (``figures/*.pdf``, for
LaTeX, written whether or not a LaTeX engine exists). Matplotlib draws each
figure once for both files (:func:`reports.vector_pair.svg_and_pdf`).

Determinism: ``svg.hashsalt`` is fixed, no date or creator is written, text is
kept as text (``svg.fonttype = "none"``), and element ids are stable.
"""
from __future__ import annotations

import io
import math
from dataclasses import dataclass

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
from matplotlib import rc_context  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

from reports.vector_pair import svg_and_pdf  # noqa: E402
from solver.drawing.layout import MeasuredLayout, measure_as_vector  # noqa: E402
from solver.notation import typeset_text  # noqa: E402
from solver.units import Q_  # noqa: E402

__all__ = ["FigureResult", "svg_text", "example1_release_sweep", "example2_free_motion", "likert_chart",
           "benchmark_figure", "scene_figure", "PAPER_SCENE_FIGURES", "RC"]

RC = {
    "svg.hashsalt": "alt-euler-report",
    "svg.fonttype": "none",
    "font.size": 9,
    "axes.grid": True,
    "grid.alpha": 0.3,
}
"""matplotlib settings shared by every figure (fixed hash salt: reproducible SVG ids)."""


@dataclass
class FigureResult:
    """A figure as SVG text plus the numbers the text around it quotes.

    Attributes
    ----------
    name : str
        File stem (``example1_sweep``).
    caption : str
        Caption written from computed values.
    svg : str
        ``<svg ...>...</svg>`` (no XML prolog), safe to inline.
    pdf : bytes
        The same figure as PDF (for the LaTeX build).
    facts : dict
        Computed numbers quoted in the caption and the paper.
    """

    name: str
    caption: str
    svg: str
    pdf: bytes
    facts: dict


_SVG_METADATA = {"Date": None, "Creator": None}
_PDF_METADATA = {"CreationDate": None, "Creator": None, "Producer": None}
"""No dates and no producer in the files: the same inputs give the same bytes."""


def _without_prolog(svg: str) -> str:
    return svg[svg.find("<svg"):]


def svg_text(fig: Figure) -> str:
    """SVG of a figure, without prolog, reproducible."""
    buf = io.StringIO()
    with rc_context(RC):
        fig.savefig(buf, format="svg", metadata=_SVG_METADATA)
    return _without_prolog(buf.getvalue())


def _result(name: str, fig: Figure, caption: str, facts: dict) -> FigureResult:
    """Both renderings of ``fig``, in one layout and one drawing: the layout engine
    (:class:`solver.drawing.layout.MeasuredLayout`, every axes placed from its texts' sizes) runs
    once, and matplotlib draws the figure once for both files (:func:`reports.vector_pair.svg_and_pdf`)."""
    with rc_context(RC):  # (Figures 1-3: the layout already fixed when their labels were placed)
        svg, pdf = svg_and_pdf(fig, _SVG_METADATA, _PDF_METADATA)
    return FigureResult(name=name, caption=caption, svg=_without_prolog(svg), pdf=pdf, facts=facts)


# --------------------------------------------------------------------------- Example 1
def example1_release_sweep(scene, deriv, n: int = 400) -> FigureResult:
    """R_A, R_B and alpha at release from rest against the release angle (Example 1).

    Parameters
    ----------
    scene : solver.scene.Scene
        Example 1 (sliding bar).
    deriv : solver.derivation.Derivation
        Its derivation about A.
    n : int
        Number of release angles between 0.5 deg and 89.5 deg.
    """
    _validate_n(n)
    with rc_context(RC):
        model = deriv.numeric()
        theta = np.radians(np.linspace(0.5, 89.5, n))
        force_unit = scene.output_units.get("force", "N")
        result = model.solve(theta, np.zeros_like(theta))
        reactions = [r for r in scene.reaction_names()]
        released = math.degrees(scene.state_si()[0])
        at = model.solve(np.array([scene.state_si()[0]]), np.array([0.0]))
        fig = Figure(figsize=(7.0, 4.6), layout=MeasuredLayout())
        measure_as_vector(fig)  # saved as SVG and PDF only: laid out in their text sizes
        ax_r, ax_a = fig.subplots(2, 1, sharex=True)
        deg = np.degrees(theta)
        facts = {"released_deg": released, "force_unit": force_unit}
        for name in reactions:
            values = Q_(result[name], "N").to(force_unit).magnitude
            ax_r.plot(deg, values, label=name)
            negative = deg[values < 0]
            facts[f"{name}_negative_from_deg"] = float(negative.min()) if negative.size else None
            facts[f"{name}_at_release"] = float(Q_(at[name][0], "N").to(force_unit).magnitude)
        ax_r.axhline(0, color="black", linewidth=0.6)
        ax_r.axvline(released, color="grey", linestyle="--", linewidth=0.8)
        ax_r.set_ylabel(f"reaction [{force_unit}]")
        ax_r.legend(loc="best", fontsize=8)
        alpha = result["alpha"]
        ax_a.plot(deg, alpha, color="tab:red", label="α")
        ax_a.axvline(released, color="grey", linestyle="--", linewidth=0.8)
        ax_a.set_ylabel("α [rad/s²]")
        ax_a.set_xlabel("release angle θ [deg] (from rest)")
        facts["alpha_at_release"] = float(at["alpha"][0])
        fig.suptitle("Example 1: reactions and angular acceleration at release", fontsize=10)
    caption = (
        f"Example 1, released from rest: reactions (in {force_unit}) and the angular acceleration α "
        f"against the release angle, computed by the solver about A. The dashed line marks the paper's "
        f"release angle, {released:.0f} deg."
    )
    for name in reactions:
        start = facts[f"{name}_negative_from_deg"]
        if start is not None:
            caption += f" {name} would have to pull (it is negative) for release angles from about {start:.0f} deg."
    return _result("example1_sweep", fig, caption, facts)


def _validate_n(n: int) -> None:
    if not isinstance(n, int) or n < 10:
        raise ValueError(f"`n` must be an integer >= 10, got {n!r}")


# --------------------------------------------------------------------------- Example 2
def example2_free_motion(scene, deriv, amplitude: float, omega_n: float, periods: float = 3.0,
                         one_dof=None) -> FigureResult:
    """Free oscillation from rest at ``amplitude``: the nonlinear equation of motion vs Eq. 46.

    Parameters
    ----------
    scene : solver.scene.Scene
        Example 2 with F_a = 0.
    deriv : solver.derivation.Derivation
    amplitude : float
        Release angle [rad] (the paper's largest small amplitude, Eq. 45).
    omega_n : float
        Linear natural frequency [rad/s] (solver.natural_frequency, Eq. 46).
    periods : float
        Length of the run in linear periods.
    one_dof : solver.period.OneDofSystem, optional
        The derivation's one-degree-of-freedom model when the caller has it (default: built here).
        Its compiled theta_ddot(theta, theta_dot, t) is the right-hand side (as ``simulate`` uses).
    """
    if not (amplitude > 0 and omega_n > 0):
        raise ValueError(f"`amplitude` and `omega_n` must be positive, got {amplitude!r}, {omega_n!r}")
    from solver.period import OneDofSystem

    qdd = (one_dof or OneDofSystem.from_derivation(deriv, reactions=False)).qdd_scalar_fn()
    t_end = periods * 2 * math.pi / omega_n

    def rhs(t, y):
        return [y[1], qdd(y[0], y[1], t)]

    def back_at_start(t, y):  # theta_dot falls through zero: the turning point at +amplitude again
        return y[1]

    back_at_start.direction = -1

    # rtol 1e-10: the exact curve must be accurate far below the plot's resolution and far below the
    # exact-vs-linear difference it is compared with.
    sol = solve_ivp(rhs, (0.0, t_end), [amplitude, 0.0], method="DOP853", rtol=1e-10, atol=1e-12,
                    dense_output=True, events=back_at_start)
    t = np.linspace(0.0, t_end, 1500)
    exact = sol.sol(t)[0]
    linear = amplitude * np.cos(omega_n * t)
    # Period of the exact motion: the first return to rest at theta = +amplitude.
    # (theta_dot also leaves zero downwards at t = 0; skip events in the first half period.)
    linear_period = 2 * math.pi / omega_n
    stops = [ts for ts in sol.t_events[0] if ts > 0.5 * linear_period]
    exact_period = float(stops[0]) if stops else float("nan")
    linear_period = 2 * math.pi / omega_n
    with rc_context(RC):
        fig = Figure(figsize=(7.0, 4.4), layout=MeasuredLayout())
        measure_as_vector(fig)  # saved as SVG and PDF only: laid out in their text sizes
        ax, ax_d = fig.subplots(2, 1, sharex=True, height_ratios=[2, 1])
        ax.plot(t, np.degrees(exact), label="nonlinear equation of motion (solve_ivp)")
        ax.plot(t, np.degrees(linear), linestyle="--", label="linear model (Eq. 46)")
        ax.set_ylabel("θ [deg]")
        # above the axes, not over them: the curves reach their maxima at every period, so no corner is free
        ax.legend(loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=2, fontsize=8, frameon=False)
        ax_d.plot(t, np.degrees(exact - linear), color="tab:purple")
        ax_d.set_ylabel("difference [deg]")
        ax_d.set_xlabel("time t [s]")
        fig.suptitle(
            f"Example 2: free motion from rest at θ₀ = {math.degrees(amplitude):.0f} deg", fontsize=10
        )
    facts = {
        "amplitude_deg": math.degrees(amplitude),
        "linear_period_s": linear_period,
        "exact_period_s": exact_period,
        "period_ratio": exact_period / linear_period,
        "max_difference_deg": float(np.max(np.abs(np.degrees(exact - linear)))),
        "t_end_s": t_end,
    }
    caption = (
        f"Example 2 with F_a = 0, released from rest at {facts['amplitude_deg']:.0f} deg, the largest amplitude "
        f"the paper treats as small (Eq. 45): the full equation of motion integrated numerically against the "
        f"linear model of Eq. 46. The full motion's period is {exact_period:.4f} s, "
        f"{100 * (facts['period_ratio'] - 1):.2f}% longer than the linear {linear_period:.4f} s; after "
        f"{periods:.0f} linear periods the two curves differ by up to {facts['max_difference_deg']:.2f} deg."
    )
    return _result("example2_motion", fig, caption, facts)


# --------------------------------------------------------------------------- Figures 1-3 from the scenes
PAPER_SCENE_FIGURES = (
    # (result name, scene file, body whose free-body diagram is shown (None: the only one), paper's number)
    ("figure1_slider_crank", "slider_crank.toml", "rod", 1),
    ("figure2_sliding_bar", "sliding_bar.toml", None, 2),
    ("figure3_disk_bar", "disk_bar.toml", None, 3),
)
"""The paper's Figures 1-3, each redrawn from its scene with a free-body diagram."""

PAPER_SCENE_TITLES = {
    1: "Slider-crank: crank OA, connecting rod AB, piston B",
    2: "Example 1: bar AB sliding on two rails",
    3: "Example 2: rolling disk with a bar hung from its centre",
}
"""The configuration panel's title of each of the paper's Figures 1-3, by number (the scene's
description, long, is in the caption)."""


def scene_figure(path, name: str, number: int, body: str | None = None, point: str | None = None,
                 system=None, solution=None) -> FigureResult:
    """A paper figure drawn from a scene file: the configuration, and one body's free-body diagram.

    Parameters
    ----------
    path : path-like
        The scene file (data/scenes/...).
    name : str
        File stem of the figure.
    number : int
        The paper's figure number (for the caption).
    body : str, optional
        The body of the free-body diagram (default: the scene's first body).
    point : str, optional
        The point P of the inertial force -m a_P (default: the body's reference point).
    system : solver.model.system.System, optional
        The scene's System when the caller has it already (its cached derivation is reused);
        default: loaded from ``path``.
    solution : solver.analyses.instant.InstantSolution, optional
        The System's solution at the scene's state about ``point`` when the caller has it already
        (the report's examples); the figure is drawn at its state. Default: solved here.
    """
    from pathlib import Path

    from solver.analyses.instant import assemble
    from solver.cli_common import state_text
    from solver.drawing import draw_system
    from solver.drawing.render import place_labels
    from solver.io.scenes import load_system

    system = load_system(path) if system is None else system
    state = assemble(system) if solution is None else solution.state
    body = body or next(iter(system.bodies))
    with rc_context(RC):
        fig = Figure(figsize=(9.0, 3.8), layout=MeasuredLayout())
        measure_as_vector(fig)  # saved as SVG and PDF only: laid out in their text sizes
        ax_scene, ax_fbd = fig.subplots(1, 2)
        draw_system(system, state, ax=ax_scene, arrange_labels=False, title=PAPER_SCENE_TITLES.get(number))
        fbd = draw_system(system, state, ax=[ax_fbd], fbd=True, point=point, bodies=[body], arrange_labels=False,
                          solution=solution)
        place_labels(fig, [ax_scene, ax_fbd])  # once, in the layout of the whole figure
    items = fbd.on(body)
    P = fbd.point[body]
    real = [i.label for i in items if i.kind in ("force", "couple")]
    elements = [e.name for e in system.bodies[body].elements]
    composite = (f"a composite of {len(elements)} elements ({', '.join(elements)})" if len(elements) > 1
                 else f"its element {elements[0]}")
    caption = typeset_text(
        f"Figure {number}, redrawn from data/scenes/{Path(path).name}: {system.description}, at "
        f"{state_text(system, state)}. Left, the configuration with its named points, guides and coordinates. "
        f"Right, the free-body diagram of {'the body' if len(system.bodies) == 1 else body}, {composite}, with the forces at this state: {'; '.join(real)}. "
        f"Dashed: the inertial force -m a_{P} drawn at the mass centre G and the couple -I_{P} alpha; with them "
        f"the forces have no moment about {P} (Eq. 10). Each arrow (arc) points the way its force (couple) acts "
        f"at this state, and |X| is its size: a reaction solved negative points against its positive sense."
    )
    facts = {"scene": system.name, "body": body, "point": P, "labels": [i.label for i in items]}
    return _result(name, fig, caption, facts)


# --------------------------------------------------------------------------- survey
def likert_chart(summary, item_texts: dict[str, str] | None = None) -> FigureResult:
    """The diverging stacked bar chart of the survey (analysis.chart)."""
    from analysis.chart import diverging_bar

    with rc_context(RC):
        # titled by what it shows (diverging_bar's default title names the data file)
        fig = diverging_bar(summary, order="questionnaire", title="Survey answers per item (Table 1)")
        measure_as_vector(fig)
    caption = (
        f"Answers of the {summary.respondents} respondents to the five items, from the dataset rebuilt from "
        "Table 1: disagreement to the left, agreement to the right, neutral answers split across the centre."
    )
    return _result("likert", fig, caption, {"respondents": summary.respondents})


# --------------------------------------------------------------------------- benchmarks
_SUPERSCRIPT = str.maketrans("-0123456789", "\u207b\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079")


def _powers_of_ten(ax) -> None:
    """Log axes labelled 10 with a superscript exponent in plain text (10⁻³), at the powers of ten
    only, without minor ticks: matplotlib's default writes each label as mathtext, whose parser
    took 0.3 s of the report's build for this one figure."""
    from matplotlib.ticker import FuncFormatter, NullLocator

    def label(value, _position):
        exponent = round(math.log10(value)) if value > 0 else None
        if exponent is None or not math.isclose(value, 10.0 ** exponent, rel_tol=1e-9):
            return ""
        return "10" + str(exponent).translate(_SUPERSCRIPT)

    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_formatter(FuncFormatter(label))
        axis.set_minor_locator(NullLocator())  # (no minor ticks: over 14 decades they were 200 Tick objects)


def benchmark_figure(series: dict[str, list[tuple[float, float]]], title: str, xlabel: str,
                     ylabel: str) -> FigureResult:
    """A log-log work-precision style plot from benchmark JSON series (name -> [(x, y), ...])."""
    with rc_context(RC):
        fig = Figure(figsize=(7.0, 4.2), layout=MeasuredLayout())
        measure_as_vector(fig)  # saved as SVG and PDF only: laid out in their text sizes
        ax = fig.subplots()
        for name, points in sorted(series.items()):
            pts = [(x, y) for x, y in points if x and y and x > 0 and y > 0]
            if not pts:
                continue
            xs, ys = zip(*sorted(pts, key=lambda p: -p[1]))  # from loose to tight accuracy
            ax.loglog(xs, ys, marker="o", markersize=3, label=name)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        _powers_of_ten(ax)
        ax.legend(fontsize=7, loc="best")
        fig.suptitle(title, fontsize=10)
    caption = (
        f"{title}. Each point is one method at one tolerance setting: the median run time and the largest "
        "relative error over all amplitudes benchmarked (read from reports/build/bench/*.json)."
    )
    return _result("benchmark", fig, caption, {})
