"""Fuzzing ``python -m analysis`` with hostile input: never a traceback, a hang or a lost row.

Each example runs the real command line in process (``main(argv)``, stdout and stderr
captured) and must end in one of two ways:

- exit 2 with exactly one line on stderr, ``error: ...``; or
- exit 0 with an answer that holds: for every item counted + missing + excluded equals
  the respondents, and where the test wrote the survey itself, the counts equal the
  test's own tally of what it wrote (labels, codes, blanks, not-applicable answers).

Strategies: CSV bytes (a survey the test tallies, rendered with hostile cell text,
delimiters, quotes, byte-order marks and line ends; and raw bytes), XLSX bytes (built
with openpyxl, then with a lying ``<dimension>`` record, truncated XML or entities),
claims and scale TOML files (typo keys, wrong types, 0 and negative items, nan, huge
numbers, deep nesting), and command-line flag values.

Budget: every test uses ``_settings(n)``. ``max_examples`` (20-40, about 190 runs in
all, plus the explicit ``@example`` cases of issue 10) is chosen so that each test takes
well under a second of CPU (a CLI run is 5-20 ms), so the module adds about five seconds
to ``make test``; ``derandomize=True`` makes ``make test`` reproducible (the
same examples every run: a failure is a bug, never flakiness). No wall-clock deadline:
on a loaded machine (2 cores shared with other runs) a 20 ms example once took over
5 s of wall time and failed the suite; the hang guard is pytest-timeout's 300 s.
"""
from __future__ import annotations

import csv
import io
import json
import re
import string
import tomllib

from hypothesis import HealthCheck, assume, example, given, settings
from openpyxl.cell.cell import ILLEGAL_CHARACTERS_RE as ILLEGAL
from hypothesis import strategies as st

import xlsx_factory as xf
from analysis.scales import BUILTIN_SCALES

PAPER = BUILTIN_SCALES["paper"]
LABELS = list(PAPER.labels)
CODE = {i: str(int(c)) for i, c in enumerate(PAPER.codes)}       # label position -> code text
NA_TEXTS = ["N/A", " not applicable ", "Does not apply"]
# texts that match no label, code or not-applicable answer of the paper scale
JUNK = ["=1+1", "@SUM(A1)", "+cmd|' /C calc'!A0", "-2", "Definitely Agreee", "6", "0", "nan",
        "inf", "yes", "<b>x</b>", "'", '"', "a,b", "a;b", "x\ny", "1.5", "\u202eevil", "Ｎeutral"]


def _settings(n: int):
    # function_scoped_fixture: the tests use capsys through `analysis_cli`, which reads
    # and clears the captured output on every call, so nothing leaks between examples
    return settings(max_examples=n, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.function_scoped_fixture,
                                           HealthCheck.too_slow])


def _check_outcome(code: int, out: str, err: str, where: tuple = ()) -> dict | None:
    """Exit 2 with one error line (naming one of ``where`` or a flag, when given), or exit 0
    with JSON whose items account for everyone."""
    assert "Traceback" not in err, err
    if code == 2:
        assert err.count("\n") == 1 and err.startswith("error: "), err
        if where:
            assert any(str(w) in err for w in where) or "argument --" in err, err
        return None
    assert code == 0, (code, err)
    data = json.loads(out)
    if "items" in data:
        for item in data["items"]:
            assert item["n"] + item["missing"] + item["excluded"] == data["respondents"], item
            assert sum(item["counts"].values()) == item["n"], item
    return data


# ---------------------------------------------------------------------------
# CSV: a survey the test tallies, rendered with hostile text
# ---------------------------------------------------------------------------
NAME_CHARS = string.ascii_letters + string.digits + " _.()"


