"""`gear-rattle check` in another project's CI (issue 30; docs/golden.md, "Using the suite in CI" and
"Versions of the suite"): the JUnit XML and JSON reports, the aligned table and the summary, the suite's
version and digest, the light install (numpy alone) and the CI jobs of docs/golden.md, run.

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
from gear_rattle.validation.golden import version as V

REPO = Path(__file__).resolve().parents[1]
GOLDEN = V.GOLDEN
DOC = REPO / "docs" / "golden.md"
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
    the schema's elements, counts equal to the children.  Returns the root."""
    root = ET.parse(path).getroot()
    suites = [root] if root.tag == "testsuite" else list(root)
    assert root.tag in ("testsuites", "testsuite")
    totals = {"tests": 0, "failures": 0, "errors": 0}
    for ts in suites:
        assert ts.tag == "testsuite" and ts.get("name")
        n = {a: _number(ts, a, int) for a in ("tests", "failures", "errors")}
        _number(ts, "time")
        cases, fails, errors = 0, 0, 0
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
                fails += sum(r.tag == "failure" for r in child)
                errors += sum(r.tag == "error" for r in child)
        assert (n["tests"], n["failures"], n["errors"]) == (cases, fails, errors)
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


def test_a_malformed_output_is_an_error_in_the_reports(tmp_path, capsys):
    """A malformed file is exit 2 with one line on stderr, and the CI reports are still written: that
    case an <error> (not a failure), the others not scored (fails on the code before: no file written)."""
    out, _ = golden_sample.write_sample(GOLDEN, tmp_path / "out")
    bad = "0002-chaotic-fig3"
    f = out / f"{bad}.csv"
    lines = f.read_text().splitlines()
    f.write_text("\n".join([lines[0] + ",tau"] + [ln + ",0" for ln in lines[1:]]) + "\n")  # tau twice
    junit, js = tmp_path / "golden.xml", tmp_path / "golden.json"
    assert main(["check", str(out), "--junit-xml", str(junit), "--json", str(js)]) == 2
    cap = capsys.readouterr()
    assert cap.out == "" and len(cap.err.strip().splitlines()) == 1 and bad in cap.err
    root = validate_junit(junit)
    errors = [t.get("name") for t in root.iter("testcase") if t.find("error") is not None]
    assert errors == [bad] and int(root.get("errors")) == 1
    doc = _strict_json(js)
    assert (doc["errors"], doc["passed"], doc["failed"]) == (1, 0, len(CASES) - 1)
    res = {r["id"]: r for r in doc["results"]}
    assert res[bad]["malformed"] is True and "tau" in res[bad]["note"]
    assert all(not r["passed"] for r in doc["results"])


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
    assert props["suite.digest"] == recorded["cases_digest"] and props["suite.digest_matches"] == "True"
    tcs = list(root.iter("testcase"))
    assert [t.get("name") for t in tcs] == CASES
    failed = [t for t in tcs if t.find("failure") is not None]
    assert [t.get("name") for t in failed] == [broken]
    f = failed[0].find("failure")
    assert "first failing: tau at line 2" in f.get("message") and "digits: tau" in f.text
    doc = _strict_json(js)
    assert doc["suite"]["version"] == V.SUITE_VERSION and doc["suite"]["digest"] == recorded["cases_digest"]
    assert (doc["tests"], doc["passed"], doc["failed"]) == (len(CASES), len(CASES) - 1, 1)
    res = {r["id"]: r for r in doc["results"]}
    bad = res[broken]
    assert bad["passed"] is False and bad["level"] == 2
    assert bad["first_failing"] == {"line": 2, "column": "tau"}
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
    assert doc["scored"] == "orbits" and res[broken]["first_failing"] == {"column": "value"}
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
    head, rows = lines[1], lines[3:-1]
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
    """Recompute the digests: they must be those recorded in cases/index.json, and docs/golden.md must
    have a changelog entry for the recorded version naming that digest -- so a change of any case or
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
    log = DOC.read_text(encoding="utf-8").split("### Changelog", 1)[1]
    entry = re.search(rf"^\* \*\*{re.escape(V.SUITE_VERSION)}\*\* .*?(?=^\* \*\*|\Z)", log, re.S | re.M)
    assert entry, f"docs/golden.md: no changelog entry for suite {V.SUITE_VERSION}"
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
    text = DOC.read_text(encoding="utf-8")
    return text.split("## Using the suite in CI", 1)[1].split("\n## ", 1)[0]


def ci_jobs() -> dict[str, list[str]]:
    """The commands of the two YAML jobs of docs/golden.md, in order: GitHub's ``run:`` steps, GitLab's
    ``script:`` items."""
    blocks = re.findall(r"```yaml\n(.*?)```", _ci_section(), re.S)
    assert len(blocks) == 2, "docs/golden.md: expected a GitHub Actions and a GitLab CI job"
    github = [m.strip() for m in re.findall(r"^\s+- run: (.+)$", blocks[0], re.M)]
    script = blocks[1].split("  script:\n", 1)[1]
    gitlab = [m.strip() for m in re.findall(r"^    - (.+)$", script.split("\n  artifacts:", 1)[0], re.M)]
    return {"github": github, "gitlab": gitlab, "_yaml": blocks}


def test_the_ci_job_definitions_parse_and_hold_the_same_commands():
    jobs = ci_jobs()
    assert jobs["github"] == jobs["gitlab"] and len(jobs["github"]) == 5
    yaml = pytest.importorskip("yaml")  # where PyYAML is installed: the blocks are valid YAML, read as above
    gh, gl = (yaml.safe_load(b) for b in jobs["_yaml"])
    steps = gh["jobs"]["golden-suite"]["steps"]
    assert [s["run"] for s in steps if "run" in s] == jobs["github"]
    assert gl["golden-suite"]["script"] == jobs["gitlab"]
    assert gl["golden-suite"]["artifacts"]["reports"]["junit"] == "golden*.xml"


@pytest.mark.parametrize("job", ["github", "gitlab"])
def test_the_ci_jobs_of_the_docs_run(tmp_path, job):
    """Each job's commands from docs/golden.md, run in order by bash on a sample output directory: the
    install line (checked to be the light install) replaced by this environment, ``./my-implementation``
    by the sample writer.  A correct output passes; one wrong value fails the job with a JUnit failure."""
    cmds = ci_jobs()[job]
    install = [c for c in cmds if c.startswith("pip install")]
    assert len(install) == 1 and "--no-deps" in install[0] and "numpy" in install[0]
    sample = f'"{sys.executable}" "{REPO / ".ci" / "golden_sample.py"}" "{GOLDEN}" out $GOLDEN_BREAK'
    script = ["set -euo pipefail", f'gear-rattle() {{ "{sys.executable}" -m gear_rattle "$@"; }}']
    for c in cmds:
        if c in install:
            continue
        script.append(sample if c.startswith("./my-implementation --out out") else c)
    for broken in ("", "0002-chaotic-fig3"):
        wd = tmp_path / (broken or "ok")
        wd.mkdir()
        env = {**os.environ, "GOLDEN_BREAK": f"--break {broken}" if broken else ""}
        p = subprocess.run(
            ["bash", "-c", "\n".join(script)], cwd=wd, capture_output=True, text=True, env=env, timeout=300
        )
        if not broken:
            assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
            assert p.stdout.startswith(f"gear-rattle {__import__('gear_rattle').__version__} (golden suite ")
            for f in ("golden.xml", "golden-orbits.xml"):
                root = validate_junit(wd / f)
                assert root.find("testsuite").get("failures") == "0"
            assert _strict_json(wd / "golden.json")["passed"] == len(CASES)
        else:
            assert p.returncode == 1, p.stdout[-2000:] + p.stderr[-2000:]
            root = validate_junit(wd / "golden.xml")
            assert [t.get("name") for t in root.iter("testcase") if t.find("failure") is not None] == [broken]
            assert not (wd / "golden-orbits.xml").exists()  # the job stops at the failing step


def test_ci_runs_the_light_install_on_the_built_wheel():
    """.ci/run installs the wheel with --no-deps and numpy alone in a fresh venv and scores a sample directory."""
    ci = (REPO / ".ci" / "run").read_text()
    stage = ci.split('stage "light install', 1)[1].split("\nstage ", 1)[0]
    assert '-m venv "$W/light"' in stage and '--no-deps "$(ls "$W"/dist/gear_rattle-*.whl)" numpy' in stage
    for cmd in (
        "gear-rattle --version",
        "gear-rattle check --suite-version",
        ".ci/golden_sample.py",
        "gear-rattle check light-out --junit-xml",
        "gear-rattle check --orbits light-out-orbits",
    ):
        assert cmd in stage, cmd
