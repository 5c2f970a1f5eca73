"""`gear-rattle check` in another project's CI (issue 30; docs/reference/golden_commands.md, "In CI", and
docs/reference/golden_formats.md, "Versions of the suite"): the JUnit XML and JSON reports, the aligned
table and the summary, the suite's version and digest against docs/record/golden_changelog.md, the light
install (numpy alone) and the CI jobs of docs/howto/golden_ci_jobs.md, run.

The JUnit file is validated structurally against the JUnit schema that Jenkins (``junit-10.xsd``),
Surefire and GitLab read -- no network and no schema library: :func:`validate_junit` checks the
element tree, the attributes each element must have, their types, and that the counts agree with the
children.  Sample outputs are the suite's own expected values (.ci/golden_sample.py); no JAX runs here.
"""

from __future__ import annotations

import importlib.util
import json
import math
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from gear_rattle.validation.cli import main
from gear_rattle.validation.golden.formats import version as V
from gear_rattle.validation.golden.paths import GOLDEN

REPO = Path(__file__).resolve().parents[1]
#: the suite's changelog, and the page of the CI jobs
CHANGELOG = REPO / "docs" / "record" / "golden_changelog.md"
JOBS = REPO / "docs" / "howto" / "golden_ci_jobs.md"
CASES = sorted(p.name for p in (GOLDEN / "cases").iterdir() if (p / "settings.json").is_file())
RECORDS = sorted(p.stem for p in (GOLDEN / "orbits").glob("*.json"))

_spec = importlib.util.spec_from_file_location("golden_sample", REPO / ".ci" / "golden_sample.py")
golden_sample = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(golden_sample)


# ------------------------------------------------------------------------------------------ JUnit


def _number(el, attr, kind=float):
    v = el.get(attr)
    assert v is not None, f"<{el.tag}> lacks the attribute {attr!r}"
    x = kind(v)
    assert x >= 0 and (kind is int or math.isfinite(x)), (el.tag, attr, v)
    return x


def validate_junit(path: Path) -> ET.Element:
    """The JUnit XML schema's structure (``junit-10.xsd``: testsuites > testsuite > properties, testcase >
    failure|error|skipped), checked element by element: required attributes present and typed, only
    the schema's elements, at most one result per testcase, the counts (skipped included) equal to the
    children.  Returns the root."""
    root = ET.parse(path).getroot()
    suites = [root] if root.tag == "testsuite" else list(root)
    assert root.tag in ("testsuites", "testsuite")
    totals = {"tests": 0, "failures": 0, "errors": 0}
    for ts in suites:
        assert ts.tag == "testsuite" and ts.get("name")
        n = {a: _number(ts, a, int) for a in ("tests", "failures", "errors", "skipped")}
        _number(ts, "time")
        cases, fails, errors, skips = 0, 0, 0, 0
        for child in ts:
            assert child.tag in ("properties", "testcase", "system-out", "system-err"), child.tag
            if child.tag == "properties":
                for prop in child:
                    assert prop.tag == "property" and prop.get("name") and prop.get("value") is not None
                    assert set(prop.attrib) == {"name", "value"}
            elif child.tag == "testcase":
                cases += 1
                assert child.get("name") and child.get("classname")
                _number(child, "time")
                for res in child:
                    assert res.tag in ("failure", "error", "skipped", "system-out", "system-err"), res.tag
                    if res.tag in ("failure", "error"):
                        assert res.get("message") and res.get("type"), res.attrib
                assert sum(r.tag in ("failure", "error", "skipped") for r in child) <= 1, child.attrib
                fails += sum(r.tag == "failure" for r in child)
                errors += sum(r.tag == "error" for r in child)
                skips += sum(r.tag == "skipped" for r in child)
                if child.get("line") is not None:  # the output file's line of the first failure
                    assert child.get("file") and int(child.get("line")) >= 1, child.attrib
        assert (n["tests"], n["failures"], n["errors"], n["skipped"]) == (cases, fails, errors, skips)
        for k in totals:
            totals[k] += n[k]
    if root.tag == "testsuites":
        for k, v in totals.items():
            assert int(root.get(k, v)) == v, (k, root.get(k), v)
    return root


