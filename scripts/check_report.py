"""Check that a Snakemake HTML report (`snakemake --report results/report.html`) shows every figure inline.

    .venv/bin/python scripts/check_report.py results/report.html

Two checks, one line per problem, exit status 1 if there is any:

1. In the report's data: every figure is a PNG result (an image every browser draws; a PDF shows blank in a browser
   without a PDF viewer) whose caption links its PDF, and that PDF is a result of the report too.
2. In headless Chromium (Debian: `apt-get install chromium`): a copy of the report with a probe script appended opens
   each PNG result the way a click on it does (`app.setView`, the report's own React app) and measures the <img> the
   report draws; each must decode to a non-empty picture shown with a non-zero width. Skipped, with a message, when no
   Chromium is found (`--chromium PATH` names one).
"""
from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

RESULTS_SCRIPT = re.compile(r'<script id="results">\s*var results = (\{.*?\});\s*</script>', re.S)
PROBE_ID = "forcenet-render-check"
#: appended to the report: opens each image result as a click would and records what the browser drew
PROBE = """
<script>
window.addEventListener("load", async () => {
  const drawn = {};
  const pause = () => new Promise(resolve => setTimeout(resolve, 50));
  for (let i = 0; i < 200 && !app; i++) await pause();  // React creates the app after the load event
  for (const [path, entry] of Object.entries(results)) {
    if (!entry.mime_type.startsWith("image/")) continue;
    app.setView({content: "img", contentPath: entry.data_uri, resultPath: path});
    let img = null;
    for (let i = 0; i < 40 && !img; i++) {
      await pause();
      img = Array.from(document.querySelectorAll("#app img")).find(node => node.src === entry.data_uri) || null;
    }
    if (img === null) { drawn[path] = null; continue; }
    // the image load (a data: URI) holds Chromium's virtual time; wait until its size is known and laid out
    for (let i = 0; i < 200 && !(img.complete && img.naturalWidth > 0); i++) await pause();
    drawn[path] = {width: img.naturalWidth, height: img.naturalHeight, shown: img.getBoundingClientRect().width};
  }
  const out = document.createElement("pre");
  out.id = "%s";
  out.textContent = JSON.stringify(drawn);
  document.body.appendChild(out);
});
</script>
""" % PROBE_ID


def report_results(html: str) -> dict:
    """The `results` object of a Snakemake report: {path: {name, labels, caption, mime_type, data_uri, ...}}."""
    match = RESULTS_SCRIPT.search(html)
    if match is None:
        raise ValueError("no `var results = {...}` in the report: not a Snakemake HTML report")
    return json.loads(match.group(1))


def data_problems(results: dict) -> list[str]:
    """Figures (results labelled `figure`) that are not shown as PNG, or whose PNG does not link a PDF in the report."""
    problems = []
    figures = {}
    for path, entry in results.items():
        name = (entry.get("labels") or {}).get("figure")
        if name:
            figures.setdefault(name, {})[entry["mime_type"]] = (path, entry)
    if not figures:
        problems.append("the report has no results labelled as figures")
    for name, kinds in sorted(figures.items()):
        if "image/png" not in kinds:
            problems.append(f"{name}: no PNG in the report (only {sorted(kinds)}), so a browser without a PDF viewer "
                            "shows nothing")
            continue
        caption = kinds["image/png"][1]["caption"]
        pdf = kinds.get("application/pdf")
        if pdf is None:
            problems.append(f"{name}: its PDF is not in the report")
        elif f"showResultInfo('{pdf[0].replace('/', '%2F')}')" not in caption and pdf[0] not in caption:
            problems.append(f"{name}: the PNG's caption does not link the PDF {pdf[0]}")
    return problems


def find_chromium(explicit: str | None = None) -> str | None:
    if explicit:
        return explicit
    for name in ("chromium", "chromium-browser", "google-chrome", "chrome"):
        found = shutil.which(name)
        if found:
            return found
    return None


def render_in_chromium(report: Path, chromium: str, timeout_s: float = 300.0) -> dict:
    """{path: {width, height, shown} | None} for every image result, as headless Chromium draws it."""
    with tempfile.TemporaryDirectory() as scratch:
        probe = Path(scratch) / "probe.html"
        html = report.read_text(encoding="utf-8")
        head, body_end, tail = html.rpartition("</body>")  # the last one: a bundled script may hold the string too
        probe.write_text(head + PROBE + body_end + tail if body_end else html + PROBE, encoding="utf-8")
        command = [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                   f"--user-data-dir={scratch}/profile", "--virtual-time-budget=60000", "--window-size=1400,1000",
                   "--dump-dom", probe.as_uri()]
        done = subprocess.run(command, capture_output=True, text=True, timeout=timeout_s)
    match = re.search(rf'<pre id="{PROBE_ID}">(.*?)</pre>', done.stdout, re.S)
    if match is None:
        raise RuntimeError(f"Chromium did not run the probe (exit {done.returncode}): {done.stderr.strip()[-500:]}")
    return json.loads(match.group(1).replace("&quot;", '"').replace("&amp;", "&"))


def render_problems(drawn: dict, results: dict) -> list[str]:
    problems = []
    for path, entry in results.items():
        if entry["mime_type"] != "image/png":
            continue
        shown = drawn.get(path)
        if not shown or "error" in shown:
            problems.append(f"{path}: Chromium drew no picture ({shown})")
        elif min(shown["width"], shown["height"], shown["shown"]) <= 0:
            problems.append(f"{path}: drawn empty ({shown})")
    return problems


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("report", type=Path)
    parser.add_argument("--chromium", help="Chromium executable (default: chromium on PATH)")
    args = parser.parse_args(argv)
    results = report_results(args.report.read_text(encoding="utf-8"))
    problems = data_problems(results)
    chromium = find_chromium(args.chromium)
    pngs = sum(entry["mime_type"] == "image/png" for entry in results.values())
    if chromium is None:
        print("no Chromium found: rendering not checked (Debian: apt-get install chromium)", file=sys.stderr)
    else:
        problems += render_problems(render_in_chromium(args.report, chromium), results)
    for problem in problems:
        print(problem, file=sys.stderr)
    if not problems:
        print(f"{args.report}: {pngs} figures shown inline as PNG, each linking its PDF"
              + ("" if chromium is None else f"; all drawn by {Path(chromium).name}"))
    return 1 if problems else 0


if __name__ == "__main__":
    raise SystemExit(main())
