"""The validation report's verdicts, paper values, summary.json and page layout (validation/report/).

The real sections take minutes; these tests build a report from a fake section instead.  The paper
values are checked against the paper's text where it is present: ``$GEAR_RATTLE_PAPER_TXT``, or
``../shared/paper.txt`` relative to the repository root.
"""

from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
from fractions import Fraction
from html import escape as html_escape
from pathlib import Path

import pytest
from reportfake import LONG, build_fake_report

from gear_rattle.validation.report import builder
from gear_rattle.validation.paper import KINDS, PAPER, PaperValue
from gear_rattle.validation.report.document import Document, Section, check_keys, md_slug, render_html, render_markdown
from gear_rattle.validation.report.verdict import (
    AGREES,
    DISAGREES,
    NOT_COMPARED,
    Z_AGREE,
    compare,
    compare_bound,
    compare_value,
    internal_check,
    row,
)

REPO = Path(__file__).resolve().parents[1]
PAPER_TXT = Path(os.environ.get("GEAR_RATTLE_PAPER_TXT") or REPO.parent / "shared" / "paper.txt")
REQUIRED_KEYS = ("r2", "r1", "alpha1", "mean_n", "kappa", "decay_time", "phi_500", "phi_1000")
#: Why the quote checks skip, and how to run them: the paper's text is not part of the repository.
PAPER_MISSING = (
    f"the paper's text is not at {PAPER_TXT}: to check the quotes, put the text of de Souza et al., "
    f"Chaos Solitons Fractals 21 (2004) 763-772 (plain text, math in LaTeX) at ../shared/paper.txt "
    f"beside the clone ({REPO.parent / 'shared' / 'paper.txt'}) or set GEAR_RATTLE_PAPER_TXT=/path/to/it"
)


def _norm(s: str) -> str:
    return re.sub(r"\s+", " ", s).strip()


# ---------------------------------------------------------------------------------------- paper.py


@pytest.mark.skipif(not PAPER_TXT.exists(), reason=PAPER_MISSING)
@pytest.mark.parametrize("key", sorted(PAPER))
def test_every_quote_is_verbatim_in_the_paper(key):
    """Each paper value quotes the paper's own words (whitespace normalised), and its printed number
    stands in the quote (the decay time is derived: it quotes the numbers it comes from)."""
    text = _norm(PAPER_TXT.read_text(encoding="utf-8"))
    pv = PAPER[key]
    assert _norm(pv.quote) in text, f"{key}: quote not found in the paper: {pv.quote!r}"
    if pv.kind not in ("derived", "qualitative", "theory", "count"):
        assert pv.printed in pv.quote


def test_paper_values_are_well_formed():
    assert set(REQUIRED_KEYS) <= set(PAPER)
    for key, pv in PAPER.items():
        assert pv.key == key and pv.kind in KINDS and pv.where and pv.quote
        assert "page" not in pv.where.lower()  # the text has no page numbers: cite section/figure/equation
        if pv.numeric:
            assert math.isfinite(float(pv.value))
    with pytest.raises(ValueError, match="kind"):
        PaperValue("x", "1", None, "roughly", "Fig. 1", "q")