def _strict_json(path: Path) -> dict:
    def refuse(name):
        raise AssertionError(f"{name} in strict JSON")

    return json.loads(path.read_text(encoding="utf-8"), parse_constant=refuse)


def _props(root) -> dict:
    return {p.get("name"): p.get("value") for p in root.iter("property")}


def test_a_malformed_output_is_an_error_of_its_case_only(tmp_path, capsys):
    """A malformed file is one line on stderr and an <error> of its case alone: every other case is
    scored as usual (before: all 25 "not scored", exit 2); exit 1, the reports written."""
    out, _ = golden_sample.write_sample(GOLDEN, tmp_path / "out")
    bad = "0002-chaotic-fig3"
    f = out / f"{bad}.csv"
    lines = f.read_text().splitlines()
    f.write_text("\n".join([lines[0] + ",tau"] + [ln + ",0" for ln in lines[1:]]) + "\n")  # tau twice
    junit, js = tmp_path / "golden.xml", tmp_path / "golden.json"
    assert main(["check", str(out), "--junit-xml", str(junit), "--json", str(js)]) == 1
    cap = capsys.readouterr()
    assert len(cap.err.strip().splitlines()) == 1 and bad in cap.err
    assert cap.out.splitlines()[-1].endswith(f"; errors: {bad}") and f"{len(CASES) - 1}/{len(CASES)}" in cap.out
    root = validate_junit(junit)
    errors = [t for t in root.iter("testcase") if t.find("error") is not None]
    assert [t.get("name") for t in errors] == [bad] and int(root.get("errors")) == 1
    assert errors[0].get("file") == str(f) and errors[0].get("line") == "1"
    assert errors[0].find("error").get("type") == "golden.malformed"
    doc = _strict_json(js)
    assert (doc["errors"], doc["passed"], doc["failed"]) == (1, len(CASES) - 1, 0)
    res = {r["id"]: r for r in doc["results"]}
    assert res[bad]["verdict"] == "error" and "tau" in res[bad]["note"]
    ff = res[bad]["first_failing"]
    assert (ff["kind"], ff["file"], ff["line"], ff["column"]) == ("malformed", str(f), 1, len(lines[0]) + 2)
    assert all(r["verdict"] == "pass" for k, r in res.items() if k != bad)


def test_junit_and_json_of_the_impact_cases(tmp_path, capsys):
    broken = "0007-chatter-sticking"
    out, _ = golden_sample.write_sample(GOLDEN, tmp_path / "out", broken)
    junit, js = tmp_path / "r" / "golden.xml", tmp_path / "r" / "golden.json"
    assert main(["check", str(out), "--junit-xml", str(junit), "--json", str(js)]) == 1
    text = capsys.readouterr().out
    root = validate_junit(junit)
    recorded = V.recorded()
    props = _props(root)
    assert props["suite.version"] == recorded["version"] == V.SUITE_VERSION
    assert props["suite.digest"] == recorded["cases_digest"] and props["suite.digest_matches"] == "true"
    tcs = list(root.iter("testcase"))
    assert [t.get("name") for t in tcs] == CASES
    failed = [t for t in tcs if t.find("failure") is not None]
    assert [t.get("name") for t in failed] == [broken]
    f = failed[0].find("failure")
    assert "first failing: tau at line 2" in f.get("message") and f.get("type") == "golden.value"
    assert (failed[0].get("file"), failed[0].get("line")) == (str(out / f"{broken}.csv"), "2")
    assert "tau: expected " in f.text and "<- tau" in f.text  # expected against got, and the rows around
    doc = _strict_json(js)
    assert doc["suite"]["version"] == V.SUITE_VERSION and doc["suite"]["digest"] == recorded["cases_digest"]
    assert (doc["tests"], doc["passed"], doc["failed"]) == (len(CASES), len(CASES) - 1, 1)
    res = {r["id"]: r for r in doc["results"]}
    bad = res[broken]
    assert bad["passed"] is False and bad["level"] == 2
    ff = bad["first_failing"]
    assert (ff["kind"], ff["line"], ff["golden_line"], ff["column"]) == ("value", 2, 2, "tau")
    assert ff["actual"]["tau"] - ff["expected"]["tau"] == pytest.approx(0.5)
    assert ff["error"] == pytest.approx(0.5) and ff["over_tolerance"] == pytest.approx(0.5 / ff["tolerance"])
    assert bad["verdict"] == "fail" and bad["event_difference"] is None
    assert bad["worst_over_tolerance"] > 1e6 and bad["digits"]["tau"] < 3
    good = res["0001-regular-fig2"]
    assert good["passed"] and good["first_failing"] is None and good["level"] == 1
    assert 0 <= good["worst_over_tolerance"] < 1 and set(good["digits"]) == {"tau", "tau_mod_2pi", "sdot"}
    # the header names the suite, the summary the failing case
    assert text.startswith(f"suite: {V.SUITE_NAME} {V.SUITE_VERSION}: cases ")
    assert text.splitlines()[-1].endswith(f"; failing: {broken}")


