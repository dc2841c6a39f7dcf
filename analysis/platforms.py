"""Survey platforms' export layouts: how each is recognised, its header rows, its metadata.

Each platform's export is recognised from its header (no option needed):

``qualtrics``
    Three header rows (field ids, question text, ``{"ImportId": ...}``), or the legacy
    two (``V1``/``ResponseID``, ``ResponseSet`` ... then the question text). Matrix
    columns (``Q1_1``) carry ``stem - statement`` in the text row.
``surveymonkey``
    ``Respondent ID``, ``Collector ID`` ...; a second header row names each matrix
    column's statement (``Response`` for a single question); the stem stands above the
    first column of its matrix only.
``canvas``
    Canvas survey/quiz "Student Analysis" report: ``name, id, sis_id, section,
    section_id, section_sis_id, submitted, attempt``, question columns
    ``"12345: question text"``, each (in quizzes) followed by a points column; only the
    question columns can be items.
``limesurvey``
    ``id, submitdate, lastpage, startlanguage`` ... (or their full-text headings);
    array statements as ``Q1[SQ001]`` or ``question [statement]``.
``moodle``
    Questionnaire or feedback export (``Response, Submitted on:, Institution,
    Department, Course, Group, ID, Full name, Username``); rate questions as
    ``Qnn_name->statement``.
``msforms``
    Microsoft Forms workbook (``ID, Start time, Completion time, Email, Name``).
``google``
    A ``Timestamp`` column; grid statements as ``question [row]``.

Items are named by their statement text; the question stem is kept apart
(:func:`split_stem`) so reports show it once above its statements.
"""
from __future__ import annotations

import re

__all__ = ["PLATFORMS", "SHAPES", "META", "detect", "header_rows", "signature_missing", "split_stem",
           "candidate", "is_blank_header", "header_row_missing",
           "name_matches", "item_matches", "resolve_reverse", "find_column", "repeated_column"]

#: How to supply a code map, for messages.
CODES_HINT = ("give the survey definition with --codes FILE.qsf (Qualtrics) or FILE.lss "
              "(LimeSurvey), or a code map --codes MAP.toml ([codes] 1 = \"Strongly "
              "disagree\" ...)")

PLATFORMS = ("google", "qualtrics", "surveymonkey", "canvas", "limesurvey", "moodle", "msforms")
#: Valid ``shape`` values of :func:`analysis.ingest.read_survey` (here, so that the
#: command line can list them without importing pandas).
SHAPES = ("auto", "wide", "long") + PLATFORMS + ("xlsx",)

META = {
    "google": {"timestamp", "email address", "email", "username", "score", "e-mail address"},
    "qualtrics": {
        "startdate", "enddate", "status", "ipaddress", "progress", "duration (in seconds)",
        "finished", "recordeddate", "responseid", "recipientlastname", "recipientfirstname",
        "recipientemail", "externalreference", "externaldatareference", "locationlatitude",
        "locationlongitude", "distributionchannel", "userlanguage", "q_recaptchascore",
        "q_relevantidduplicate", "q_relevantidduplicatescore", "q_relevantidfraudscore",
        "q_relevantidlaststartdate", "responseset", "name", "emailaddress", "locationaccuracy"},
    "surveymonkey": {"respondent id", "collector id", "start date", "end date", "ip address",
                     "email address", "first name", "last name", "custom data 1",
                     "custom data"},
    "canvas": set(),          # only "<id>: <question>" columns are candidates
    "limesurvey": {"id", "submitdate", "lastpage", "startlanguage", "seed", "token",
                   "startdate", "datestamp", "ipaddr", "refurl", "response id",
                   "date submitted", "last page", "start language", "date started",
                   "date last action", "ip address", "referrer url"},
    "moodle": {"response", "submitted on:", "submitted on", "institution", "department",
               "course", "group", "groups", "id", "full name", "username", "user", "userid",
               "date", "email address", "id number"},
    "msforms": {"id", "start time", "completion time", "email", "name", "last modified time",
                "total points", "quiz feedback", "language"},
}

#: Column names of a long file (a row per answer): respondent, item, answer.
LONG_RESP = ("respondent", "respondent_id", "respondentid", "respondent id", "id",
              "response_id", "responseid", "response id", "participant", "participant_id",
              "student", "student_id", "student id", "user", "user_id")
LONG_ITEM = ("item", "question", "question_id", "questionid", "item_id", "question id",
              "item id")
LONG_ANSWER = ("answer", "response", "value", "choice", "rating")


