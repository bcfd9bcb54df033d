"""report.html: one self-contained page (inline CSS, images as base64 data URIs; the only
script is the 3D player's, inlined with three.js, see player.py)."""

import base64
import html
import math
import os

from .player import CSS as PLAYER_CSS
from .quantities import num

# summary.csv column -> header shown (with unit)
SUMMARY_HEADERS = {
    "engine": "engine", "kind": "kind", "integrator": "integrator", "dt": "dt (s)",
    "steps": "steps", "wall_s": "wall (s)", "us_per_step": "µs / step",
    "force_evals": "force evals", "stable": "stable", "blowup_t": "blow-up t (s)",
    "max_energy_error": "max energy error (J)", "final_rms_vs_reference": "final RMS vs ref (m)",
    "max_rms_vs_reference": "max RMS vs ref (m)", "drape_coefficient": "drape coeff.",
}
STABILITY_HEADERS = {
    "engine": "engine", "integrator": "integrator", "stable_dt": "largest stable dt (s)",
    "first_unstable_dt": "first unstable dt (s)", "predicted_dt": "predicted dt (s)",
    "ratio_measured_to_predicted": "measured / predicted", "cause": "cause",
}
RECOMMENDATION_HEADERS = {
    "scope": "scope", "engine": "engine", "integrator": "integrator", "dt": "dt (s)",
    "error_max": "max error (m)", "wall_s_per_sim_s": "wall s / sim s",
    "tolerance": "tolerance (m)",
}
CONVERGENCE_HEADERS = {"engine": "engine", "integrator": "integrator", "order": "order",
                       "points": "points"}
WORK_PRECISION_HEADERS = {
    "engine": "engine", "integrator": "integrator", "dt": "dt (s)", "stable": "stable",
    "error_final": "final error (m)", "error_max": "max error (m)", "wall_s": "wall (s)",
    "wall_s_per_sim_s": "wall s / sim s", "force_evals": "force evals",
    "cg_iterations": "CG iterations",
}
RESOLUTION_HEADERS = {
    "engine": "engine", "integrator": "integrator", "particles": "particles", "dt": "dt (s)",
    "stable": "stable", "error_final": "final error (m)", "wall_s_per_sim_s": "wall s / sim s",
    "force_evals": "force evals",
}

CSS = """
body { font-family: "DejaVu Sans", Helvetica, Arial, sans-serif; font-size: 15px; color: #1d1d1f;
       margin: 0; background: #f4f4f6; }
main { max-width: 1340px; margin: 0 auto; padding: 20px 28px 40px; background: #fff; }
h1 { font-size: 26px; margin: 8px 0 4px; }
h2 { font-size: 20px; margin: 30px 0 10px; border-bottom: 2px solid #d0d0d8; padding-bottom: 4px; }
h3 { font-size: 16px; margin: 18px 0 6px; }
.meta { color: #555; font-size: 13px; margin: 2px 0; }
.desc { margin: 8px 0 4px; }
ul.verdicts { list-style: none; padding-left: 0; margin: 4px 0; }
ul.verdicts li { margin: 4px 0; padding: 5px 10px; border-left: 5px solid #9aa;
                 background: #f7f8fa; }
ul.verdicts li.ok { border-color: #2e9a44; }
ul.verdicts li.bad { border-color: #d03030; background: #fdf3f3; }
.badge { display: inline-block; font-size: 12px; font-weight: bold; padding: 1px 6px;
         border-radius: 3px; margin-right: 6px; color: #fff; background: #888; }
.ok .badge { background: #2e9a44; } .bad .badge { background: #d03030; }
table { border-collapse: collapse; margin: 6px 0 12px; font-size: 13px; }
th, td { border: 1px solid #ccd; padding: 4px 7px; }
th { background: #eceef3; text-align: center; vertical-align: bottom; }
td.num { text-align: right; font-family: "DejaVu Sans Mono", monospace; white-space: nowrap; }
tr.unstable td { background: #fdeaea; }
.scroll { overflow-x: auto; }
figure { margin: 18px 0 26px; }
figure img { display: block; max-width: 100%; height: auto; border: 1px solid #dde; }
figcaption { color: #333; font-size: 14px; margin-top: 6px; max-width: 1100px; }
p.skipped { color: #555; font-style: italic; margin: 4px 0; }
pre { background: #f4f5f7; padding: 10px; font-size: 12px; overflow-x: auto; }
details summary { cursor: pointer; color: #2455a4; margin: 6px 0; }
ul.params { margin: 6px 0; padding-left: 22px; }
.notes { color: #555; font-size: 13px; }
"""