def test_junit_and_json_of_the_orbit_records(tmp_path, capsys):
    broken = "fold-r2-6-impact-alpha3"
    _, orbits = golden_sample.write_sample(GOLDEN, tmp_path / "out", broken)
    junit, js = tmp_path / "o.xml", tmp_path / "o.json"
    assert main(["check", "--orbits", str(orbits), "--junit-xml", str(junit), "--json", str(js), "--summary"]) == 1
    assert capsys.readouterr().out.startswith(f"{len(RECORDS) - 1}/{len(RECORDS)} orbits")
    root = validate_junit(junit)
    assert _props(root)["suite.digest"] == V.recorded()["orbits_digest"]
    assert [t.get("name") for t in root.iter("testcase") if t.find("failure") is not None] == [broken]
    doc = _strict_json(js)
    res = {r["id"]: r for r in doc["results"]}
    ff = res[broken]["first_failing"]
    assert doc["scored"] == "orbits" and (ff["kind"], ff["column"], ff["file"]) == (
        "value",
        "value",
        str(orbits / f"{broken}.json"),
    )
    lo, hi = ff["expected"]
    assert ff["actual"] - hi == pytest.approx(0.5, rel=1e-6) and ff["line"] == 1
    assert res[broken]["worst_over_tolerance"] > 1e9 and res[broken]["digits"]["value"] < 2
    assert all(r["passed"] and r["worst_over_tolerance"] < 1 for k, r in res.items() if k != broken)


def test_the_table_aligns_for_long_ids_and_the_summary_names_the_failures(tmp_path, capsys):
    """Columns misaligned for ids longer than 30 characters (a fixed width): now as wide as the widest."""
    suite = tmp_path / "suite"
    long_id = "0001-regular-fig2-" + "with-a-much-longer-identifier-" * 2
    for cid in ("0001-regular-fig2", "0003-free-flight-start"):
        shutil.copytree(GOLDEN / "cases" / cid, suite / (long_id if cid.startswith("0001") else cid))
    s = json.loads((suite / long_id / "settings.json").read_text())
    s["id"] = long_id
    (suite / long_id / "settings.json").write_text(json.dumps(s))
    out = tmp_path / "out"
    out.mkdir()
    shutil.copy(suite / long_id / "expected.csv", out / f"{long_id}.csv")
    golden_sample.write_sample(GOLDEN, tmp_path / "x", "0003-free-flight-start")
    shutil.copy(tmp_path / "x" / "0003-free-flight-start.csv", out)
    assert main(["check", str(out), "--suite", str(suite)]) == 1
    lines = capsys.readouterr().out.splitlines()
    # case folders without an index.json: no version is claimed for them (not the shipped suite's)
    assert "suite without a recorded version unversioned" in lines[0] and "no index.json" in lines[0]
    head, rows = lines[1], lines[3:5]
    assert len(rows) == 2
    for word, right in (("result", False), ("tau", True), ("tau%2pi", True), ("sdot", True), ("n/wall/kind", False)):
        k = re.search(rf"(?<!\S){re.escape(word)}(?!\S)", head)
        for r in rows:  # a cell starts (left-aligned) or ends (right-aligned) where the header's word does
            if right:
                assert r[k.end() - 1] != " " and r[k.end()] == " ", (word, r)
            else:
                assert r[k.start() - 1] == " " and r[k.start()] != " ", (word, r)
    assert lines[-1].startswith("1/2 cases pass") and lines[-1].endswith("; failing: 0003-free-flight-start")