def test_paper_bounds_and_values_as_the_paper_states_them():
    """Fig. 5/6 captions: r = 0.82144 / 0.82145 >~ r2 (r2 is at most these); Fig. 7: r = 0.74001 <~ r1;
    Section 4: alpha1 ~ 1.24370; Fig. 9: alpha = 1.24500 >= alpha1; Eq. (14): <n> = 2272, kappa = 0.893 +- 0.001;
    Fig. 10: 0.010 +- 0.001 (n = 500), 0.003 +- 0.002 (n = 1000)."""
    assert (PAPER["r2"].kind, PAPER["r2"].value) == ("upper_bound", 0.82144)
    assert (PAPER["r2_fig6"].kind, PAPER["r2_fig6"].value) == ("upper_bound", 0.82145)
    assert (PAPER["r1"].kind, PAPER["r1"].value) == ("lower_bound", 0.74001)
    assert (PAPER["alpha1"].kind, PAPER["alpha1"].value) == ("approx", 1.2437)
    assert (PAPER["alpha1_fig9"].kind, PAPER["alpha1_fig9"].value) == ("upper_bound", 1.245)
    assert (PAPER["mean_n"].value, PAPER["mean_n"].error) == (2272.0, None)
    assert (PAPER["kappa"].value, PAPER["kappa"].error) == (0.893, 0.001)
    assert (PAPER["phi_500"].value, PAPER["phi_500"].error) == (0.010, 0.001)
    assert (PAPER["phi_1000"].value, PAPER["phi_1000"].error) == (0.003, 0.002)
    assert (PAPER["r2_impacts_per_period"].value, PAPER["alpha1_impacts_per_period"].value) == (6.0, 4.0)
    # a printed parameter is exact; a printed result is known to half a unit of its last digit
    assert PAPER["r2"].sigma == 0.0 and PAPER["alpha1"].sigma == pytest.approx(1e-5 / math.sqrt(12))


def test_sections_take_the_paper_numbers_from_paper_py():
    """No section types a number the paper states (they read validation/paper.py)."""
    import gear_rattle.validation.report as rep

    folder = Path(rep.__file__).parent
    printed = {pv.printed for pv in PAPER.values() if pv.kind in ("value", "approx", "upper_bound", "lower_bound")}
    printed |= {"2272", "0.893", "1.2437", "0.82144"}
    for src in sorted(folder.glob("sec_*.py")):
        code = "\n".join(line for line in src.read_text().splitlines() if not line.startswith("TITLE"))
        for p in printed:
            assert not re.search(rf"(?<![\d.]){re.escape(p)}(?!\d)", code), f"{src.name} types the paper's {p}"


def test_decay_time_error_propagates_the_rounding_of_mean_n_and_the_error_of_kappa():
    """Eq. (14): the paper's decay time <n>/kappa = 2272/0.893, error from the rounding of 2272
    (1/sqrt(12)) and kappa's +-0.001, about 0.1 %; no 2 % floor."""
    pt = PAPER["decay_time"]
    assert pt.value == pytest.approx(2272 / 0.893, rel=1e-9)
    expected = 2272 / 0.893 * math.hypot((1 / math.sqrt(12)) / 2272, 0.001 / 0.893)
    assert pt.error == pytest.approx(expected, rel=1e-9)
    assert 0.0009 < pt.error / pt.value < 0.0013
    # 2 % above the paper's value: would have agreed with a 2 % floor, disagrees now
    v = compare(pt.value * 1.02, 5.0, pt)
    assert v.verdict == DISAGREES and v.z > Z_AGREE


# ---------------------------------------------------------------------------------------- verdicts


def test_value_verdict_by_z_score_in_quadrature():
    pk = PAPER["kappa"]  # 0.893 +- 0.001
    v = compare_value(0.896, 0.001, pk)
    assert v.z == pytest.approx(0.003 / math.hypot(0.001, 0.001))
    assert v.verdict == DISAGREES and "z = +2.12" in v.text
    assert compare_value(0.8958, 0.001, pk).verdict == AGREES  # z = 1.98
    w = compare_value(0.8961, 0.001, pk)  # z = 2.19
    assert w.verdict == DISAGREES and f"z = {w.z:+.2f}" in w.text and w.deviation == pytest.approx(0.0031)
    # without our error bar the paper's error alone sets the scale
    assert compare_value(0.8935, None, pk).verdict == AGREES
    assert compare_value(0.8951, None, pk).verdict == DISAGREES


def test_intermittency_slope_six_sigma_from_minus_half_disagrees():
    """Type-I intermittency (Section 3): -0.552 +- 0.008 is 6.5 sigma from -1/2 and must not agree."""
    v = compare(-0.552, 0.008, PAPER["intermittency_slope"])
    assert v.verdict == DISAGREES and v.z == pytest.approx(-6.5)
    assert compare(-0.51, 0.008, PAPER["intermittency_slope"]).verdict == AGREES


