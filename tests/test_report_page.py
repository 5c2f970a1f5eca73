"""The report page as a reader sees it (issue 23 item 11): in headless Chromium at 1024 and 1400 px the
page has no horizontal scroll, the verdict table comes first and fits the width, its rows are a few
lines tall, and disagreements are marked by more than colour (a cross and capitals).

Built from the small fake report of tests/reportfake.py (seconds), and run once on the published
docs/report/report.html.  Needs Debian's ``chromium`` (``.ci/run`` installs it where apt is
available); skips with the reason where it is absent.  No network: the page is a local file with
everything embedded, and Chromium runs with its background networking off.
"""

from __future__ import annotations

import html
import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest
from reportfake import build_fake_report

REPO = Path(__file__).resolve().parents[1]
PUBLISHED = REPO / "docs" / "report" / "report.html"
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
needs_chromium = pytest.mark.skipif(
    CHROMIUM is None,
    reason="chromium is not installed (Debian: apt-get install -y chromium; .ci/run installs it "
    "where apt is available): the report page is not checked in a browser",
)
#: The flags that work on this machine (no sandbox as root, no GPU, no background connections).
FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--hide-scrollbars",
]

#: Measures the laid-out page and writes the result as JSON into <pre id="measure"> (read by --dump-dom).
MEASURE_JS = r"""
<script>
window.addEventListener('load', () => {
  const vw = document.documentElement.clientWidth, out = {vw: vw, sw: document.documentElement.scrollWidth};
  try {
  const table = document.getElementById('verdict-table');
  const box = e => { const r = e.getBoundingClientRect();
                     return [r.left + scrollX, r.top + scrollY, r.right + scrollX, r.bottom + scrollY]; };
  out.table = box(table);
  out.rows = [...table.querySelectorAll('tr')].slice(1).map(tr => ({
      cls: tr.className, h: tr.getBoundingClientRect().height, verdict: tr.querySelector('td.verdict').textContent,
      weight: getComputedStyle(tr.querySelector('td.verdict')).fontWeight}));
  const line = document.createElement('p'); line.textContent = 'x'; document.body.appendChild(line);
  out.line = line.getBoundingClientRect().height; line.remove();
  out.first_section = box(document.querySelector("h2[id^='sec-']"));
  out.about = box(document.getElementById('about'));
  out.details = [...document.querySelectorAll('details')]
      .map(d => ({open: d.open, h: d.getBoundingClientRect().height}));
  out.wide = [...document.body.querySelectorAll('*')].filter(e => !e.closest('.scroll') && box(e)[2] > vw + 0.5)
      .map(e => e.tagName + ': ' + (e.textContent || '').slice(0, 60));
  } catch (err) { out.error = String(err); }
  const pre = document.createElement('pre'); pre.id = 'measure'; pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
});
</script>
"""


def measure(page: Path, width: int, tmp_path: Path) -> dict:
    """Open ``page`` (a copy with :data:`MEASURE_JS`) in headless Chromium ``width`` px wide; the layout."""
    probe = tmp_path / f"measure-{width}.html"
    probe.write_text(page.read_text(encoding="utf-8").replace("</body>", MEASURE_JS + "</body>"), encoding="utf-8")
    cmd = [
        CHROMIUM,
        *FLAGS,
        f"--user-data-dir={tmp_path / f'profile-{width}'}",
        f"--window-size={width},900",
        "--virtual-time-budget=5000",
        "--dump-dom",
        probe.as_uri(),
    ]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    m = re.search(r'<pre id="measure">(.*?)</pre>', r.stdout, flags=re.S)
    assert m, f"chromium exited {r.returncode} without the measurement; stderr: {r.stderr[-2000:]}"
    out = json.loads(html.unescape(m.group(1)))
    assert "error" not in out, f"{page}: {out['error']} (is it a page of today's layout, with its verdict table?)"
    return out


@pytest.fixture(scope="module")
def fake_page(tmp_path_factory):
    mp = pytest.MonkeyPatch()
    try:
        out = build_fake_report(tmp_path_factory.mktemp("page") / "rep", mp)
    finally:
        mp.undo()
    return out / "report.html"


def test_page_is_self_contained(fake_page):
    """Nothing on the page is fetched: no http(s) source or link, figures embedded as data URIs."""
    text = fake_page.read_text(encoding="utf-8")
    assert not re.findall(r"""(?:src|href)=['"](?!#|data:)""", text)
    assert "url(" not in text and "<img src='data:image/png;base64," in text


@needs_chromium
@pytest.mark.parametrize("width", [1024, 1400])
def test_fake_report_page_in_chromium(fake_page, width, tmp_path):
    m = measure(fake_page, width, tmp_path)
    assert width - 20 <= m["vw"] <= width, m["vw"]  # the window is as wide as asked
    # no horizontal scroll: nothing wider than the page (a wide table of a section scrolls in its own box)
    assert m["sw"] <= m["vw"], m["wide"]
    assert not m["wide"]
    # the verdict table comes first, fits the width, and starts on the first screen
    left, top, right, bottom = m["table"]
    assert right <= m["vw"] and top < 900 and bottom < m["about"][1] < m["first_section"][1]
    # every row a few lines tall (the longest reason wraps to at most 5 lines at 1024 px)
    assert len(m["rows"]) == 13
    assert max(r["h"] for r in m["rows"]) <= 5.5 * m["line"], (m["line"], [r["h"] for r in m["rows"]])
    # disagreements: a cross and capitals and bold, not colour alone; agreements a tick
    bad = [r for r in m["rows"] if r["cls"] == "bad"]
    assert len(bad) == 4
    for r in bad:
        symbol, label = r["verdict"].split(" ", 1)
        assert symbol == "✗" and label == label.upper() and int(r["weight"]) >= 600, r
    assert all(r["verdict"].startswith(("✓", "–")) for r in m["rows"] if r["cls"] != "bad")
    # the explanations are folded: each closed details element is one or two lines
    assert m["details"] and all(not d["open"] and d["h"] <= 2.6 * m["line"] for d in m["details"])


@needs_chromium
@pytest.mark.skipif(not PUBLISHED.is_file(), reason=f"no published report at {PUBLISHED}")
def test_published_report_page_has_no_horizontal_scroll_at_1024(tmp_path):
    """docs/report/report.html, as published: no horizontal scroll at 1024 px, the verdict table first."""
    m = measure(PUBLISHED, 1024, tmp_path)
    assert m["sw"] <= m["vw"] and not m["wide"], m["wide"]
    assert m["table"][2] <= m["vw"] and m["table"][3] < m["first_section"][1]
    assert max(r["h"] for r in m["rows"]) <= 5.5 * m["line"]
