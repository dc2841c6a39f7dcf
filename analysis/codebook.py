"""What an export's numeric (or short) answer codes mean: survey definitions and code maps.

A numeric export stores each answer as the number of its choice, in the order the
survey's author listed the choices. That order is not known from the numbers: a
Qualtrics matrix listing "Strongly agree" first codes it 1. So codes are read only
through one of:

``.qsf``
    A Qualtrics survey definition (JSON; Survey > Tools > Import/Export > Export
    survey). Matrix and multiple-choice questions give, per export column
    (``DataExportTag`` + ``_`` + choice id, or the choice's own export tag), the code
    of every answer (its recode value, else its id) and the statement text.
``.lss``
    A LimeSurvey survey structure (XML; Display/Export > Survey structure). Each
    question's answer codes (``A1``, ``1`` ...) give the answer text; array
    sub-questions give the statement text of columns ``Q1[SQ001]``.
``.toml``
    A code map written by hand::

        [codes]             # code = answer label, for every item column
        1 = "Strongly disagree"
        2 = "Disagree"
        3 = "Neither agree nor disagree"
        4 = "Agree"
        5 = "Strongly agree"
        columns = ["Q2_*"]  # optional: the columns it applies to (default: any
                            # column all of whose answers are codes of the map)

Public API: :func:`load_codebook` -> :class:`Codebook`.
"""
from __future__ import annotations

import json
import re
from dataclasses import dataclass, field
from pathlib import Path

from ._io import read_bytes, read_toml
from .errors import SurveyInputError
from .platforms import CODES_HINT

__all__ = ["Codebook", "load_codebook", "CODES_HINT"]


_MAX_DEFINITION_BYTES = 50_000_000
_TAG = re.compile(r"<[^>]*>")


def _plain(html: str) -> str:
    """Question text without HTML tags and with white space collapsed."""
    text = _TAG.sub(" ", str(html or ""))
    for a, b in (("&nbsp;", " "), ("&amp;", "&"), ("&lt;", "<"), ("&gt;", ">"),
                 ("&quot;", '"'), ("&#39;", "'")):
        text = text.replace(a, b)
    return " ".join(text.split())


def _code_key(text) -> str:
    """Canonical text of a code (``"4"``, ``"4.0"`` -> ``"4"``; ``" A1 "`` -> ``"a1"``)."""
    t = str(text).strip()
    try:
        v = float(t)
        if v == v and v.is_integer():
            return str(int(v))
    except ValueError:
        pass
    return t.casefold()


@dataclass
class Codebook:
    """Answer codes and statement texts of export columns.

    Attributes
    ----------
    source : str
        The definition or code-map file.
    columns : dict of str to dict
        Per export column (case-folded header): code key -> answer text.
    default : dict or None
        A map for any column (a code map without per-column entries).
    patterns : list of str
        Columns the default map is limited to (``fnmatch`` patterns; empty: any).
    texts : dict of str to str
        Per export column: statement (item) text.
    stems : dict of str to str
        Per export column: the question stem of a matrix/array question.
    """

    source: str
    columns: dict = field(default_factory=dict)
    default: "dict | None" = None
    patterns: list = field(default_factory=list)
    texts: dict = field(default_factory=dict)
    stems: dict = field(default_factory=dict)

    def map_for(self, column: str) -> "dict | None":
        """The code -> answer map of one column, or None."""
        key = column.strip().casefold()
        if key in self.columns:
            return self.columns[key]
        if self.default is not None:
            from .ingest import name_matches
            if not self.patterns or any(name_matches(p, column) for p in self.patterns):
                return self.default
        return None

    @staticmethod
    def key(code) -> str:
        return _code_key(code)


def load_codebook(path: "str | Path") -> Codebook:
    """Read a ``.qsf``, ``.lss`` or ``.toml`` code map (see the module docstring).

    Raises
    ------
    SurveyInputError
        Unreadable file, unknown kind, or a definition without any coded question.
    """
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix == ".toml":
        return _from_toml(p)
    raw = read_bytes(p)
    if len(raw) > _MAX_DEFINITION_BYTES:
        raise SurveyInputError(f"survey definition larger than {_MAX_DEFINITION_BYTES} bytes",
                               str(p))
    head = raw[:200].lstrip(b"\xef\xbb\xbf \t\r\n")
    if suffix == ".qsf" or head.startswith(b"{"):
        book = _from_qsf(raw, str(p))
    elif suffix == ".lss" or head.startswith(b"<"):
        book = _from_lss(raw, str(p))
    else:
        raise SurveyInputError("--codes needs a .qsf (Qualtrics), .lss (LimeSurvey) or .toml "
                               "code map", str(p))
    if not book.columns:
        raise SurveyInputError("no coded questions in the survey definition", str(p))
    return book