def test_upper_bound_checked_strictly_against_the_printed_parameter():
    """Fig. 5: r = 0.82144 >~ r2.  An r2 4.5e-7 above 0.82144 violates it; Fig. 6's 0.82145 is satisfied."""
    r2 = 0.8214404475801397
    v = compare(r2, None, PAPER["r2"])
    assert v.verdict == DISAGREES and v.bound == "violated" and not v.proven
    assert v.deviation == pytest.approx(4.475801397e-7, rel=1e-6)
    assert "above 0.82144" in v.text and "<=" in v.text
    assert compare(r2, None, PAPER["r2_fig6"]).verdict == AGREES
    assert compare(r2, None, PAPER["r2_fig6"]).bound == "satisfied"
    assert compare(0.82144, None, PAPER["r2"]).verdict == AGREES  # equality is allowed by ">~"
    # our error bar does not soften the direction; a margin within it is said to be undecided by our accuracy
    w = compare_bound(1.24501, 1e-4, PAPER["alpha1_fig9"])
    assert w.verdict == DISAGREES and "not decided by our accuracy" in w.text
    assert compare_bound(1.2436, 5e-4, PAPER["alpha1_fig9"]).verdict == AGREES
    assert "not decided" not in compare_bound(1.2436, 1e-6, PAPER["alpha1_fig9"]).text


def test_bound_reports_its_margin_in_the_papers_last_digit_not_a_z_score():
    """Issue 23 item 13: the r2 row printed "24924395.9 sigma" (margin 4.5e-7 over a Newton residual of
    2e-14).  A bound prints its margin in absolute terms and in units of the paper's last printed digit
    (1e-05 for 0.82144), and has no z."""
    v = compare_bound(0.8214404475801397, 2e-14, PAPER["r2"])
    assert v.z is None and v.sigma is None and "sigma" not in v.text
    assert v.unit == 1e-05 == PAPER["r2"].printed_unit
    assert "4.48e-07 above 0.82144 (0.0448 × its last digit, 1e-05)" in v.text
    r1 = compare_bound(0.7414346, 2e-6, PAPER["r1"])
    assert r1.bound == "satisfied" and "0.00142 above 0.74001 (142 × its last digit, 1e-05); must be >= it" in r1.text
    assert PAPER["alpha1_fig9"].printed_unit == 1e-05 and PAPER["kappa"].printed_unit == 1e-03
    for key in ("decay_time", "fig2_motion", "r2_impacts_per_period", "intermittency_slope"):
        assert PAPER[key].printed_unit is None, key  # derived, a word, a count, a theory value


def test_bound_decided_by_an_enclosure_is_proven():
    """Issue 22 item 5 will pass a proven enclosure of r2: the whole enclosure on the bound's side of the
    printed decimal (compared exactly) proves it; wholly on the other side proves the violation; an
    enclosure that contains the printed value decides nothing (the point verdict stands, "not proven")."""
    r2 = 0.8214404475801397
    ok = compare(r2, 2e-14, PAPER["r2_fig6"], enclosure=(r2 - 1e-13, r2 + 1e-13))
    assert (ok.verdict, ok.bound, ok.proven) == (AGREES, "satisfied (proven)", True)
    assert "proven: our enclosure" in ok.text and "lies wholly below 0.82145" in ok.text
    bad = compare(r2, 2e-14, PAPER["r2"], enclosure=(r2 - 1e-13, r2 + 1e-13))
    assert (bad.verdict, bad.bound) == (DISAGREES, "violated (proven)") and "wholly above 0.82144" in bad.text
    # r1 is a lower bound: the enclosure must lie above 0.74001
    assert compare(0.7414, None, PAPER["r1"], enclosure=(0.7413, 0.7415)).bound == "satisfied (proven)"
    assert compare(0.7399, None, PAPER["r1"], enclosure=(0.7398, 0.74)).bound == "violated (proven)"
    # an enclosure containing the printed value: not proven, the point value decides
    und = compare(0.82143, None, PAPER["r2"], enclosure=(0.82142, 0.82146))
    assert (und.verdict, und.bound, und.proven) == (AGREES, "satisfied", False) and "not proven" in und.text
    # compared exactly with the printed decimal: the double nearest 0.82144 lies below it, the next one above
    x = float("0.82144")
    y = math.nextafter(x, 1.0)
    assert Fraction(x) < Fraction("0.82144") < Fraction(y)
    assert compare(x, None, PAPER["r2"], enclosure=(x, x)).bound == "satisfied (proven)"
    assert compare(y, None, PAPER["r2"], enclosure=(y, y)).bound == "violated (proven)"