def long_column_refusal(flag: str, name: str, header: list[str]) -> "str | None":
    """Why ``flag`` (``--by``, ``--group``) cannot group a long file by its column ``name``:
    it is one of the file's respondent, item and answer columns (each respondent's answers
    are spread over its rows). None when ``name`` is another column, or the file is not long.
    Both routes word it here."""
    idx = [find_column(header, names) for names in (LONG_RESP, LONG_ITEM, LONG_ANSWER)]
    if None in idx:
        return None
    key = name.strip().casefold()
    for j, what in zip(idx, ("respondent", "item", "answer")):
        if header[j].strip().casefold() == key:
            cols = ", ".join(header[k].strip() for k in idx)
            return (f"{flag} {name.strip()}: {header[j].strip()!r} is the long file's {what} "
                    f"column ({cols}); group by another column")
    return None


def spaced_name(name: str) -> str:
    """A column name as every output prints it and as items are named: runs of white space
    (a line break in a quoted header cell) as one space, outer spaces trimmed."""
    return " ".join(str(name).split()) or str(name)


def find_column(header: list[str], names) -> "int | None":
    """Index of the first of ``names`` among the header (ignoring case and outer spaces)."""
    keys = [h.strip().casefold() for h in header]
    for n in names:
        if n in keys:
            return keys.index(n)
    return None


_CANVAS_ITEM = re.compile(r"^\s*\d+\s*:\s*(.+)$", re.S)
_BRACKET = re.compile(r"^([^\[]*\S)\s*\[(.+)\]\s*$", re.S)
_UNNAMED = re.compile(r"^(Unnamed: \d+(_level_\d+)?|column \d+)(\.\d+)?$")
_MATRIX_FIELD = re.compile(r"_\d+$")


def name_matches(pattern: str, name: str) -> bool:
    """A column name matches a name or a pattern, ignoring case and outer spaces.

    In a pattern ``*`` stands for any text and ``?`` for one character; everything else,
    square brackets included, is literal (Google and LimeSurvey headers hold
    ``[statement]``, which ``fnmatch`` would read as a set of characters).
    """
    from .scales import normalize_answer
    if normalize_answer(name) == normalize_answer(pattern):
        return True
    if "*" not in pattern and "?" not in pattern:
        return False
    rx = "".join(".*" if ch == "*" else "." if ch == "?" else re.escape(ch)
                 for ch in normalize_answer(pattern))
    return re.fullmatch(rx, normalize_answer(name), re.S) is not None


def item_matches(pattern: str, name: str, field: "str | None" = "") -> bool:
    """An item is named by its name (a statement text) or by its export field id
    (``Q1_4``), either as a name or as a pattern (:func:`name_matches`): the one rule of
    ``--items``, ``--reverse``, ``--reliability`` and claims."""
    return name_matches(pattern, name) or bool(field) and name_matches(pattern, field)


def resolve_reverse(source, names, reverse, fields=None) -> set:
    """The items named reverse-keyed (``--reverse``): names or patterns matched to ``names``.

    Parameters
    ----------
    source : str
        File named in the error.
    names : list of str
        The survey's items.
    reverse : str, list of str or None
        Names or ``*``/``?`` patterns (of names or export field ids).
    fields : list of str, optional
        Each item's export field id (``Q1_4``), when it has one.

    Raises
    ------
    SurveyInputError
        A name or pattern that matches no item (a typo is never ignored).
    """
    from .errors import SurveyInputError
    out = set()
    for pat in ([reverse] if isinstance(reverse, str) else list(reverse or [])):
        hits = [n for j, n in enumerate(names)
                if item_matches(pat, n, fields[j] if fields and j < len(fields) else "")]
        if not hits:
            raise SurveyInputError(f"reverse-keyed item {pat!r} is not an item; items are "
                                   f"{list(names)!r}", source)
        out.update(hits)
    return out


def is_blank_header(h: str) -> bool:
    """A header cell the reader had to name (pandas ``Unnamed: 3``, workbook ``column 4``)."""
    return not h.strip() or bool(_UNNAMED.match(h))


_CANVAS_POINTS = re.compile(r"^\s*\d+(\.\d+)?\s*$")


def points_column(shape: str, given: str) -> bool:
    """A Canvas quiz export's points column (header ``1.0`` after each question): never
    an item, and repeated by design."""
    return shape == "canvas" and bool(_CANVAS_POINTS.match(given))