@st.composite
def cells(draw):
    """(kind, position, text): kind is label / code / blank / na / junk."""
    kind = draw(st.sampled_from(["label", "label", "label", "code", "blank", "na", "junk"]))
    if kind in ("label", "code"):
        i = draw(st.integers(0, len(LABELS) - 1))
        text = LABELS[i] if kind == "label" else CODE[i]
        case = draw(st.sampled_from([str, str.upper, str.lower, lambda t: t.replace(" ", "  ")]))
        pad = draw(st.sampled_from(["", " ", "\t"]))
        return kind, i, pad + case(text) + pad.strip(" ")
    if kind == "blank":
        return kind, None, draw(st.sampled_from(["", " ", "  "]))
    if kind == "na":
        return kind, None, draw(st.sampled_from(NA_TEXTS))
    # (no NUL: a text file holding one is refused as UTF-16 or binary, which the hostile-bytes
    # test below covers)
    return kind, None, draw(st.sampled_from(JUNK) | st.text(
        st.characters(exclude_characters="\x00", exclude_categories=("Cs",)), min_size=1, max_size=8).map(lambda t: "zz" + t))


@st.composite
def tallied_surveys(draw):
    """Header names, the cell matrix, and the column-major order of answers."""
    m = draw(st.integers(1, 4))
    names = draw(st.lists(st.text(NAME_CHARS, min_size=1, max_size=8).filter(
        lambda t: t.strip() and not re.fullmatch(r"\d+|#", t.strip())),
        min_size=m, max_size=m, unique_by=lambda t: " ".join(t.split()).casefold()))
    n = draw(st.integers(1, 8))
    matrix = [[draw(cells()) for _ in range(m)] for _ in range(n)]
    # one column has no delimiter to find: an answer holding ',', ';' or a tab makes the
    # file a valid CSV of another delimiter too (refused or read that way, by design)
    assume(m > 1 or not any(c in t for row in matrix for _, _, t in row for c in ",;\t"))
    return names, matrix


def _tally(names, matrix, unknown_as_missing: bool):
    """Expected per-item counts, or the (row, column) of the first unknown answer."""
    expected = {}
    for j, name in enumerate(names):
        counts = [0] * len(LABELS)
        missing = excluded = 0
        for r, row in enumerate(matrix):
            kind, i, _ = row[j]
            if kind in ("label", "code"):
                counts[i] += 1
            elif kind == "na":
                excluded += 1
            elif kind == "blank" or unknown_as_missing:
                missing += 1
            else:
                return ("error", r + 2, name)         # header is row 1
        expected[name] = (counts, missing, excluded)
    return expected


def _render_csv(names, matrix, sep: str, bom: bool, crlf: bool) -> bytes:
    buf = io.StringIO()
    end = "\r\n" if crlf else "\n"
    w = csv.writer(buf, delimiter=sep, lineterminator=end)
    # csv quotes a field holding its own line terminator only: a bare CR in an unquoted
    # field is a line break to every reader (and to ours), so such rows are quoted whole
    quoted = csv.writer(buf, delimiter=sep, lineterminator=end, quoting=csv.QUOTE_ALL)
    w.writerow(names)
    for row in matrix:
        texts = [t for _, _, t in row]
        (quoted if any("\r" in t or "\n" in t for t in texts) else w).writerow(texts)
    return (b"\xef\xbb\xbf" if bom else b"") + buf.getvalue().encode("utf-8")


def _code_map(folder) -> str:
    """A --codes map saying what the paper scale's numeric codes mean, for every column.

    Numeric answers are refused unless a code map (or survey definition) says which end
    of the numbering means agreement (issue 9); with this map the test's tally of codes holds.
    """
    f = folder / "fuzz_codes.toml"
    f.write_text('columns = ["*"]\n[codes]\n' + "".join(
        f'"{CODE[i]}" = "{LABELS[i]}"\n' for i in CODE), encoding="utf-8")
    return str(f)