@pytest.mark.parametrize(
    "enc, match",
    [
        ((0.9, 0.8), "lo <= hi"),
        ((0.1, 0.2), "contain the computed value"),
        ((float("nan"), 1.0), "finite"),
        ((1.0,), "pair"),
        ("ab", "real"),
    ],
)
def test_bad_enclosure_is_refused(enc, match):
    with pytest.raises(ValueError, match=match):
        compare(0.8214404475801397, None, PAPER["r2"], enclosure=enc)


def test_enclosure_only_for_bounds():
    with pytest.raises(ValueError, match="enclosure"):
        compare(0.9, 0.01, PAPER["kappa"], enclosure=(0.8, 1.0))
    with pytest.raises(ValueError, match="enclosure"):
        row("track_agreement", "t", 1e-13, paper=None, tolerance=1e-10, enclosure=(0, 1))


def test_lower_bound_checked_in_its_direction():
    """Fig. 7: r = 0.74001 <~ r1, so r1 must be above 0.74001."""
    assert compare(0.7414, 1e-5, PAPER["r1"]).verdict == AGREES
    v = compare(0.7399, 1e-5, PAPER["r1"])
    assert v.verdict == DISAGREES and v.bound == "violated" and "below 0.74001" in v.text and v.z is None
    with pytest.raises(ValueError, match="kind"):
        compare_bound(1.0, None, PAPER["kappa"])


def test_counts_and_categories_must_be_equal():
    assert compare(6, None, PAPER["r2_impacts_per_period"]).verdict == AGREES
    assert compare(3, None, PAPER["r2_impacts_per_period"]).verdict == DISAGREES
    assert compare(4.5, None, PAPER["alpha1_impacts_per_period"]).verdict == DISAGREES
    assert compare(-0.1, None, PAPER["fig2_motion"], category="regular").verdict == AGREES
    assert compare(0.3, None, PAPER["fig3_motion"], category="undetermined").verdict == DISAGREES
    with pytest.raises(ValueError, match="category"):
        compare(0.3, None, PAPER["fig3_motion"])


def test_internal_checks_are_not_compared_but_pass_or_fail():
    v = internal_check(3e-13, 1e-10)
    assert (v.verdict, v.check, v.text) == (NOT_COMPARED, "pass", "3e-13 <= tolerance 1e-10")
    f = internal_check(2e-10, 1e-10)
    assert (f.check, f.text) == ("fail", "2e-10 > tolerance 1e-10")
    assert internal_check(float("nan"), 1e-10).check == "fail"
    w = internal_check(1e-13, 1e-10, ok=False)
    assert w.check == "fail" and "further condition failed" in w.text
    assert compare(1.0, None, None).verdict == NOT_COMPARED and compare(1.0, None, None).check is None
    assert compare(None, None, None, tolerance=1e-10).check == "fail"
    # a paper value that was not computed is a disagreement, never a silent agreement
    assert compare(None, None, PAPER["alpha1"]).verdict == DISAGREES


def test_row_builds_a_judged_number():
    n = row("alpha1", "alpha1", 1.24363, 0.00053, paper="alpha1", explanation="e")
    assert n.verdict == AGREES and n.value == 1.24363 and n.error == 0.00053 and n.paper_value is PAPER["alpha1"]
    assert "z = " in n.deviation and "Section 4" in n.paper
    m = row("track_agreement", "tracks", 4e-13, paper=None, tolerance=1e-10)
    assert (m.verdict, m.check, m.paper) == (NOT_COMPARED, "pass", "(not in the paper)")
    with pytest.raises(ValueError, match="key"):
        row("bad key", "q", 1.0)