# ------------------------------------------------------------------------------ version and digest


def test_the_suite_files_the_digest_the_version_and_the_changelog_change_together():
    """Recompute the digests: they must be those recorded in cases/index.json, and the suite's changelog
    (docs/record/golden_changelog.md) must have an entry for the recorded version naming that digest -- so a change of any case or
    record file fails here until the index is regenerated, the version raised and its entry written."""
    block = V.recorded()
    files = V.suite_files(GOLDEN / "cases")
    assert len(files) == 3 * len(CASES) and "index.json" not in files  # settings, expected, provenance
    assert len(V.suite_files(GOLDEN / "orbits")) == len(RECORDS)
    cases, orbits = V.folder_digest(GOLDEN / "cases"), V.folder_digest(GOLDEN / "orbits")
    assert block["cases_digest"] == cases, "a case file changed: raise SUITE_VERSION, regenerate cases/index.json"
    assert block["orbits_digest"] == orbits, "an orbit record changed: raise SUITE_VERSION, regenerate the index"
    assert block["digest"] == V.combined_digest(cases, orbits)
    assert block["version"] == V.SUITE_VERSION and re.fullmatch(r"\d+\.\d+\.\d+", V.SUITE_VERSION)
    log = CHANGELOG.read_text(encoding="utf-8")
    entry = re.search(rf"^\* \*\*{re.escape(V.SUITE_VERSION)}\*\* .*?(?=^\* \*\*|\Z)", log, re.S | re.M)
    assert entry, f"{CHANGELOG.relative_to(REPO)}: no entry for suite {V.SUITE_VERSION}"
    assert block["digest"] in " ".join(entry.group(0).split()), "the changelog entry does not name the digest"
    versions = re.findall(r"^\* \*\*(\d+\.\d+\.\d+)\*\*", log, re.M)
    assert versions[0] == V.SUITE_VERSION and len(set(versions)) == len(versions)  # newest first, each once


def test_the_digest_sees_every_byte_and_the_order_is_canonical(tmp_path):
    d = tmp_path / "cases"
    shutil.copytree(GOLDEN / "cases", d)
    assert V.folder_digest(d) == V.recorded()["cases_digest"]
    (d / "README.txt").write_text("not a suite file")  # neither *.json nor *.csv: not part of the digest
    (d / "index.json").write_text("{}")
    assert V.folder_digest(d) == V.recorded()["cases_digest"]
    f = d / CASES[-1] / "expected.csv"
    f.write_bytes(f.read_bytes() + b"\n")
    assert V.folder_digest(d) != V.recorded()["cases_digest"]