def _assert_tally(data: dict, names, matrix, expected):
    assert data["respondents"] == len(matrix)         # no row lost, none invented
    got = {it["item"]: it for it in data["items"]}
    # item names are shown with their white space collapsed ("A " -> "A"); the strategy
    # draws names that stay distinct after that
    shown = {name: " ".join(name.split()) for name in names}
    assert set(got) == set(shown.values()), (list(got), names)
    for name, (counts, missing, excluded) in expected.items():
        it = got[shown[name]]
        assert [it["counts"][lab] for lab in LABELS] == counts, (name, it)
        assert (it["missing"], it["excluded"]) == (missing, excluded), (name, it)


@_settings(30)
@given(tallied_surveys(), st.sampled_from([",", ";", "\t"]), st.booleans(), st.booleans(),
       st.booleans(), st.booleans())
def test_csv_survey_counts_every_answer(analysis_cli, tmp_path_factory, survey, sep, bom, crlf,
                                        unknown_as_missing, code_map):
    names, matrix = survey
    f = tmp_path_factory.getbasetemp() / "fuzz_survey.csv"
    f.write_bytes(_render_csv(names, matrix, sep, bom, crlf))
    argv = ["summarize", str(f), "--scale", "paper", "--json", "--items", *names]
    # names are matched as fnmatch patterns too: this alphabet has no pattern characters
    if unknown_as_missing:
        argv.append("--unknown-as-missing")
    if code_map:
        argv += ["--codes", _code_map(tmp_path_factory.getbasetemp())]
    code, out, err = analysis_cli(*argv)
    data = _check_outcome(code, out, err)
    kinds = {k for row in matrix for k, _, _ in row}
    if "code" in kinds and not code_map:
        # a numeric answer without a code map is refused (or an unknown answer first)
        assert code == 2, out
        assert "--codes" in err or ("junk" in kinds and "not on scale" in err), err
        if "junk" not in kinds:
            assert "numeric answer" in err, err
        return
    expected = _tally(names, matrix, unknown_as_missing)
    if isinstance(expected, tuple):                    # an unknown answer: named, exit 2
        _, row, name = expected
        assert code == 2, out
        assert f"column {name!r}" in err and f"row {row}," in err, (err, row, name)
        return
    # a row of blank cells is an empty row, not a respondent (as an empty line), unless the file
    # has one column, where an empty line is a blank answer
    respondents = [row for row in matrix if len(names) == 1 or any(k != "blank" for k, _, _ in row)]
    if not respondents:
        assert code == 2 and "no responses below the header row" in err, (out, err)
        return
    assert data is not None, err
    _assert_tally(data, names, respondents, _tally(names, respondents, unknown_as_missing))


HOSTILE_PIECES = [b",", b";", b"\t", b'"', b"\n", b"\r\n", b"\r", b"\x00", b"\xff\xfe",
                  b"\xef\xbb\xbf", b"#", b"Definitely Agree", b"Neutral", b"N/A", b"5", b"q1",
                  b"=cmd()", b"\xe9", b"\xc3", b"  ", b"Timestamp", b"respondent", b"item",
                  b"answer", b'{"ImportId":"x"}', b"Status", b"Survey Preview"]


@_settings(40)
@given(st.lists(st.sampled_from(HOSTILE_PIECES) | st.binary(max_size=6), max_size=40),
       st.sampled_from([[], ["--scale", "paper"], ["--unknown-as-missing"],
                        ["--encoding", "cp1252"], ["--shape", "long"]]))
@example([b"q1,q2\n\nNeutral,\"", b"x" * 140_000, b"\"\n"], [])   # past csv's field limit
@example([b"q1,q2\nNeutral,Neutral,\"", b"x" * 140_000, b"\"\n"], [])
def test_csv_hostile_bytes(analysis_cli, tmp_path_factory, pieces, extra):
    f = tmp_path_factory.getbasetemp() / "fuzz_bytes.csv"
    f.write_bytes(b"".join(pieces))
    code, out, err = analysis_cli("summarize", str(f), "--json", *extra)
    _check_outcome(code, out, err, where=(f,))