# ---------------------------------------------------------------------------------------- the report


@pytest.fixture
def fake_report(tmp_path, monkeypatch):
    return build_fake_report(tmp_path / "rep", monkeypatch)


def test_summary_json_has_stable_keys_with_numeric_value_and_error(fake_report):
    data = json.loads((fake_report / "summary.json").read_text())
    nums = {n["key"]: n for n in data["numbers"]}
    assert set(REQUIRED_KEYS) <= set(nums)
    for n in data["numbers"]:
        for f in (
            "key",
            "value",
            "error",
            "paper_value",
            "paper_error",
            "paper_kind",
            "verdict",
            "check",
            "z",
            "quantity",
            "paper",
            "computed",
            "error_bar",
            "deviation",
            "explanation",
            "section",
            "paper_digit",
            "bound",
            "margin_digits",
            "enclosure",
        ):
            assert f in n, (n["key"], f)
        for f in ("value", "error", "paper_error", "z", "deviation_value", "paper_digit", "margin_digits"):
            assert n[f] is None or (isinstance(n[f], (int, float)) and math.isfinite(n[f])), (n["key"], f)
    assert nums["r1"]["value"] == 0.74139 and nums["r1"]["error"] == 2e-5
    assert nums["r2"]["error"] == 2e-14 and nums["r2"]["verdict"] == DISAGREES
    assert nums["r2"]["paper_kind"] == "upper_bound" and nums["r2"]["paper_value"] == 0.82144
    # a bound: no z-score; its outcome, the margin in the paper's last digit and that digit
    assert (nums["r2"]["z"], nums["r2"]["bound"], nums["r2"]["paper_digit"]) == (None, "violated", 1e-05)
    assert nums["r2"]["margin_digits"] == pytest.approx(0.04475801397, rel=1e-6) and nums["r2"]["enclosure"] is None
    assert nums["r2_fig6"]["bound"] == "satisfied (proven)" and nums["r2_fig6"]["enclosure"] == [
        0.8214404475801,
        0.8214404475802,
    ]
    assert nums["kappa"]["bound"] is None and nums["kappa"]["paper_digit"] == 0.001
    assert nums["kappa"]["paper_error"] == 0.001 and nums["kappa"]["verdict"] == DISAGREES
    assert nums["phi_1000"]["value"] is None and nums["phi_1000"]["verdict"] == DISAGREES
    assert nums["fig2_motion"]["paper_value"] == "regular"
    assert nums["track_agreement"]["verdict"] == NOT_COMPARED and nums["track_agreement"]["check"] == "pass"
    assert nums["release_T_post"]["value"] == 1234 and nums["release_T_post"]["verdict"] == NOT_COMPARED
    assert data["counts"]["agrees"] + data["counts"]["disagrees"] + data["counts"]["not compared"] == len(nums)
    assert data["profile"] == "quick" and "environment" in data and data["sections"][0]["ok"]