E = html.escape


def _cell(value, col, text_cols):
    if col in text_cols or isinstance(value, str):
        return f"<td>{E(str(value))}</td>"
    if col == "stable":
        if isinstance(value, float) and math.isnan(value):
            return "<td></td>"
        return f"<td>{'yes' if value >= 0.5 else '<b>no</b>'}</td>"
    if isinstance(value, float) and math.isnan(value):
        return '<td class="num"></td>'
    counts = ("steps", "force_evals", "points", "cg_iterations", "particles")
    if col in counts and float(value).is_integer():
        return f'<td class="num">{int(value)}</td>'
    return f'<td class="num">{E(num(float(value), 4))}</td>'


UNCOUNTED_NOTE = ("n/a*: the engine does not count force evaluations (Bullet's solvers do not "
                  "report them), so its cost is its wall time alone.")


def _uncounted(row, col):
    """True for a force-evaluation count of 0 over steps taken: an engine that counts none."""
    return (col == "force_evals" and "steps" in row and row[col] == 0
            and isinstance(row["steps"], float) and row["steps"] > 0)


def _uncounted_cell():
    return '<td class="num">n/a*</td>'


def table(t, headers, extra_first=None):
    """An HTML table of a csvio.Table: known columns first (friendly headers), then extras.

    extra_first  (header, value) of a column put before the others (the run label in --compare)
    """
    cols = [c for c in headers if c in t.columns] + [c for c in t.order if c not in headers]
    text_cols = {c for c in cols if t[c].dtype == object}
    head = "".join(f"<th>{E(headers.get(c, c))}</th>" for c in cols)
    if extra_first:
        head = f"<th>{E(extra_first[0])}</th>" + head
    body, uncounted = [], False
    for row in t.rows():
        cls = ' class="unstable"' if "stable" in row and row["stable"] < 0.5 else ""
        cells = "".join(_uncounted_cell() if _uncounted(row, c) else _cell(row[c], c, text_cols)
                        for c in cols)
        uncounted = uncounted or any(_uncounted(row, c) for c in cols)
        if extra_first:
            cells = f"<td>{E(extra_first[1])}</td>" + cells
        body.append(f"<tr{cls}>{cells}</tr>")
    note = f'<p class="notes">{UNCOUNTED_NOTE}</p>' if uncounted else ""
    return f'<div class="scroll"><table><tr>{head}</tr>{"".join(body)}</table></div>{note}'


def verdict_list(groups):
    out = []
    badge = {"ok": "OK", "bad": "ATTENTION", "info": "INFO"}
    for heading, lines in groups:
        out.append(f"<h3>{E(heading)}</h3><ul class=\"verdicts\">")
        for kind, text in lines:
            out.append(f'<li class="{kind}"><span class="badge">{badge[kind]}</span>{E(text)}</li>')
        out.append("</ul>")
    return "\n".join(out)


def image(path):
    with open(path, "rb") as f:
        data = base64.b64encode(f.read()).decode("ascii")
    return f'<img alt="{E(os.path.basename(path))}" src="data:image/png;base64,{data}">'


def _run_info(f):
    info = f.run_info
    parts = []
    for key in ("tool", "version", "git_commit", "compiler", "date", "command"):
        if key in info:
            parts.append(f"{key.replace('_', ' ')}: {info[key]}")
    for key, value in info.items():
        if key not in ("tool", "version", "git_commit", "compiler", "date", "command") and \
                isinstance(value, (str, int, float)):
            parts.append(f"{key.replace('_', ' ')}: {value}")
    return " · ".join(parts)


def _head(folders):
    """The document's head and the page's title, folders, run information and descriptions."""
    names = []
    for f in folders:
        if f.name not in names:
            names.append(f.name)
    title = f"clothbench report — {' / '.join(names)}"
    out = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
           '<meta name="viewport" content="width=device-width, initial-scale=1">',
           f"<title>{E(title)}</title><style>{CSS}{PLAYER_CSS}</style></head><body><main>",
           f"<h1>{E(title)}</h1>"]
    for f in folders:
        label = f"{f.label}: " if len(folders) > 1 else ""
        out.append(f'<p class="meta">{E(label)}folder {E(os.path.abspath(f.path))}</p>')
        info = _run_info(f)
        if info:
            out.append(f'<p class="meta">{E(label)}{E(info)}</p>')
    descs = {str(f.scenario.get("description", "")) for f in folders} - {""}
    for d in sorted(descs):
        out.append(f'<p class="desc">{E(d)}</p>')
    if len(folders) > 1:
        out.append(f'<p class="desc">Comparison: <b>{E(folders[0].label)}</b> is drawn with solid '
                   f'lines, <b>{E(folders[1].label)}</b> with dashed lines.</p>')
    return out


