#!/usr/bin/python3
"""The engines compared at the fitted fabric: one page of a `clothbench fit --run` folder.

usage: fit_page.py DIR [--out OUTDIR] [--svg] [--debug]

DIR is the output folder of `clothbench fit ... --run`: its fit.csv and, in DIR/runs/, the
run folder of each fitted scenario. The page shows, per engine, the fitted parameters and every
target metric against its target (with the fit's status); a plot of each metric's error per
engine against the issue's goal (3 %, the drape coefficient 0.03); and for each fitted run the
engines' final shapes side by side with the run's summary and test metrics (gallery.py's
panels). OUTDIR (default DIR) gets fit.html (self-contained) and its PNGs.

Exit codes: 0 page written; 2 bad input (one line on stderr naming the folder or file); 1
internal error (one line; --debug prints the traceback).
"""

import math
import os
import signal
import sys

if __name__ == "__main__" and not __package__:
    _here = os.path.dirname(os.path.abspath(__file__))
    sys.path = [p for p in sys.path if os.path.abspath(p or ".") != _here]
    sys.path.insert(0, os.path.dirname(_here))

from analysis.csvio import ArgumentParser, ReportError, message  # noqa: E402

PROG = "fit page"
GOAL = 0.03  # issue 31: relative, and absolute for the drape coefficient (a fraction itself)


def parse_args(argv):
    p = ArgumentParser(PROG, description=(
        "One page (fit.html) comparing the engines at the values clothbench fit found: the "
        "fitted parameters, each metric against its target, the final shapes side by side."))
    p.add_argument("dir", metavar="DIR", help="output folder of clothbench fit --run")
    p.add_argument("--out", metavar="OUTDIR", help="folder for fit.html (default: DIR)")
    p.add_argument("--svg", action="store_true", help="write SVG images besides the PNGs")
    p.add_argument("--debug", action="store_true", help="print the traceback of an internal error")
    return p.parse_args(argv)


def read_fit(path):
    """fit.csv's rows as dicts (numbers as floats, NaN for empty), read against its schema."""
    from analysis.csvio import read_table
    if not os.path.exists(path):
        raise ReportError(f"{path}: no such file (expected the output folder of clothbench fit)")
    return [{k: (str(v) if isinstance(v, str) else float(v)) for k, v in row.items()}
            for row in read_table(path).rows()]


def error_of(row):
    """The row's miss in the goal's terms: absolute for the drape coefficient, else relative."""
    if row["metric"] == "drape_coefficient":
        return row["achieved"] - row["target"]
    return row["relative_error"]


def _engines(rows):
    out = []
    for r in rows:
        if r["engine"] not in out:
            out.append(r["engine"])
    return out


def _metrics(rows):
    out = []
    for r in rows:
        if (r["metric"], r["target"]) not in out:
            out.append((r["metric"], r["target"]))
    return out


def fit_table(rows):
    """Engines by (fitted parameters, then each metric: achieved, miss and status)."""
    from analysis.page import E
    from analysis.quantities import num
    engines, metrics = _engines(rows), _metrics(rows)
    params = []
    for r in rows:
        if r["parameter"] and r["parameter"] not in params:
            params.append(r["parameter"])
    head = ("<tr><th>engine</th>" + "".join(f"<th>{E(p)}</th>" for p in params)
            + "".join(f"<th>{E(m)}<br>target {E(num(t, 4))}</th>" for m, t in metrics) + "</tr>")
    body = []
    for e in engines:
        mine = [r for r in rows if r["engine"] == e]
        cells = []
        for p in params:
            v = [r["value"] for r in mine if r["parameter"] == p and r["value"] == r["value"]]
            cells.append(f'<td class="num">{E(num(v[0], 4)) if v else ""}</td>')
        for m, t in metrics:
            r = next((r for r in mine if r["metric"] == m and r["target"] == t), None)
            cells.append(_metric_cell(r))
        body.append(f"<tr><td>{E(e)}</td>{''.join(cells)}</tr>")
    return f'<div class="scroll"><table>{head}{"".join(body)}</table></div>'


def _metric_cell(r):
    """One engine's metric: achieved, its miss, the status when not converged, runs."""
    from analysis.page import E
    from analysis.quantities import num
    if r is None:
        return "<td></td>"
    if r["status"] == "no engine":
        return '<td class="num">not in the scene<br>of this metric</td>'
    achieved = num(r["achieved"], 4) if r["achieved"] == r["achieved"] else "no value"
    miss = error_of(r)
    unit = "" if r["metric"] == "drape_coefficient" else " %"
    scale = 1.0 if r["metric"] == "drape_coefficient" else 100.0
    miss_text = f" ({miss * scale:+.{3 if not unit else 1}f}{unit})" if miss == miss else ""
    status = r["status"]
    flag = "" if status == "converged" else f"<br><b>{E(status)}</b>"
    runs = int(r["runs"]) if r["runs"] == r["runs"] else 0
    return f'<td class="num">{E(achieved)}{E(miss_text)}{flag}<br>{runs} runs</td>'