def test_page_starts_with_counts_naming_disagreements_then_the_verdict_table(fake_report):
    """Issue 23 item 11: the counts (naming the rows that disagree), then a compact verdict table (key,
    paper, ours +- error, verdict, one-line reason), disagreements marked by a cross and capitals (not
    by colour alone), explanations in folded details below; the Markdown twin in the same order."""
    data = json.loads((fake_report / "summary.json").read_text())
    c = data["counts"]
    assert (c["agrees"], c["disagrees"], c["not compared"], c["check pass"]) == (7, 4, 2, 1)
    line = (
        "Verdicts: 7 agree, 4 disagree (r2, mean_n, kappa, phi_1000), 2 not compared (internal checks: 1 pass, 0 fail)."
    )
    html = (fake_report / "report.html").read_text()
    md = (fake_report / "report.md").read_text()
    # HTML: counts, then the verdict table before anything else of substance (provenance, sections)
    assert line in html
    table = re.search(r"<table class='verdicts'.*?</table>", html, flags=re.S).group(0)
    assert html.index(line) < html.index(table) < html.index("About this run") < html.index("Fake section (test)</h2>")
    assert html.index(table) < html.index("Environment:")
    head = re.findall(r"<th>(.*?)</th>", table)
    assert head == ["key", "paper", "ours ± error", "verdict", "reason"]
    rows = re.findall(r"<tr class='(\w+)'>(.*?)</tr>", table)
    assert len(rows) == len(data["numbers"])
    by_key = {re.search(r"#row-(\w+)", r).group(1): (cls, r) for cls, r in rows}
    for key in ("r2", "mean_n", "kappa", "phi_1000"):
        cls, r = by_key[key]
        assert cls == "bad" and ("✗ DISAGREES" in r or "✗ VIOLATED" in r), key
    assert "✓ satisfied (proven)" in by_key["r2_fig6"][1] and "✓ agrees" in by_key["alpha1"][1]
    assert "✓ check passes" in by_key["track_agreement"][1] and "– not compared" in by_key["release_T_post"][1]
    assert "0.8214404476 ± 2e-14<" in by_key["r2"][1] and "Newton residual" not in by_key["r2"][1]
    assert "0.0448 × its last digit" in by_key["r2"][1] and "sigma" not in table
    assert "1234 ± 0 (certified)" in by_key["release_T_post"][1]
    # the long explanations are not in the table but in the folded details, one per row, linked from the key
    assert "GOY law" not in table
    details = re.findall(r"<details id='row-(\w+)' class='(\w+)'>", html)
    assert [k for k, _ in details] == [n["key"] for n in data["numbers"]]
    assert html.count(html_escape(LONG)) == 2 and "<details open" not in html
    for href in re.findall(r"href='#([^']+)'", html):
        assert f"id='{href}'" in html
    # Markdown: the same order and the same columns, disagreements in bold with the cross
    assert line in md and md.index(line) < md.index("| key | paper | ours ± error | verdict | reason |")
    assert md.index("| key | paper") < md.index("## Details of each row") < md.index("## About this run")
    assert "| **✗ VIOLATED** |" in md and "| **✗ DISAGREES** |" in md and "| ✓ agrees |" in md
    headings = {md_slug(h) for h in re.findall(r"^#{2,3} (.+)$", md, flags=re.M)}
    links = re.findall(r"\]\(#([^)]+)\)", md)
    assert len(links) >= len(data["numbers"]) + 4 and set(links) <= headings
    assert "![a figure wider than the page](figures/fake.png)" in md
    assert md.count(LONG.strip()) == 2
    # a proven bound shows its enclosure in the details
    enc = "proven enclosure [0.8214404475801, 0.8214404475802]"
    assert enc in html and enc in md and enc not in table


def test_failed_section_is_counted_and_linked(tmp_path):
    ok = Section("a", "A: fine")
    bad = Section("b", "B: broken", ok=False, error="RuntimeError: x")
    doc = Document("t", [], [], [ok, bad])
    html = render_html(doc)
    md = render_markdown(doc, tmp_path)
    assert "1 section(s) FAILED" in html and "href='#sec-b'" in html and "id='sec-b'" in html
    assert f"(#{md_slug('B: broken — FAILED')})" in md and "## B: broken — FAILED" in md