# ---------------------------------------------------------------------------
# XLSX
# ---------------------------------------------------------------------------
XLSX_SAFE = st.text(string.ascii_letters + string.digits + " ,;'\"<>&%", min_size=1, max_size=8)


@_settings(20)
@given(tallied_surveys(), st.sampled_from(["none", "dimension", "truncated", "xxe", "bomb"]),
       st.sampled_from(["A1:A1", "A1:B2", "B2:C3", "A1:XFD1048576"]), st.floats(0.05, 0.95))
def test_xlsx_survey(analysis_cli, tmp_path_factory, survey, damage, ref, keep):
    names, matrix = survey
    # openpyxl would store "=..." as a formula and refuses control characters: such junk
    # stays in the CSV tests (here it becomes plain junk); codes are stored as numbers,
    # as spreadsheets store them
    matrix = [[(k, i, "zzjunk" if k == "junk" and (t.startswith("=") or ILLEGAL.search(t))
                else t) for k, i, t in row] for row in matrix]
    rows = [list(names)] + [[int(t) if k == "code" else t for k, _, t in row] for row in matrix]
    data_bytes = xf.workbook(rows)
    if damage == "dimension":
        data_bytes = xf.with_dimension(data_bytes, ref)
    elif damage == "truncated":
        data_bytes = xf.truncated(data_bytes, keep)
    elif damage in ("xxe", "bomb"):
        data_bytes = xf.with_entity(data_bytes, damage)
    f = tmp_path_factory.getbasetemp() / "fuzz.xlsx"
    f.write_bytes(data_bytes)
    code, out, err = analysis_cli("summarize", str(f), "--scale", "paper", "--json",
                                  "--unknown-as-missing", "--items", *names,
                                  "--codes", _code_map(tmp_path_factory.getbasetemp()))
    data = _check_outcome(code, out, err, where=(f,))
    if damage in ("none", "dimension"):
        # rows below the data whose cells are all blank are no respondents in a workbook
        # (a sheet shows empty rows without end); blank rows between answers are
        while matrix and all(k == "blank" for k, _, _ in matrix[-1]):
            matrix = matrix[:-1]
        if not matrix:
            assert code == 2 and "no responses" in err, (out, err)
            return
        assert data is not None, err
        _assert_tally(data, names, matrix, _tally(names, matrix, True))
    elif damage in ("xxe", "bomb"):
        assert code == 2 and "entities" in err and "root:" not in out


# ---------------------------------------------------------------------------
# claims and scale TOML files
# ---------------------------------------------------------------------------
SURVEY = ("q1,q2\n" + "Definitely Agree,Neutral\n" * 3 + "Neutral,Partially Agree\n"
          + ",N/A\n")
# written above: q1 = DA 3, Neutral 1, blank 1; q2 = Neutral 3, PA 1, N/A 1
TALLY = {"q1": {"Definitely Agree": 3, "Neutral": 1}, "q2": {"Neutral": 3, "Partially Agree": 1}}
VALID_N = {"q1": 4, "q2": 4}

TOML_VALUES = st.sampled_from(
    ["0", "-1", "1", "2", "3", "1e400", "nan", "-inf", "true", '"q1"', '"Q2 "', '"nope"', '""',
     "[]", "[1, 2]", '["Definitely Agree"]', '["neutral", "PARTIALLY AGREE"]', '["Agree"]',
     '">"', '"<="', '"=>"', '"%"', '"fraction"', "90", "50", "0.5", "{a = 1}",
     "9" * 30, "[" * 300 + "]" * 300, '"' + "x" * 200 + '"'])
# values one step from valid, per key (drawn as often as all of TOML_VALUES together)
NEAR = {"item": st.sampled_from(["0", "-1", "3", "-2", "1", '"q3"', '"Q1 "']),
        "threshold": st.sampled_from(["nan", "inf", "-1", "101", "100", "0", "1.5"]),
        "unit": st.sampled_from(['"fraction"', '"%"', '"percent"']),
        "comparison": st.sampled_from(['"<"', '">="', '"=="', "1"]),
        "categories": st.sampled_from(['["Neutral", "neutral"]', '["Neutral", "Partially Agree"]',
                                       '["N/A"]', '["Neutral", 1]'])}