def repeated_column(header: list[str], shape: "str | None" = None) -> "str | None":
    """Why two columns of ``header`` (names as written in the file) cannot be told apart,
    or None when every name is distinct.

    Names are compared as columns are matched everywhere (``--items``, ``--group``,
    DuckDB): ignoring case and spacing. Blank header cells name no column and are
    not compared. A Canvas export's points columns (``1.0`` after each question) repeat
    by design and are never read, so they are not compared either. The message names
    the first repeated name with all its 1-based positions, and how many other names
    repeat.
    """
    from .scales import normalize_answer
    where: dict[str, list[int]] = {}
    for j, h in enumerate(header):
        if not h.strip() or points_column(shape, h):
            continue
        where.setdefault(normalize_answer(h), []).append(j)
    repeated = [js for js in where.values() if len(js) > 1]
    if not repeated:
        return None
    js = repeated[0]
    cols = ", ".join(str(j + 1) for j in js[:-1]) + f" and {js[-1] + 1}"
    names = [header[j] for j in js]
    if len(set(names)) == 1:
        what = f"columns {cols} are {'both' if len(js) == 2 else 'all'} named {names[0]!r}"
    else:
        what = (f"columns {cols} are named " + ", ".join(map(repr, names[:-1]))
                + f" and {names[-1]!r}, which differ only in case or spacing (columns are "
                f"matched ignoring both)")
    more = len(repeated) - 1
    return (f"{what}; rename {'one' if len(js) == 2 else 'all but one'}"
            + (f" ({more} more name{'s' if more > 1 else ''} repeat{'' if more > 1 else 's'})"
               if more else ""))


def _keys(header) -> set:
    return {h.strip().casefold() for h in header}


def _import_id_row(peek) -> bool:
    return len(peek) >= 3 and any(c.strip().startswith(('{"ImportId"', "{'ImportId'"))
                                  for c in peek[2])


def detect(header: list[str], peek: list[list[str]]) -> "str | None":
    """The platform whose export this header is, or None."""
    keys = _keys(header)
    if _import_id_row(peek) or "responseset" in keys or {"v1", "v2", "v3"} <= keys:
        return "qualtrics"
    if {"respondent id", "collector id"} <= keys:
        return "surveymonkey"
    if {"sis_id", "submitted", "attempt"} <= keys or (
            "section_id" in keys and any(_CANVAS_ITEM.match(h) for h in header)):
        return "canvas"
    if {"submitdate", "lastpage"} <= keys or {"startlanguage", "lastpage"} <= keys or (
            {"response id", "date submitted", "last page"} <= keys):
        return "limesurvey"
    if {"submitted on:", "full name"} <= keys or {"response", "submitted on:"} <= keys or (
            {"full name", "username", "course"} <= keys):
        return "moodle"
    if {"start time", "completion time"} <= keys:
        return "msforms"
    if "timestamp" in keys:
        return "google"
    return None


def header_rows(shape: str, header: list[str], peek: list[list[str]]) -> int:
    """Header rows below the first that are not responses (0, 1 or 2)."""
    if shape == "qualtrics":
        return 2 if _import_id_row(peek) else 1
    if shape == "surveymonkey":
        return 1
    return 0


def _on_a_scale(cell: str) -> bool:
    from .scales import BUILTIN_SCALES
    return any(s.matches_label(cell) for s in BUILTIN_SCALES.values())


def _surveymonkey_row_missing(header: list[str], second: list[str]) -> "str | None":
    """Why the second row of a SurveyMonkey export is an answer row, or None.

    SurveyMonkey leaves the metadata columns of its statements row blank and writes
    statement text (or ``Response``) above the answers; a respondent id there, or an
    answer label of a built-in scale, means the row was deleted and respondent 1's
    answers moved up.
    """
    for name in ("respondent id", "collector id"):
        j = find_column(header, (name,))
        if j is not None and j < len(second) and second[j].strip():
            return f"{header[j].strip()} {second[j].strip()!r}"
    for h, cell in zip(header, second):
        if cell.strip() and candidate("surveymonkey", h) and _on_a_scale(cell):
            return f"the answer {cell.strip()!r}"
    return None


def _text_row(header: list[str], row: list[str]) -> bool:
    """Whether ``row`` is Qualtrics' question-text row: at least two metadata columns
    whose text is their field name spelled out (``StartDate`` above ``Start Date``)."""
    same = sum(1 for h, t in zip(header, row) if h.strip().casefold() in META["qualtrics"]
               and t.strip() and "".join(t.split()).casefold() == h.strip().casefold())
    return same >= 2