def test_rerender_draws_the_same_report_from_document_json(fake_report):
    """document.json holds the model: rerender() from it rewrites report.html, report.md and summary.json
    byte for byte, without computing; a change of the rules applies on rerender."""
    files = {f: (fake_report / f).read_bytes() for f in ("report.html", "report.md", "summary.json", "document.json")}
    doc = json.loads(files["document.json"])
    assert doc["format"] == "gear-rattle report document 1" and doc["header"]["profile"] == "quick"
    spec = {r["key"]: r for r in doc["sections"][0]["rows"]}
    assert spec["r2_fig6"]["enclosure"] == [0.8214404475801, 0.8214404475802] and spec["r2"]["paper"] == "r2"
    assert doc["sections"][0]["blocks"][-1] == ["fig", "figures/fake.png", "a figure wider than the page"]
    builder.rerender(fake_report)
    # the same page, but for the note that it was drawn again (by which commit)
    commit = builder.git_commit()
    note = f"This page was drawn again from document.json by commit {commit}"
    for f in ("report.html", "report.md"):
        new = (fake_report / f).read_text(encoding="utf-8")
        assert note in new and note not in files[f].decode()
        assert re.sub(r"(<p>)?This page was drawn again[^\n]*\n(\n)?", "", new) == files[f].decode(), f
    s0, s1 = json.loads(files["summary.json"]), json.loads((fake_report / "summary.json").read_text())
    assert s1.pop("rerendered") == {"git_commit": commit} and s1 == s0
    # drawing again what was drawn again changes nothing
    files = {f: (fake_report / f).read_bytes() for f in files}
    builder.rerender(fake_report)
    for f, b in files.items():
        assert (fake_report / f).read_bytes() == b, f
    # a NaN value survives the JSON (as "nan") and is judged again as a NaN
    doc["sections"][0]["rows"][2]["value"] = "nan"
    (fake_report / "document.json").write_text(json.dumps(doc))
    builder.rerender(fake_report)
    r1 = {n["key"]: n for n in json.loads((fake_report / "summary.json").read_text())["numbers"]}["r1"]
    assert r1["verdict"] == DISAGREES and r1["deviation"] == "computed value is nan"


def test_rerender_command_refuses_bad_input_in_one_line(tmp_path):
    run = lambda *a: subprocess.run(  # noqa: E731
        [sys.executable, "-m", "gear_rattle.validation.report", *a],
        capture_output=True,
        text=True,
        timeout=120,
    )
    r = run("rerender", str(tmp_path))
    assert r.returncode == 2 and r.stdout == "" and r.stderr.count("\n") == 1 and "document.json" in r.stderr
    (tmp_path / "document.json").write_text('{"format": "something else"}')
    r = run("rerender", str(tmp_path))
    assert r.returncode == 2 and "format" in r.stderr and "Traceback" not in r.stderr


def test_md_slug_follows_github():
    assert (
        md_slug("Figs. 2-3: regular and chaotic rattling (time series)")
        == "figs-2-3-regular-and-chaotic-rattling-time-series"
    )
    assert md_slug("Summary: the paper's numbers beside ours") == "summary-the-papers-numbers-beside-ours"


def test_duplicate_summary_keys_are_refused():
    a, b = Section("a", "A"), Section("b", "B")
    a.numbers.append(row("kappa", "k", 0.9, 0.01, paper="kappa"))
    b.numbers.append(row("kappa", "k again", 0.9, 0.01, paper="kappa"))
    with pytest.raises(ValueError, match="kappa"):
        check_keys([a, b])


# ---------------------------------------------------------------------------------------- section helpers


def test_local_slopes_of_an_exact_power_law():
    """The local slopes the report lists for the laminar-length curve (Figs. 5-6, type-I intermittency)."""
    import numpy as np

    from gear_rattle.validation.dynamics.settling import local_slopes

    dr = np.logspace(-5, -3, 4)
    out = local_slopes(dr, 3.0 * dr**-0.5, 0.03 * dr**-0.5)
    assert [s for *_, s, _ in out] == pytest.approx([-0.5] * 3, abs=1e-12)
    assert all(e == pytest.approx(math.hypot(0.01, 0.01) / math.log(10 ** (2 / 3))) for *_, e in out)


def test_period_and_laminar_detection_on_synthetic_series():
    import numpy as np

    from gear_rattle.validation.dynamics.settling import laminar_in_series as _laminar_in_series
    from gear_rattle.validation.dynamics.settling import period_of as _period

    th = np.tile([0.1, 1.2, 2.3, 6.2], 60)
    sd = np.tile([0.5, -0.4, 0.3, -0.2], 60)
    assert _period(th, sd) == 4
    assert _period(th + np.linspace(0, 1e-3, th.size), sd) is None
    six = np.tile([1.0, -1.0, 0.5, -0.5, 0.2, -0.2], 40)
    burst = np.random.default_rng(0).uniform(-2, 2, 30)
    frac, n_ph, tail = _laminar_in_series(np.concatenate([six, burst, six]), 0.05)
    assert n_ph == 2 and tail is not None and 0.8 < frac < 1.0
    assert _laminar_in_series(np.concatenate([six, burst]), 0.05)[2] is None