CLAIM_KEYS = ["item", "threshold", "id", "item", "categories", "comparison", "threshold", "unit", "statement",
              "printed", "comparision", "treshold", "items", "decimals"]


@st.composite
def claims_files(draw):
    tables = []
    for _ in range(draw(st.integers(0, 3))):
        # a valid claim with a few keys changed, added or removed: near misses are the
        # cases a lax reader gets wrong (item = 0, a typo key, a nan threshold)
        body = {"item": draw(st.sampled_from(['"q1"', "2", '" Q2"'])),
                "categories": draw(st.sampled_from(['["Definitely Agree"]', '["neutral"]'])),
                "threshold": draw(st.sampled_from(["50", "0.5"]))}
        for _ in range(draw(st.integers(0, 2))):
            key = draw(st.sampled_from(CLAIM_KEYS))
            if draw(st.integers(0, 4)) == 0:
                body.pop(key, None)
            else:
                body[key] = draw(NEAR.get(key, st.nothing()) | TOML_VALUES)
        tables.append("[[claims]]\n" + "".join(f"{k} = {v}\n" for k, v in body.items()))
    head = draw(st.sampled_from(["", "", "", "# comment\n", "claims = [1, 2]\n", "claim = 1\n"]))
    return head + "\n".join(tables)


def _expected_claim(spec: dict):
    """(k, n) of a claim on SURVEY, tallied by the test."""
    item = spec["item"]
    name = f"q{item}" if isinstance(item, int) else " ".join(item.split()).casefold()
    tally = TALLY[name]
    keys = {lab.casefold(): lab for lab in LABELS}
    k = sum(tally.get(keys[c.strip().casefold()], 0) for c in spec["categories"])
    return k, VALID_N[name]


_CLAIM = '[[claims]]\ncategories = ["Definitely Agree"]\nthreshold = 50\n'


@_settings(30)
@given(claims_files())
# the cases of issue 10, always run besides the generated ones
@example(_CLAIM + "item = 0\n")
@example(_CLAIM + "item = -1\n")
@example(_CLAIM + "item = 1\ncomparision = '<'\n")
@example('[[claims]]\nitem = 1\ncategories = ["Neutral"]\nthreshold = nan\n')
@example("claims = [1, 2]\n")
@example('[[claims]]\nitem = 2\ncategories = ["Neutral", " NEUTRAL"]\nthreshold = 50\n')
@example("claims = " + "[" * 50_000 + "]" * 50_000 + "\n")
def test_claims_files(analysis_cli, tmp_path_factory, text):
    base = tmp_path_factory.getbasetemp()
    (base / "fuzz_claims_survey.csv").write_text(SURVEY)
    f = base / "fuzz_claims.toml"
    f.write_text(text)
    code, out, err = analysis_cli("claims", str(base / "fuzz_claims_survey.csv"), str(f),
                                  "--json")
    data = _check_outcome(code, out, err)
    if data is None:
        assert str(f) in err or "q1" in err, err        # the claims file (or the item) is named
        return
    specs = tomllib.loads(text)["claims"]
    assert len(data["claims"]) == len(specs)
    for spec, got in zip(specs, data["claims"]):
        assert set(spec) <= {"id", "item", "categories", "comparison", "threshold", "unit",
                             "statement", "printed", "decimals"}
        assert not isinstance(spec["item"], int) or spec["item"] >= 1
        assert (got["k"], got["n"]) == _expected_claim(spec)


SCALE_KEYS = ["name", "labels", "codes", "positive", "negative", "neutral", "not_applicable",
              "aliases", "description", "lables"]