def error_plot(rows, outdir, svg, colors):
    """One panel per target metric: each engine's miss against the goal's band; the PNG."""
    import matplotlib.pyplot as plt
    import numpy as np

    from analysis.plots import style
    engines, metrics = _engines(rows), _metrics(rows)
    fig, axes = plt.subplots(1, len(metrics), figsize=(min(4.2 * len(metrics), 17), 3.6),
                             layout="constrained", squeeze=False)
    for ax, (m, t) in zip(axes[0], metrics):
        drape = m == "drape_coefficient"
        scale = 1.0 if drape else 100.0
        ax.axhspan(-GOAL * scale, GOAL * scale, color="#d9f0d9", zorder=0,
                   label="goal: within 0.03" if drape else "goal: within 3 %")
        ax.axhline(0.0, color="#555", lw=0.8)
        for k, e in enumerate(engines):
            r = next((r for r in rows if r["engine"] == e and r["metric"] == m
                      and r["target"] == t), None)
            miss = error_of(r) if r else math.nan
            if miss == miss:
                ax.bar(k, miss * scale, color=colors[e], width=0.7)
            elif r is not None:
                ax.text(k, 0.0, "no engine" if r["status"] == "no engine" else "no value",
                        rotation=90, ha="center", va="bottom",
                        fontsize=style.FONT - 2, color="#a00")
        ax.set_xlim(-0.6, len(engines) - 0.4)
        ax.set_xticks(np.arange(len(engines)))
        ax.set_xticklabels(engines, rotation=30, ha="right", fontsize=style.FONT - 2)
        ax.set_title(f"{m} (target {t:.4g})", fontsize=style.FONT)
        ax.set_ylabel("achieved - target" if drape else "(achieved - target) / target (%)")
        ax.legend(loc="best", fontsize=style.FONT - 2)
    return style.save(fig, outdir, "fit-errors", svg)


def _run_folders(d):
    """The run folders of the fitted scenarios, DIR/runs/*, by name."""
    from analysis.folder import Folder
    runs = os.path.join(d, "runs")
    if not os.path.isdir(runs):
        raise ReportError(f"{d}: no runs/ folder (run clothbench fit with --run, or run each "
                          "fitted/<scenario> into runs/<its name>)")
    names = sorted(n for n in os.listdir(runs)
                   if os.path.exists(os.path.join(runs, n, "snapshots.csv")))
    if not names:
        raise ReportError(f"{runs}: no run folder in it")
    return [Folder(os.path.join(runs, n), n) for n in names]


def page(rows, folders, outdir, svg):
    """fit.html's text."""
    from analysis import gallery
    from analysis.page import CSS, E, image
    from analysis.plots import style
    engines = _engines(rows)
    for f in folders:
        engines += [e for e in f.engines() if e not in engines]
    colors = style.Colors(engines)
    title = "clothbench fit: the engines at the fitted fabric"
    parts = [f"<h1>{E(title)}</h1>",
             '<p class="meta">each engine run with the values fit found for it (fitted/); '
             "the goal of issue 31: every metric within 3 % of its target, the drape coefficient "
             "within 0.03</p>",
             "<h2>Fitted parameters and metrics</h2>", fit_table(rows),
             f"<figure>{image(error_plot(rows, outdir, svg, colors))}</figure>"]
    for k, f in enumerate(folders):
        print(f"fit page: {k + 1}/{len(folders)} {f.label}", file=sys.stderr, flush=True)
        parts.append(gallery._section(f, gallery._final_row(f, outdir, k, svg, colors)))
    return (f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>{E(title)}'
            f"</title><style>{CSS}</style></head><body><main>" + "\n".join(parts)
            + "</main></body></html>\n")


def run(argv):
    args = parse_args(argv)
    rows = read_fit(os.path.join(args.dir, "fit.csv"))
    if not rows:
        raise ReportError(f"{args.dir}/fit.csv: no rows")
    folders = _run_folders(args.dir)
    outdir = args.out or args.dir
    os.makedirs(outdir, exist_ok=True)
    text = page(rows, folders, outdir, args.svg)
    target = os.path.join(outdir, "fit.html")
    tmp = target + ".tmp"
    try:
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(text)
        os.replace(tmp, target)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    print(f"wrote {target} ({len(_engines(rows))} engines, {len(folders)} runs)")
    return 0


def _interrupt(signum, frame):
    raise KeyboardInterrupt(signum)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    signal.signal(signal.SIGTERM, _interrupt)
    try:
        return run(argv)
    except ReportError as e:
        print(message(PROG, e), file=sys.stderr)
        return 2
    except KeyboardInterrupt as e:
        return 143 if e.args == (signal.SIGTERM,) else 130
    except Exception as e:  # a bug here, not the user's input
        if "--debug" in argv:
            raise
        text = " ".join(str(e).split())
        print(message(PROG, f"internal error: {type(e).__name__}: {text} (a bug; rerun with "
                            "--debug for the traceback)"), file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