# ------------------------------------------------------------------ the transient section (Figs. 9-11)


def test_transient_section_release_row_is_the_certified_T_post(tmp_path, monkeypatch):
    """Figs. 9-11 / Eq. (14), issue 10 item 3: the quick report's transient section (its experiments
    shrunk to small meshes here; the section's code is the real one) gives a ``release_T_post`` row
    whose value is what ``certified_release_duration`` returns for the decimal parameters (error 0,
    not compared with the paper, the float64-rounding value and the float64 sample in its text), and
    keeps the mean_n / kappa / decay_time rows, computed from durations in which every sticking orbit
    is first_stick + the certified T_post."""
    import numpy as np

    from gear_rattle.core.paper import PAPER_DECIMAL, PAPER_PARAMS
    from gear_rattle.mapimpl.certified import certified_release_duration
    from gear_rattle.mapimpl.engine.t_post import float64_target
    from gear_rattle.validation.report import sec_transients
    from gear_rattle.validation.transient import experiments as E

    # 32 x 8 basin points, 36 x (1 + 2 x 3) uncertainty orbits and a 16 x 16 transient mesh: 256 lanes,
    # a queue of 256 each, so one engine kernel compiled for the basins serves all three (the 128, 140
    # and 324 orbits of 16 x 8, 20 and 18 x 18 compiled it three times)
    small = {
        "basins": dict(nx=32, ny=8, ns=(90, 500)),
        "uncertainty": dict(n_points=36, eps=[1e-6, 1e-5, 1e-4], ns=(100, 500)),
        "transients": dict(nx=16, deltas=(1e-3,), n_boot=5),
        "stick_time_sensitivity": dict(stick_times=(1e-5,), n_boot=5),
        "float64_horizon": dict(n_side=3, impacts=400),
    }
    for name, kw in small.items():
        f = getattr(E, name)
        monkeypatch.setattr(E, name, lambda *a, _f=f, _kw=kw, **k: _f(*a, **{**k, **_kw}))
    ctx = builder.Context(profile="quick", out_dir=tmp_path, progress=False)
    sec = sec_transients.build(ctx)
    nums = {n.key: n for n in sec.numbers}
    assert {"mean_n", "kappa", "decay_time", "release_T_post"} <= set(nums)
    tg = float64_target(PAPER_PARAMS)
    dec = certified_release_duration(PAPER_DECIMAL, 0, 1e-3, confirm=False, target=tg)
    f64 = certified_release_duration(PAPER_DECIMAL, 0, 1e-3, rounding="float64", confirm=False, target=tg)
    r = nums["release_T_post"]
    assert r.value == dec.value and r.error == 0 and r.verdict == NOT_COMPARED
    assert "certified" in r.explanation and "ball arithmetic" in r.explanation
    assert f"T_post = {f64.value}" in r.explanation and "sample" in r.explanation
    z = np.load(tmp_path / "data" / "transients" / "transients.npz")
    c = z["composed"] & (z["stick_wall"] == 0)
    assert c.sum() >= 5
    assert np.array_equal(z["hit"][..., 0][c], z["first_stick"][c] + dec.value)
    d = z["hit"][..., 0].ravel()
    assert nums["mean_n"].value == pytest.approx(np.where(d < 0, int(z["cap"]), d).mean(), rel=1e-12)
    # every file the section wrote is strict JSON (issue 23 item 8) and the CSVs hold numbers only
    files = sorted((tmp_path / "data").rglob("*.json"))
    assert len(files) == 5
    for f in files:
        json.loads(f.read_text(), parse_constant=lambda c: pytest.fail(f"{f.name}: {c} in JSON"))
    for f in (tmp_path / "data").rglob("*.csv"):
        header, *rows = f.read_text().splitlines()
        assert header[0].isidentifier() and all(isinstance(float(x), float) for r in rows for x in r.split(",")), f