def _tables(folders):
    """The summary, stability, recommendation and convergence tables, then every
    work-precision and resolution row folded away."""
    out = []
    summaries = [f for f in folders if f.has("summary.csv")]
    if summaries:
        out.append("<h2>Summary</h2>")
        if len(folders) > 1:
            for f in summaries:
                out.append(f"<h3>{E(f.label)}</h3>")
                out.append(table(f.table("summary.csv"), SUMMARY_HEADERS))
        else:
            out.append(table(summaries[0].table("summary.csv"), SUMMARY_HEADERS))
    for name, heading, headers in (
            ("stability.csv", "Stability limits", STABILITY_HEADERS),
            ("recommendation.csv", "Recommendation", RECOMMENDATION_HEADERS),
            ("convergence.csv", "Convergence orders", CONVERGENCE_HEADERS)):
        have = [f for f in folders if f.has(name)]
        if have:
            out.append(f"<h2>{E(heading)}</h2>")
            for f in have:
                if len(folders) > 1:
                    out.append(f"<h3>{E(f.label)}</h3>")
                out.append(table(f.table(name), headers))
    for name, what, headers in (
            ("work_precision.csv", "Every work-precision row", WORK_PRECISION_HEADERS),
            ("resolution.csv", "Every resolution row", RESOLUTION_HEADERS)):
        for f in folders:
            if f.has(name):
                label = f" ({f.label})" if len(folders) > 1 else ""
                out.append(f"<details><summary>{E(what)}{E(label)}</summary>")
                out.append(table(f.table(name), headers))
                out.append("</details>")
    return out


def _plots(figures):
    """Each plot as a figure, or its heading and why it is left out."""
    if not figures:
        return []
    out = ["<h2>Plots</h2>"]
    for stem, heading, caption, path in figures:
        if path is None:
            out.append(f'<h3>{E(heading)}</h3>'
                       f'<p class="skipped" id="skipped-{E(stem)}">{E(caption)}</p>')
            continue
        out.append(f"<figure><h3>{E(heading)}</h3>{image(path)}"
                   f"<figcaption>{E(caption)}</figcaption></figure>")
    return out


def _scenario(folders, params):
    """Each folder's key scenario parameters and its resolved scenario.toml."""
    if not (any(p for _, p in params) or any(f.scenario_text for f in folders)):
        return []
    out = ["<h2>Scenario</h2>"]
    for f, (label, plist) in zip(folders, params):
        if len(folders) > 1:
            out.append(f"<h3>{E(label)}</h3>")
        if plist:
            out.append('<ul class="params">' + "".join(
                f"<li>{E(text)}</li>" for _, text in plist) + "</ul>")
        if f.scenario_text:
            out.append("<details><summary>Resolved scenario.toml</summary>"
                       f"<pre>{E(f.scenario_text)}</pre></details>")
    return out


def build(folders, figures, verdict_groups, notes, params, player_html=""):
    """The page as a string.

    folders         one or two Folder objects
    figures         list of (stem, title, caption, png path); path None: a plot left out,
                    whose caption says why
    verdict_groups  list of (heading, [(kind, text)]) from verdicts
    notes           list of strings (files missing, plots skipped)
    params          list of (folder label, [(name, text)]) key scenario parameters
    player_html     the 3D player's section (player.section), or ""
    """
    out = _head(folders)
    # the cloths moving come first: people look before they read
    if player_html:
        out.append(player_html)
    out.append("<h2>Verdicts</h2>")
    out.append(verdict_list(verdict_groups) if verdict_groups else
               "<p>No verdicts: the folder has no run or sweep results.</p>")
    out += _tables(folders) + _plots(figures) + _scenario(folders, params)
    if notes:
        out.append("<h2>Notes</h2><ul class=\"notes\">" +
                   "".join(f"<li>{E(n)}</li>" for n in notes) + "</ul>")
    out.append("</main></body></html>")
    return "\n".join(out) + "\n"
