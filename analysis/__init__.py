"""Likert survey analytics and verification of published percentage tables.

Python API (names are loaded on first use, so ``import analysis`` stays light)
-----------------------------------------------------------------------------
Published tables (:mod:`analysis.tables`)
    ``table1_check(rule="half_away") -> TableCheck``: the paper's Table 1 against its N,
    read from ``data/published/``. ``read_table_csv(path) -> PublishedTable``,
    ``verify_table(table, n=None, n_range=None, rule=..., decimals=None) -> TableCheck``.
    ``TableCheck.to_dict()`` is the ``verify-table --json`` shape; ``to_full_dict()`` adds
    nearest attainable values, reconstructed counts (``rows[i].reconstructed``) and reasons.
Surveys (:mod:`analysis.ingest`, :mod:`analysis.likert`)
    ``read_survey(path, scale=None, items=None, shape="auto", unknown="error", ...) -> SurveyData``,
    ``survey_from_frame(df, ...)``, ``summarize(data, confidence_level=0.95, method="wilson")
    -> SurveySummary`` (``.items``: ``ItemSummary`` with counts, percent, n, missing,
    excluded, agree/neutral/disagree ``Proportion``, median, q1, q3),
    ``summarize_dataframe(df, ...)``. ``SurveySummary.to_dict()`` is the ``summarize --json`` shape.
Claims (:mod:`analysis.claims`)
    ``load_claims(path)``, ``evaluate_claims(claims_or_path, summary) -> ClaimsReport``
    (``.results``: ``ClaimResult`` with k, n, share, ci, verdict, verdict_code, reason).
Rebuilt data (:mod:`analysis.respondents`, :mod:`analysis.paper`)
    ``rebuild_table1_dataset(out_path) -> RebuiltDataset``;
    ``table1_reproduction(out_dir) -> Table1Reproduction``: the whole chain for the paper
    (check, rebuilt CSV in ``out_dir``, summary, per-cell printed vs recomputed with reasons
    in ``.cells``, the two claims in ``.claims``).
Chart and report (:mod:`analysis.chart`, :mod:`analysis.report`)
    ``diverging_bar(summary) -> Figure``, ``figure_svg(fig) -> str``,
    ``render_report(data, claims=None, ...) -> str``, ``build_report(data, out_path, ...)``.
Statistics (:mod:`analysis.reliability`, :mod:`analysis.groups`)
    ``cronbach_alpha(scores)``, ``cronbach_alpha_for(data, items=None)``,
    ``compare_groups(data, column, min_size=5)``, ``cliffs_delta(x, y)``.
Scales (:mod:`analysis.scales`)
    ``get_scale(name_or_toml) -> Scale``, ``BUILTIN_SCALES``.

Bad input raises :class:`analysis.errors.SurveyInputError` (one line naming file,
row, column); bad option strings raise ``ValueError`` listing the valid options.
"""
from importlib import import_module

_EXPORTS = {
    "table1_check": "tables", "verify_table": "tables", "read_table_csv": "tables",
    "TableCheck": "tables", "PublishedTable": "tables", "load_table1": "tables",
    "load_survey_facts": "tables", "published_dir": "tables",
    "read_survey": "ingest", "survey_from_frame": "ingest", "SurveyData": "ingest",
    "summarize": "likert", "summarize_dataframe": "likert", "proportion": "likert",
    "SurveySummary": "likert", "ItemSummary": "likert", "Proportion": "likert",
    "load_claims": "claims", "evaluate_claims": "claims", "ClaimsReport": "claims",
    "rebuild_table1_dataset": "respondents", "table1_reproduction": "paper",
    "diverging_bar": "chart", "figure_svg": "chart",
    "render_report": "report", "build_report": "report",
    "cronbach_alpha": "reliability", "cronbach_alpha_for": "reliability",
    "compare_groups": "groups", "cliffs_delta": "groups",
    "summarize_by": "institution", "GroupedSummary": "institution",
    "summary_frame": "export", "write_table": "export", "load_codebook": "codebook",
    "faceted_bar": "chart", "figure_bytes": "chart", "summarize_tally": "likert",
    "get_scale": "scales", "Scale": "scales", "BUILTIN_SCALES": "scales",
    "SurveyInputError": "errors",
}
__all__ = sorted(_EXPORTS)


def __getattr__(name):
    if name in _EXPORTS:
        value = getattr(import_module(f"{__name__}.{_EXPORTS[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + __all__)