def header_row_missing(shape: str, header: list[str], records: list[list[str]],
                       row: int = 2) -> "str | None":
    """Why a platform export lacks one of its header rows (None when nothing is missing).

    Parameters
    ----------
    shape : str
        The shape detected or given (a Qualtrics export that lost a header row is no
        longer recognised, so ``wide`` is checked for Qualtrics rows too).
    header : list of str
        The first row.
    records : list of list of str
        The (at most two) rows below it, as read.
    row : int
        Spreadsheet row of ``records[0]``, for the message.
    """
    second = records[0]
    if shape == "surveymonkey":
        what = _surveymonkey_row_missing(header, second)
        if what:
            return ("SurveyMonkey's second header row (the statements row) is missing: "
                    f"row {row} holds answers ({what}), not statement text")
    if shape not in ("wide", "qualtrics"):
        return None
    if any(c.strip().startswith(('{"ImportId"', "{'ImportId'")) for c in second):
        return (f"Qualtrics' question-text header row is missing: row {row} holds the "
                "{\"ImportId\": ...} row, which Qualtrics writes below the question text")
    if (_text_row(header, second) and "responseset" not in _keys(header)
            and not _import_id_row([header] + records)):
        return (f"Qualtrics' third header row ({{\"ImportId\": ...}}) is missing: row {row} "
                f"holds question text but row {row + 1} holds answers")
    return None


def signature_missing(shape: str, header: list[str], peek: list[list[str]]) -> "str | None":
    """Why a forced ``shape`` does not fit the file (None when it fits)."""
    found = detect(header, peek)
    if shape in ("wide", "long") or found == shape:
        return None
    what = {"qualtrics": "no Qualtrics header rows (third row of {\"ImportId\": ...}, or "
                         "legacy ResponseSet / V1 columns)",
            "surveymonkey": "no Respondent ID and Collector ID columns",
            "canvas": "no Canvas Student Analysis columns (sis_id, submitted, attempt)",
            "limesurvey": "no LimeSurvey columns (submitdate, lastpage)",
            "moodle": "no Moodle columns (Submitted on:, Full name)",
            "msforms": "no Microsoft Forms columns (Start time, Completion time)",
            "google": "no Timestamp column"}.get(shape)
    if what is None:
        return None
    return (f"--shape {shape} does not fit this file: {what}"
            + (f"; it looks like a {found} export" if found else ""))


def candidate(shape: str, name: str, text: str = "") -> bool:
    """Whether a column may be an item at all (metadata columns may not).

    ``text`` is the column's question-text row where the export has one (the legacy
    Qualtrics field row says ``V7`` where the text row says ``Status``).
    """
    if shape == "canvas":
        return bool(_CANVAS_ITEM.match(name))
    meta = META.get(shape, ())
    return name.strip().casefold() not in meta and text.strip().casefold() not in meta


def split_stem(shape: str, field: str, text: str) -> tuple[str, str]:
    """(statement, stem) of a column from its header ``field`` and its question ``text``.

    ``text`` is the question-text row (Qualtrics) or the header itself. The stem is ""
    for a single question.
    """
    if shape == "canvas":
        m = _CANVAS_ITEM.match(text)
        return (" ".join(m.group(1).split()) if m else text), ""
    if shape == "qualtrics" and _MATRIX_FIELD.search(field.strip()):
        sep = " - " if " - " in text else "-"
        if sep in text:
            stem, _, statement = text.rpartition(sep)
            if statement.strip() and stem.strip():
                return statement.strip(), stem.strip()
        return text, ""
    if "->" in text and shape == "moodle":
        stem, _, statement = text.rpartition("->")
        return statement.strip(), stem.strip()
    m = _BRACKET.match(text)
    if m and shape in ("google", "limesurvey", "moodle", "msforms", "wide", None):
        return m.group(2).strip(), m.group(1).strip()
    return text, ""


def surveymonkey_names(header: list[str], second: list[str]) -> list[tuple[str, str]]:
    """(statement, stem) per column of a SurveyMonkey export's two header rows.

    The stem is written above the first column of a matrix only; later columns of the
    same matrix have a blank first-row cell (named ``Unnamed: n`` by the reader).
    """
    out = []
    stem = ""
    for h, s in zip(header, second + [""] * (len(header) - len(second))):
        if not is_blank_header(h):
            stem = h.strip()
        s = s.strip()
        if s in ("", "Response", "Open-Ended Response") or s.casefold() == stem.casefold():
            out.append((stem, ""))
        else:
            out.append((s, stem))
    return out