def _from_toml(p: Path) -> Codebook:
    data = read_toml(p)
    for key in data:
        if key not in ("codes", "columns"):
            raise SurveyInputError(f"key {key!r}: unknown key; allowed: ['codes', 'columns']",
                                   str(p))
    codes = data.get("codes")
    if isinstance(codes, dict) and "columns" in codes:   # columns = [...] under [codes]
        if "columns" in data:
            raise SurveyInputError("key 'columns': given twice (at the top and under "
                                   "[codes]); give it once", str(p))
        codes = dict(codes)
        data = {**data, "columns": codes.pop("columns")}
    if not isinstance(codes, dict) or not codes or not all(
            isinstance(v, str) and v.strip() for v in codes.values()):
        raise SurveyInputError("key 'codes': must be a table of code = \"answer label\"", str(p))
    cols = data.get("columns", [])
    if not isinstance(cols, list) or not all(isinstance(c, str) for c in cols):
        raise SurveyInputError("key 'columns': must be a list of column names or patterns",
                               str(p))
    return Codebook(str(p), default={_code_key(k): v for k, v in codes.items()},
                    patterns=list(cols))


def _from_qsf(raw: bytes, source: str) -> Codebook:
    try:
        doc = json.loads(raw.decode("utf-8-sig"))
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        raise SurveyInputError(f"not a Qualtrics .qsf file (JSON: {e})", source) from None
    except RecursionError:
        raise SurveyInputError("not a Qualtrics .qsf file (JSON nested too deeply)",
                               source) from None
    elements = doc.get("SurveyElements") if isinstance(doc, dict) else None
    if not isinstance(elements, list):
        raise SurveyInputError("not a Qualtrics .qsf file (no SurveyElements)", source)
    book = Codebook(source)
    for el in elements:
        if not isinstance(el, dict) or el.get("Element") != "SQ":
            continue
        q = el.get("Payload")
        if not isinstance(q, dict):
            continue
        tag = str(q.get("DataExportTag") or q.get("QuestionID") or "")
        qtext = _plain(q.get("QuestionText", ""))
        choices = q.get("Choices") if isinstance(q.get("Choices"), dict) else {}
        recode = q.get("RecodeValues") if isinstance(q.get("RecodeValues"), dict) else {}
        if q.get("QuestionType") == "Matrix" and isinstance(q.get("Answers"), dict):
            answers = {_code_key(recode.get(aid, aid)): _plain(a.get("Display", ""))
                       for aid, a in q["Answers"].items() if isinstance(a, dict)}
            tags = q.get("ChoiceDataExportTags") or {}
            for cid, c in choices.items():
                col = str(tags.get(cid) or f"{tag}_{cid}") if isinstance(tags, dict) \
                    else f"{tag}_{cid}"
                key = col.strip().casefold()
                book.columns[key] = answers
                book.texts[key] = _plain(c.get("Display", "")) if isinstance(c, dict) else col
                book.stems[key] = qtext
        elif q.get("QuestionType") == "MC" and choices:
            key = tag.strip().casefold()
            book.columns[key] = {_code_key(recode.get(cid, cid)): _plain(c.get("Display", ""))
                                 for cid, c in choices.items() if isinstance(c, dict)}
            book.texts[key] = qtext
    return book


def _rows(root, table: str) -> list[dict]:
    node = root.find(table)
    if node is None or node.find("rows") is None:
        return []
    return [{child.tag: (child.text or "") for child in row}
            for row in node.find("rows").findall("row")]


def _from_lss(raw: bytes, source: str) -> Codebook:
    if b"<!DOCTYPE" in raw[:4096].upper() or b"<!ENTITY" in raw.upper():
        raise SurveyInputError("survey definition declares a DOCTYPE/ENTITY; not read", source)
    import xml.etree.ElementTree as ET
    try:
        root = ET.fromstring(raw)
    except ET.ParseError as e:
        raise SurveyInputError(f"not a LimeSurvey .lss file (XML: {e})", source) from None
    questions = _rows(root, "questions")
    qtexts = {r.get("qid"): r.get("question", "") for r in _rows(root, "question_l10ns")}
    answers: dict[str, dict] = {}
    aid_text = {r.get("aid"): r.get("answer", "") for r in _rows(root, "answer_l10ns")}
    for r in _rows(root, "answers"):
        text = r.get("answer", aid_text.get(r.get("aid"), ""))
        answers.setdefault(r.get("qid"), {})[_code_key(r.get("code", ""))] = _plain(text)
    by_qid = {r.get("qid"): r for r in questions}
    for r in _rows(root, "subquestions"):
        by_qid.setdefault(r.get("qid"), r)
    book = Codebook(source)
    for qid, r in by_qid.items():
        parent = r.get("parent_qid", "0")
        text = _plain(r.get("question", qtexts.get(qid, "")))
        if parent and parent != "0":
            pq = by_qid.get(parent)
            if pq is None or parent not in answers:
                continue
            key = f"{pq.get('title', '')}[{r.get('title', '')}]".casefold()
            book.columns[key] = answers[parent]
            book.texts[key] = text
            book.stems[key] = _plain(pq.get("question", qtexts.get(parent, "")))
        elif qid in answers:
            key = r.get("title", "").casefold()
            book.columns[key] = answers[qid]
            book.texts[key] = text
    return book
