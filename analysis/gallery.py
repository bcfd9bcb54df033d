#!/usr/bin/python3
"""One page of several runs: each run's final shape in every engine, and its test metrics.

usage: gallery.py DIR [DIR ...] --out OUTDIR [--title TEXT] [--svg] [--debug]

Each DIR is the output folder of `clothbench run`. For each, the page shows a row of 3D panels,
one per engine, of the engine's last snapshot (same view for every panel of a run, coloured by
the distance to the run's reference engine), the run's summary line per engine (stable, drape
coefficient, final RMS distance from the reference) and, when the scenario has a [test], its
tests.csv as a table (engines by metrics). OUTDIR gets gallery.html (self-contained) and one PNG
per run.

Exit codes: 0 page written; 2 bad input (one line on stderr naming the folder or file); 1
internal error (one line; --debug prints the traceback).
"""

import os
import signal
import sys

if __name__ == "__main__" and not __package__:
    _here = os.path.dirname(os.path.abspath(__file__))
    sys.path = [p for p in sys.path if os.path.abspath(p or ".") != _here]
    sys.path.insert(0, os.path.dirname(_here))

from analysis.csvio import ArgumentParser, ReportError, message  # noqa: E402
from analysis.folder import Folder  # noqa: E402

PROG = "gallery"


def parse_args(argv):
    p = ArgumentParser(PROG, description=(
        "One page (gallery.html) of several run folders: each run's final shape in every "
        "engine, its summary and its standard test's metrics."))
    p.add_argument("dirs", nargs="+", metavar="DIR", help="output folders of clothbench run")
    p.add_argument("--out", metavar="OUTDIR", required=True,
                   help="folder for gallery.html and its images (created if missing)")
    p.add_argument("--title", default="clothbench gallery", help="the page's title")
    p.add_argument("--svg", action="store_true", help="write SVG images besides the PNGs")
    p.add_argument("--debug", action="store_true", help="print the traceback of an internal error")
    return p.parse_args(argv)


def _read(dirs):
    """Every folder read and checked before anything is drawn; labels made unique."""
    folders, seen = [], {}
    for d in dirs:
        if not os.path.isdir(d):
            raise ReportError(f"{d}: no such folder")
        if not os.path.exists(os.path.join(d, "snapshots.csv")):
            raise ReportError(f"{d}: no snapshots.csv (expected the output folder of clothbench run)")
        label = os.path.basename(os.path.normpath(d))
        seen[label] = seen.get(label, 0) + 1
        folders.append(Folder(d, label if seen[label] == 1 else f"{label} ({seen[label]})"))
    return folders


def _final_row(folder, outdir, index, svg, colors):
    """One run's figure: a 3D panel per engine of its last snapshot; returns the PNG path."""
    import matplotlib.pyplot as plt

    from analysis.plots import drape, style
    pairs = drape.rows_of([folder])
    last = {(folder.label, e): [folder.snapshot_times(e)[-1]] for _, e in pairs}
    box = drape.view_box([folder], pairs, last)
    norm = drape.distance_norm(pairs, sorted({t[0] for t in last.values()}))
    cmap = plt.get_cmap("viridis")
    ncols = max(1, len(pairs))
    fig = plt.figure(figsize=(min(3.4 * ncols, 17), 3.9), layout="constrained")
    axes = []
    for k, (f, engine) in enumerate(pairs):
        ax = drape.cell_axes(fig, (1, ncols), k + 1, box)
        t = last[(f.label, engine)][0]
        state = drape.draw_cloth(ax, f, engine, t, box, (colors, norm, cmap))
        ax.set_title(f"{engine}\nt = {style.fmt(t)} s{state}", fontsize=style.FONT - 1)
        axes.append(ax)
    if axes:
        bar = fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=cmap), ax=axes, shrink=0.7,
                           pad=0.02, aspect=25, extend="max")
        bar.set_label("distance to the reference (mm)")
    stem = f"gallery-{index + 1:02d}"
    return style.save(fig, outdir, stem, svg)