def test_suite_version_and_require_suite(tmp_path, capsys):
    assert main(["check", "--suite-version"]) == 0
    out = capsys.readouterr().out
    assert out.count(f"{V.SUITE_NAME} {V.SUITE_VERSION}:") == 2 and V.recorded()["digest"] in out
    copy = tmp_path / "cases"
    shutil.copytree(GOLDEN / "cases", copy)
    assert main(["check", "--suite-version", "--suite", str(copy)]) == 0
    assert "matches the digest recorded" in capsys.readouterr().out
    (copy / CASES[0] / "settings.json").write_text((copy / CASES[0] / "settings.json").read_text() + " ")
    assert main(["check", "--suite-version", "--suite", str(copy)]) == 1
    assert "DIFFERS from the digest recorded for" in capsys.readouterr().out
    out_dir, _ = golden_sample.write_sample(GOLDEN, tmp_path / "out")
    assert main(["check", str(out_dir), "--suite", str(copy), "--require-suite", V.SUITE_VERSION]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"--require-suite {V.SUITE_VERSION}: the suite is {V.SUITE_VERSION}+modified" in err[0]
    assert main(["check", str(out_dir), "--require-suite", "0.7.0", "--summary"]) == 2
    assert main(["check", str(out_dir), "--require-suite", V.SUITE_VERSION, "--summary"]) == 0
    capsys.readouterr()


# ----------------------------------------------------------------------------------- light install

#: What the full install adds to numpy: blocked (``sys.modules[name] = None``) as if never installed.
HEAVY = ("jax", "jaxlib", "scipy", "diffrax", "optimistix", "equinox", "matplotlib", "flint", "tqdm")


def _light_python(code: str, cwd) -> subprocess.CompletedProcess:
    prelude = f"import sys\nfor _m in {HEAVY!r}:\n    sys.modules[_m] = None\n"
    return subprocess.run(
        [sys.executable, "-c", prelude + code],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=300,
        env={**os.environ, "JAX_PLATFORMS": "cpu"},
    )


def test_the_light_install_scores_and_the_other_commands_say_what_to_install(tmp_path):
    """With numpy alone: --version, check PATH, check --orbits PATH and check --suite-version work and
    import no heavy package; every other command is one line naming the packages, exit 2."""
    out, orbits = golden_sample.write_sample(GOLDEN, tmp_path / "out")
    light = [
        ["--version"],
        ["check", str(out), "--summary"],
        ["check", "--orbits", str(orbits), "--summary"],
        ["check", "--suite-version"],
        ["check", str(out), "--json", "-"],
        ["check", "--suite-version", "--json", "-"],
        ["check", "--export-suite", str(tmp_path / "exported")],
    ]
    heavy = [
        ["simulate"],
        ["report", "--profile", "quick"],
        ["atlas", "--help"],
        ["check", "--self"],
        ["lyapunov"],
        ["transients"],
    ]
    code = (
        "import contextlib, io, json\nfrom gear_rattle.validation.cli import main\nres = []\n"
        f"for argv in {light + heavy!r}:\n"
        "    o, e = io.StringIO(), io.StringIO()\n"
        "    with contextlib.redirect_stdout(o), contextlib.redirect_stderr(e):\n"
        "        try:\n            rc = main(argv)\n        except SystemExit as x:\n            rc = x.code\n"
        "    res.append([rc, o.getvalue(), e.getvalue()])\n"
        "import gear_rattle\n"
        "res.append(sorted(m for m, mod in sys.modules.items() if mod is not None and m.split('.')[0] in "
        "('jax', 'scipy', 'matplotlib')))\n"
        "print(json.dumps(res))\n"
    )
    p = _light_python(code, tmp_path)
    assert p.returncode == 0, p.stderr[-3000:]
    *res, loaded = json.loads(p.stdout.splitlines()[-1])
    assert loaded == []
    for argv, (rc, _o, e) in zip(light, res[: len(light)]):
        assert rc == 0 and e == "", (argv, rc, e)
    assert res[0][1].strip() == f"gear-rattle {__import__('gear_rattle').__version__} (golden suite {V.SUITE_VERSION})"
    assert json.loads(res[4][1])["passed"] == len(CASES)
    assert json.loads(res[5][1])["cases"]["ids"] == CASES and (tmp_path / "exported" / "FORMAT.md").is_file()
    for argv, (rc, o, e) in zip(heavy, res[len(light) :]):
        assert rc == 2 and o == "" and e.count("\n") == 1 and "Traceback" not in e, (argv, rc, e)
        assert e.startswith(f"gear-rattle {argv[0]}: error: this command needs jax") and "pip install gear-rattle" in e


def test_import_gear_rattle_does_not_import_jax_and_jax_still_computes_in_float64(tmp_path):
    code = (
        "import gear_rattle, sys\nassert 'jax' not in sys.modules, 'import gear_rattle imported JAX'\n"
        "from gear_rattle.mapimpl import flight\nimport jax.numpy as jnp\n"
        "print(jnp.zeros(2).dtype, gear_rattle.Params(3.0, 0.1, 0.1, 0.9).arrays().alpha.dtype)\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "JAX_ENABLE_X64"}
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path, env=env, timeout=300)
    assert p.returncode == 0, p.stderr[-2000:]
    assert p.stdout.split() == ["float64", "float64"]


# ------------------------------------------------------------------------------ the CI jobs of the docs


def _ci_section() -> str:
    return JOBS.read_text(encoding="utf-8")


def ci_jobs() -> dict:
    """The commands of the two YAML jobs of docs/howto/golden_ci_jobs.md, in order (GitHub's ``run:`` steps, GitLab's
    ``script:`` items), and the variables each declares (GitHub's ``env:``, GitLab's ``variables:``)."""
    blocks = re.findall(r"```yaml\n(.*?)```", _ci_section(), re.S)
    assert len(blocks) == 2, f"{JOBS.relative_to(REPO)}: expected a GitHub Actions and a GitLab CI job"
    github = [m.strip() for m in re.findall(r"^\s+- run: (.+)$", blocks[0], re.M)]
    script = blocks[1].split("  script:\n", 1)[1]
    gitlab = [m.strip() for m in re.findall(r"^    - (.+)$", script.split("\n  artifacts:", 1)[0], re.M)]

    def variables(text: str, key: str) -> dict:
        body = re.search(rf"^( +){key}:\n((?:\1  .*\n)+)", text, re.M)
        assert body, f"{JOBS.relative_to(REPO)}: a job without {key}:"
        return dict(re.findall(r'^\s+(\w+): "([^"]*)"$', body.group(2), re.M))

    return {
        "github": github,
        "gitlab": gitlab,
        "_yaml": blocks,
        "_vars": {"github": variables(blocks[0], "env"), "gitlab": variables(blocks[1], "variables")},
    }


def test_the_ci_job_definitions_parse_and_hold_the_same_commands():
    jobs = ci_jobs()
    assert jobs["github"] == jobs["gitlab"] and len(jobs["github"]) == 7
    assert jobs["_vars"]["github"] == jobs["_vars"]["gitlab"] and set(jobs["_vars"]["github"]) == {
        "GOLDEN_LEVELS",
        "GOLDEN_ORBITS",
    }
    yaml = pytest.importorskip("yaml")  # where PyYAML is installed: the blocks are valid YAML, read as above
    gh, gl = (yaml.safe_load(b) for b in jobs["_yaml"])
    steps = gh["jobs"]["golden-suite"]["steps"]
    assert [s["run"] for s in steps if "run" in s] == jobs["github"]
    assert gh["jobs"]["golden-suite"]["env"] == jobs["_vars"]["github"]
    assert gl["golden-suite"]["script"] == jobs["gitlab"]
    assert gl["golden-suite"]["variables"] == jobs["_vars"]["gitlab"]
    assert gl["golden-suite"]["artifacts"]["reports"]["junit"] == "golden*.xml"


def run_ci_job(tmp_path: Path, job: str, levels: str, orbits: str, sample: str) -> tuple:
    """Run one documented job's commands, in order, with bash (``set -eu``: it stops at the first failing
    step, as CI does), the install line replaced by this environment, ``./my-implementation`` by
    .ci/golden_sample.py with the flags ``sample``, the job's two variables set to ``levels`` and
    ``orbits`` (what a user edits).  Returns ``(process, working directory)``."""
    jobs = ci_jobs()
    cmds, declared = jobs[job], jobs["_vars"][job]
    install = [c for c in cmds if c.startswith("pip install")]
    assert len(install) == 1 and "--no-deps" in install[0] and "numpy" in install[0]
    impl = [c for c in cmds if c.startswith("./my-implementation ")]
    assert len(impl) == 1
    program = f'"{sys.executable}" "{REPO / ".ci" / "golden_sample.py"}" {sample}'
    script = ["set -eu", f'gear-rattle() {{ "{sys.executable}" -m gear_rattle "$@"; }}']
    script += [c.replace("./my-implementation", program, 1) for c in cmds if c not in install]
    wd = tmp_path / f"{job}-{levels}-{orbits}-{abs(hash(sample)) % 10**6}"
    wd.mkdir()
    env = {**os.environ, **declared, "GOLDEN_LEVELS": levels, "GOLDEN_ORBITS": orbits}
    p = subprocess.run(["bash", "-c", "\n".join(script)], cwd=wd, capture_output=True, text=True, env=env, timeout=600)
    return p, wd


def _level_of() -> dict:
    return {c: json.loads((GOLDEN / "cases" / c / "settings.json").read_text())["level"] for c in CASES}


def _verdicts(wd: Path, name: str) -> dict:
    """``{id: (JUnit result tag or 'pass', JSON verdict)}`` of a run's reports; the JUnit file is
    validated and its counts compared with the JSON's."""
    root = validate_junit(wd / f"{name}.xml")
    doc = _strict_json(wd / f"{name}.json")
    ts = root.find("testsuite")
    assert int(ts.get("tests")) == doc["tests"] and int(ts.get("errors")) == doc["errors"]
    assert int(ts.get("failures")) == doc["failed"] + doc["xpassed"]
    assert int(ts.get("skipped")) == doc["skipped"] + doc["xfailed"]
    assert sum(doc[k] for k in ("passed", "failed", "errors", "skipped", "xfailed", "xpassed")) == doc["tests"]
    tags = {t.get("name"): (t[0].tag if len(t) else "pass") for t in ts.iter("testcase")}
    return {r["id"]: (tags[r["id"]], r["verdict"]) for r in doc["results"]}


@pytest.mark.parametrize("job", ["github", "gitlab"])
@pytest.mark.parametrize("levels, orbits", [("1", "no"), ("1,2", "no"), ("1,2", "yes")])
def test_the_ci_jobs_of_the_docs_pass_a_correct_implementation(tmp_path, job, levels, orbits):
    """As copied, for an implementation of level 1 only, of levels 1-2, and with the orbit records: a
    correct one passes, the cases of other levels <skipped>; the orbit step does nothing without the
    records (before: 'out-orbits not found', exit 2)."""
    flags = f"--levels {levels}" + ("" if orbits == "yes" else " --no-orbits")
    p, wd = run_ci_job(tmp_path, job, levels, orbits, flags)
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    assert p.stdout.startswith(f"gear-rattle {__import__('gear_rattle').__version__} (golden suite ")
    wanted = {int(x) for x in levels.split(",")}
    got = _verdicts(wd, "golden")
    assert got == {c: (("pass", "pass") if lv in wanted else ("skipped", "skipped")) for c, lv in _level_of().items()}
    assert (wd / "golden-orbits.xml").exists() == (orbits == "yes")
    if orbits == "yes":
        assert set(_verdicts(wd, "golden-orbits").values()) == {("pass", "pass")}
    assert json.loads((wd / "golden-suite" / "suite.json").read_text())["cases"]["folder"] == "cases"


#: Faulty samples: flags, and the verdicts expected of the cases that are not plain passes.
BROKEN, MALFORMED, DROPPED = "0002-chaotic-fig3", "0007-chatter-sticking", "0012-release-orbit-fig11"


@pytest.mark.parametrize(
    "fault",
    ["wrong", "malformed", "missing-file", "crash-midway", "crash-at-start", "crash-after-writing", "wrong-orbit"],
)
def test_the_ci_job_fails_each_faulty_implementation_with_reports(tmp_path, fault):
    """The GitHub job (its commands are GitLab's, checked above) on faulty samples of levels 1-2 with the
    orbit records: exit status 1, the JUnit report and the JSON naming what failed and how."""
    level = _level_of()
    l12 = [c for c in CASES if level[c] in (1, 2)]
    flags = {
        "wrong": f"--break {BROKEN}",
        "malformed": f"--malformed {MALFORMED}",
        "missing-file": f"--drop {DROPPED}",
        "crash-midway": "--crash-after 5",
        "crash-at-start": "--crash-after 0",
        "crash-after-writing": "--crash-after 99",
        "wrong-orbit": f"--break {RECORDS[0]}",
    }[fault]
    p, wd = run_ci_job(tmp_path, "github", "1,2", "yes", f"--levels 1,2 {flags}")
    assert p.returncode == 1, p.stdout[-3000:] + p.stderr[-3000:]
    got = _verdicts(wd, "golden")
    odd = {c: v for c, v in got.items() if v != ("pass", "pass") and level[c] in (1, 2)}
    assert all(got[c] == ("skipped", "skipped") for c in CASES if level[c] == 3)
    root = ET.parse(wd / "golden.xml").getroot()
    tc = {t.get("name"): t for t in root.iter("testcase")}
    if fault == "wrong":
        assert odd == {BROKEN: ("failure", "fail")}
        assert tc[BROKEN].find("failure").get("type") == "golden.value"
        assert tc[BROKEN].get("file") == f"out/{BROKEN}.csv" and tc[BROKEN].get("line") == "2"
        assert "expected" in tc[BROKEN].find("failure").text and "<- tau" in tc[BROKEN].find("failure").text
    elif fault == "malformed":
        assert odd == {MALFORMED: ("error", "error")} and MALFORMED in p.stderr
    elif fault == "missing-file":
        assert odd == {DROPPED: ("failure", "fail")}
        assert tc[DROPPED].find("failure").get("type") == "golden.no-output"
    elif fault in ("crash-midway", "crash-at-start"):
        written = 5 if fault == "crash-midway" else 0
        assert odd == {c: ("failure", "fail") for c in l12[written:]}
        assert {tc[c].find("failure").get("type") for c in odd} == {"golden.no-output"}
        if written == 0:  # no output folder at all: one line on stderr, the reports still written
            assert "PATH='out' not found" in p.stderr
    elif fault == "crash-after-writing":  # every file right, the program's own status fails the job
        assert odd == {} and set(_verdicts(wd, "golden-orbits").values()) == {("pass", "pass")}
        assert "my-implementation exited with status 101" in p.stdout
    else:
        assert odd == {}
        orbit = _verdicts(wd, "golden-orbits")
        assert {k: v for k, v in orbit.items() if v != ("pass", "pass")} == {RECORDS[0]: ("failure", "fail")}
    if fault not in ("crash-after-writing", "wrong-orbit"):
        assert not (wd / "golden-orbits.xml").exists()  # the job stops at its first failing step


def test_ci_runs_the_light_install_on_the_built_wheel():
    """.ci/run installs the wheel with --no-deps and numpy alone in a fresh venv and scores a sample directory."""
    ci = (REPO / ".ci" / "run").read_text()
    stage = ci.split('stage "light install', 1)[1].split("\nstage ", 1)[0]
    assert '-m venv "$W/light"' in stage and '--no-deps "$(ls "$W"/dist/gear_rattle-*.whl)" numpy' in stage
    for cmd in (
        "gear-rattle --version",
        "gear-rattle check --suite-version",
        "gear-rattle check --suite-version --json light-suite.json",
        "gear-rattle check --export-suite light-suite",
        '.ci/golden_sample.py" light-suite light-out --levels 1,2',
        "gear-rattle check light-out --level 1,2 --junit-xml",
        "gear-rattle check --orbits light-out-orbits",
        "gear-rattle check no-such-out --junit-xml light-missing.xml",
    ):
        assert cmd in stage, cmd