SCALE_VALUES = st.sampled_from(
    ['["Low", "High"]', '["Low", "Mid", "High"]', "[1, 2]", "[1, nan]", "[1, inf]",
     "[1, 1]", "[1, 2, 3]", '["Low"]', '["High"]', "[]", '"x"', "3", "{Lo = \"Low\"}",
     "[" + "9" * 5000 + ", 1]", "[" * 200 + "]" * 200, '["N/A"]', '["Low", "low"]'])


@_settings(20)
@given(st.dictionaries(st.sampled_from(SCALE_KEYS), SCALE_VALUES, max_size=5))
@example({"labels": '["Low", "Mid", "High"]', "codes": "[1, nan, 3]"})     # issue 10
@example({"labels": '["Low", "High"]', "codes": "[1, inf]"})
@example({"labels": "[" * 50_000 + "]" * 50_000})
def test_scale_files(analysis_cli, tmp_path_factory, body):
    base = tmp_path_factory.getbasetemp()
    survey = base / "fuzz_scale_survey.csv"
    survey.write_text("q1\nLow\nHigh\nlow\n\nN/A\n")
    f = base / "fuzz_scale.toml"
    f.write_text("".join(f"{k} = {v}\n" for k, v in body.items()))
    code, out, err = analysis_cli("summarize", str(survey), "--scale", str(f), "--json")
    data = _check_outcome(code, out, err, where=(f, survey))
    if data is not None:
        assert data["respondents"] == 5
        # nan or infinite codes are never accepted
        assert not re.search(r"nan|inf", body.get("codes", ""))


# ---------------------------------------------------------------------------
# command-line flag values
# ---------------------------------------------------------------------------
FLAG_VALUES = st.sampled_from(["0", "-1", "1", "2", "0.95", "1.0", "nan", "inf", "1e9",
                               "99999999999999999999", "x", "", " ", "--json", "q1", "*",
                               "[", "utf-16", "idna", "rot13", "cp1252", "wilson", "beta",
                               "round", "agree", "long", "xlsx", "1000001"])
FLAGS = ["--confidence", "--decimals", "--respondents", "--min-group", "--encoding", "--items",
         "--reverse", "--group", "--ci", "--shape", "--order", "--percent-method",
         "--reliability", "--scale"]


@_settings(30)
@given(st.lists(st.tuples(st.sampled_from(FLAGS), FLAG_VALUES), max_size=3))
@example([("--confidence", "nan")])
@example([("--encoding", "idna")])
@example([("--respondents", "99999999999999999999")])
def test_summarize_flag_values(analysis_cli, tmp_path_factory, flags):
    base = tmp_path_factory.getbasetemp()
    survey = base / "fuzz_flags_survey.csv"
    survey.write_text(SURVEY)
    argv = [a for pair in flags for a in pair]
    code, out, err = analysis_cli("summarize", str(survey), "--json", *argv)
    data = _check_outcome(code, out, err, where=(survey, "--"))
    if data is not None and len(data["items"]) == 2 and "--respondents" not in argv:
        for it in data["items"]:                        # flags never change what is counted
            assert {k: v for k, v in it["counts"].items() if v} == TALLY[it["item"]]


@_settings(20)
@given(st.sampled_from(["--n", "--n-range", "--decimals", "--rule"]),
       st.lists(FLAG_VALUES, min_size=1, max_size=2))
@example("--n", ["1000001"])
@example("--n-range", ["2", "1"])
def test_verify_table_flag_values(analysis_cli, flag, values):
    from analysis.tables import published_dir
    code, out, err = analysis_cli("verify-table", str(published_dir() / "table1.csv"), "--json",
                                  flag, *values)
    data = _check_outcome(code, out, err)
    if data is not None:
        for row in data["rows"]:
            for cell in row["cells"]:
                assert cell["attainable"] == bool(cell["counts"])
                assert all(0 <= k <= data["n"] for k in cell["counts"])