def _tests_table(folder):
    """tests.csv as engines by metrics, or "" when the run has no [test]."""
    if not folder.has("tests.csv"):
        return ""
    from analysis.page import E
    from analysis.plots import standard_tests
    from analysis.quantities import num
    rows = standard_tests.metrics(folder)
    engines = []
    for _, _, values in rows:
        engines += [e for e in values if e not in engines]
    head = "<th>engine</th>" + "".join(f"<th>{E(m)} ({E(u)})</th>" for m, u, _ in rows)
    body = []
    for e in engines:
        cells = "".join(f'<td class="num">{E(num(v[e], 4)) if e in v and v[e] == v[e] else ""}</td>'
                        for _, _, v in rows)
        body.append(f"<tr><td>{E(e)}</td>{cells}</tr>")
    return f'<div class="scroll"><table><tr>{head}</tr>{"".join(body)}</table></div>'


def _summary_table(folder):
    """Per engine: stable, drape coefficient and final RMS distance from the reference."""
    if not folder.has("summary.csv"):
        return ""
    from analysis.page import E
    from analysis.quantities import num
    t = folder.table("summary.csv")
    cols = [("stable", "stable"), ("drape_coefficient", "drape coeff."),
            ("final_rms_vs_reference", "final RMS vs ref (m)")]
    cols = [(c, h) for c, h in cols if c in t.columns]
    head = "<th>engine</th>" + "".join(f"<th>{E(h)}</th>" for _, h in cols)
    body = []
    for row in t.rows():
        cells = []
        for c, _ in cols:
            v = row[c]
            if c == "stable":
                cells.append(f"<td>{'yes' if v >= 0.5 else '<b>no</b>'}</td>")
            else:
                cells.append(f'<td class="num">{E(num(float(v), 4)) if v == v else ""}</td>')
        body.append(f"<tr><td>{E(str(row['engine']))}</td>{''.join(cells)}</tr>")
    return f'<div class="scroll"><table><tr>{head}</tr>{"".join(body)}</table></div>'


def _section(folder, png):
    from analysis.page import E, image
    scenario = folder.scenario
    name = str(scenario.get("name", folder.label))
    desc = str(scenario.get("description", ""))
    parts = [f"<h2>{E(name)}</h2>",
             f'<p class="meta">folder: {E(folder.label)}</p>'
             + (f'<p class="desc">{E(desc)}</p>' if desc else ""),
             f"<figure>{image(png)}</figure>", _summary_table(folder), _tests_table(folder)]
    return "\n".join(parts)


def run(argv):
    args = parse_args(argv)
    folders = _read(args.dirs)
    if os.path.exists(args.out) and not os.path.isdir(args.out):
        raise ReportError(f"--out {args.out}: exists and is not a folder")
    os.makedirs(args.out, exist_ok=True)

    from analysis.page import CSS, E
    from analysis.plots import style
    engines = []
    for f in folders:
        engines += [e for e in f.engines() if e not in engines]
    colors = style.Colors(engines)
    sections = []
    for k, f in enumerate(folders):
        print(f"gallery: {k + 1}/{len(folders)} {f.label}", file=sys.stderr, flush=True)
        sections.append(_section(f, _final_row(f, args.out, k, args.svg, colors)))
    text = (f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>{E(args.title)}'
            f"</title><style>{CSS}</style></head><body><main><h1>{E(args.title)}</h1>"
            f'<p class="meta">{len(folders)} runs; each row: every engine\'s last snapshot, '
            "coloured by its distance to the run's reference engine</p>"
            + "\n".join(sections) + "</main></body></html>\n")
    target = os.path.join(args.out, "gallery.html")
    tmp = target + ".tmp"
    try:
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(text)
        os.replace(tmp, target)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    print(f"wrote {target} ({len(folders)} runs)")
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
