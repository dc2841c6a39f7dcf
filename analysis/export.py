"""Summary tables an instructor can reuse: pandas DataFrames, CSV and XLSX files.

:func:`summary_frame` gives one row per item (whether it is reverse-keyed, counts and percent per label, n,
missing, excluded, agreement share and interval, median, IQR with Q1 and Q3, mean, SD) -- the
same numbers as ``summarize --json``, the quartiles to two places (:func:`~analysis.rounding.quartile_values`:
the IQR is Q3 - Q1 as written). :func:`write_table` writes a DataFrame as CSV or
XLSX by the file's suffix. Every text cell that a spreadsheet would read as a
formula (starting with ``=``, ``+``, ``-``, ``@``, a tab or a carriage return) is
written with a leading apostrophe, so it shows as the text it is; numbers stay
numbers.

Public API: :func:`summary_frame`, :func:`write_table`, :data:`TABLE_FORMATS`.
"""
from __future__ import annotations

import io
from pathlib import Path

from ._io import atomic_write, spreadsheet_safe
from .rounding import quartile_values

__all__ = ["TABLE_FORMATS", "summary_frame", "item_columns", "reversal_columns", "write_table", "neutralise"]

#: Table file formats, chosen by the output file's suffix.
TABLE_FORMATS = ("csv", "xlsx")


def neutralise(value):
    """A cell value safe for a spreadsheet: formula-like text gets a leading apostrophe
    (:func:`analysis._io.spreadsheet_safe`); other values are kept as they are."""
    return spreadsheet_safe(value) if isinstance(value, str) else value


def summary_frame(summary):
    """One row per item of a :class:`~analysis.likert.SurveySummary` (a pandas DataFrame)."""
    import pandas as pd
    labels = list(summary.scale.labels)
    return pd.DataFrame([{"item": it.item, "stem": it.stem, **item_columns(it, labels)}
                         for it in summary.items])


def item_columns(it, labels) -> dict:
    """The columns every summary table gives an item (:class:`~analysis.likert.ItemSummary`),
    in one order and with one set of names, whichever route made it (``--table`` alone, with
    ``--group`` or with ``--by``): reversal, n, missing, excluded, the count and percent of each
    label, the agreement percent with its interval, the disagreement percent, and the median,
    IQR (with Q1 and Q3, to two places: the IQR is Q3 - Q1 as written), mean and SD of the codes."""
    def pct(x):
        return None if it.agree.share is None or x is None else 100 * x
    iqr, q1, q3 = quartile_values(it.q1, it.q3)
    row = {**reversal_columns(it), "n": it.n, "missing": it.missing, "excluded": it.excluded}
    row.update({f"{lab} (count)": it.counts[lab] for lab in labels})
    row.update({f"{lab} (%)": it.percent[lab] for lab in labels})
    row.update({"agree (%)": pct(it.agree.share), "agree CI low (%)": pct(it.agree.ci[0]),
                "agree CI high (%)": pct(it.agree.ci[1]),
                "disagree (%)": None if it.disagree.share is None else 100 * it.disagree.share,
                "median": it.median, "IQR": iqr, "Q1": q1, "Q3": q3, "mean": it.mean, "SD": it.sd})
    return row


def reversal_columns(it) -> dict:
    """Table columns marking a reverse-keyed item: ``reversed`` (true or false) and
    ``statistics on reversed codes`` (counts and percentages are always raw)."""
    return {"reversed": it.reverse,
            "statistics on reversed codes": ", ".join(it.reversed_statistics)}


def table_format(path) -> str:
    """``"csv"`` or ``"xlsx"`` from the file name; ValueError naming ``--table`` otherwise."""
    fmt = Path(str(path)).suffix.lower().lstrip(".")
    if fmt not in TABLE_FORMATS:
        raise ValueError(f"--table {str(path)!r}: the file name must end in .csv or .xlsx")
    return fmt


def write_table(frame, path: "str | Path") -> Path:
    """Write a DataFrame as CSV (UTF-8 with BOM, so Excel reads it) or XLSX, atomically."""
    fmt = table_format(path)
    safe = frame.copy()
    safe.columns = [neutralise(str(c)) for c in safe.columns]
    import pandas as pd
    for c in safe.columns:
        if not pd.api.types.is_numeric_dtype(safe[c]):
            safe[c] = safe[c].astype(object).map(neutralise)
    if fmt == "csv":
        return atomic_write(path, safe.to_csv(index=False), encoding="utf-8-sig")
    import openpyxl
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "summary"
    ws.append(list(safe.columns))
    for rec in safe.itertuples(index=False):
        ws.append([None if v is pd.NA or (isinstance(v, float) and v != v) else v
                   for v in rec])
    # openpyxl would store "=..." text as a formula: neutralised cells start with "'"; mark
    # every text cell as a string so nothing is evaluated
    for row in ws.iter_rows():
        for cell in row:
            if isinstance(cell.value, str):
                cell.data_type = "s"
    buf = io.BytesIO()
    wb.save(buf)
    return atomic_write(path, buf.getvalue())
