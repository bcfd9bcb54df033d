#!/usr/bin/python3
"""Turn a clothbench output folder into plots and one self-contained report.html.

usage: report.py DIR [--compare DIR2] [--labels A,B] [--out OUTDIR] [--svg]
                 [--snapshot-times T1,T2,...] [--tolerance E] [--movie] [--force] [--debug]

DIR is the output folder of `clothbench run` and/or a sweep (`clothbench stability`,
`clothbench accuracy`); the report draws every plot the folder has data for. With --compare the
same plots show both folders: DIR with solid lines, DIR2 dashed, and the 3D player shows both
folders' engines side by side. --movie also writes movie.mp4 of the player's grid view (ffmpeg).

Exit codes: 0 report written; 2 bad input (missing folder, no CSV, missing column, malformed
value: one line on stderr naming the file); 1 internal error (one line; --debug or
CLOTHBENCH_REPORT_DEBUG=1 prints the traceback).
"""

import math
import os
import signal
import sys

if __name__ == "__main__" and not __package__:
    # run as a script: import the package from the repository root, and keep analysis/ itself
    # off the path so that its module names never shadow the standard library's
    _here = os.path.dirname(os.path.abspath(__file__))
    sys.path = [p for p in sys.path if os.path.abspath(p or ".") != _here]
    sys.path.insert(0, os.path.dirname(_here))

from analysis.csvio import ArgumentParser, ReportError, message  # noqa: E402
from analysis.folder import Folder  # noqa: E402

PROG = "report"
DEBUG_ENV = "CLOTHBENCH_REPORT_DEBUG"


def _positive_number(text):
    """A finite number > 0, refused as `clothbench accuracy --tolerance` refuses it."""
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not (math.isfinite(value) and value > 0):
        # a ReportError, not argparse's own: one line, as for every other bad input
        raise ReportError(f'--tolerance: expected a finite number > 0, got "{text}"')
    return value


def parse_args(argv):
    p = ArgumentParser(
        PROG,
        description="Plots and a self-contained report.html from a clothbench output folder.")
    p.add_argument("dir", metavar="DIR", help="output folder of clothbench run or a sweep")
    p.add_argument("--compare", metavar="DIR2",
                   help="second folder drawn in the same plots (dashed), e.g. before a change")
    p.add_argument("--labels", metavar="A,B",
                   help="names of DIR and DIR2 in legends (default: the folder names)")
    p.add_argument("--out", metavar="OUTDIR",
                   help="where to write report.html and the images (default: DIR, or "
                        "DIR/compare-DIR2NAME with --compare)")
    p.add_argument("--svg", action="store_true", help="write SVG images besides the PNGs")
    p.add_argument("--snapshot-times", metavar="LIST",
                   help="snapshot times (s) for the drape plot, comma separated (default: up to 4 "
                        "spread from the first to the last)")
    p.add_argument("--force", action="store_true",
                   help="with --compare: compare folders of different scenarios all the same")
    p.add_argument("--tolerance", metavar="E", type=_positive_number,
                   help="error tolerance (m) drawn on the work-precision plot (default: from "
                        "recommendation.csv)")
    p.add_argument("--movie", action="store_true",
                   help="also write movie.mp4: every engine's cloth over time (needs ffmpeg)")
    p.add_argument("--debug", action="store_true",
                   help=f"print the traceback of an internal error (or set {DEBUG_ENV}=1)")
    return p.parse_args(argv)


def labels_for(args):
    if args.labels:
        parts = [s.strip() for s in args.labels.split(",")]
        if len(parts) != (2 if args.compare else 1) or not all(parts):
            raise ReportError(f"--labels: expected {2 if args.compare else 1} comma-separated "
                              f"names, got '{args.labels}'")
        return parts
    paths = [args.dir] + ([args.compare] if args.compare else [])
    names = [os.path.basename(os.path.normpath(p)) for p in paths]
    if len(names) == 2 and names[0] == names[1]:
        names = [os.path.join(*os.path.normpath(os.path.abspath(p)).split(os.sep)[-2:])
                 for p in paths]
        if names[0] == names[1]:
            names = ["A", "B"]
    return names


def parse_times(text):
    if not text:
        return None
    try:
        return [float(s) for s in text.split(",") if s.strip()]
    except ValueError:
        raise ReportError(f"--snapshot-times: expected numbers separated by commas, got '{text}'") \
            from None


def notes_for(folders):
    """Lines for the page about files that are absent or empty."""
    notes = []
    run_files = ["frames.csv", "divergence.csv", "snapshots.csv", "summary.csv"]
    sweep_files = ["stability.csv", "work_precision.csv", "convergence.csv", "recommendation.csv"]
    for f in folders:
        prefix = f"{f.label}: " if len(folders) > 1 else ""
        present = set(f.tables)
        for group in (run_files, sweep_files):
            if present & set(group):
                missing = [n for n in group if n not in present]
                if missing:
                    notes.append(f"{prefix}no {', '.join(missing)}: the plots that need "
                                 f"{'it' if len(missing) == 1 else 'them'} are left out.")
        for name in sorted(present):
            if not f.has(name):
                notes.append(f"{prefix}{name} has a header but no rows.")
        if not f.scenario_text and present & set(run_files):
            notes.append(f"{prefix}no scenario.toml: titles use the folder name.")
    return notes


def _refuse_different_scenarios(folders, force):
    """--compare of two scenes that are not the same scenario compares nothing (a 5 x 5 cloth
    against a chain): refused, or with --force a loud warning on stderr."""
    if len(folders) != 2 or folders[0].name == folders[1].name:
        return
    what = (f"--compare: {folders[0].path} is the scenario '{folders[0].name}' and "
            f"{folders[1].path} is '{folders[1].name}'")
    if not force:
        raise ReportError(f"{what}; a comparison of different scenes means little "
                          "(--force compares them all the same)")
    print(message(PROG, f"warning: {what}; compared because of --force"), file=sys.stderr)


def _output_folder(args):
    """The folder the report goes to, created and checked writable."""
    outdir = args.out or (args.dir if not args.compare else os.path.join(
        args.dir, "compare-" + os.path.basename(os.path.normpath(args.compare))))
    try:
        os.makedirs(outdir, exist_ok=True)
    except OSError as e:
        raise ReportError(f"{outdir}: cannot create the output folder: {e.strerror}") from None
    if not os.access(outdir, os.W_OK):
        raise ReportError(f"{outdir}: output folder is not writable")
    return outdir


def _colored_keys(folders, style):
    """Every engine, and every engine / integrator of the sweeps, in the order colours go."""
    engines = []
    for f in folders:
        engines += [e for e in f.engines() if e not in engines]
        for name in ("work_precision.csv", "stability.csv", "convergence.csv", "resolution.csv"):
            if f.has(name):
                keys = [style.config_key(e, i) for e, i in style.configs(f.table(name))]
                engines += [k for k in keys if k not in engines]
    return engines


def _figures(folders, ctx, plots):
    """(stem, title, caption, PNG path) of each plot, or (stem, title, why it is left out,
    None)."""
    figures = []
    for plot in plots:
        if any(plot.available(f) for f in folders):
            reason = plot.skip_reason(folders) if hasattr(plot, "skip_reason") else None
            if reason:
                figures.append((plot.STEM, plot.TITLE, f"Not drawn: {reason}", None))
            else:
                figures.append((plot.STEM, plot.TITLE, plot.CAPTION, plot.draw(folders, ctx)))
    return figures


def _verdict_groups(folders, verdicts):
    groups = []
    for f in folders:
        prefix = f"{f.label}: " if len(folders) > 1 else ""
        groups += [(prefix + h, lines) for h, lines in verdicts.run_verdicts(f)]
        groups += [(prefix + h, lines) for h, lines in verdicts.sweep_verdicts(f)]
    if len(folders) == 2:
        groups = verdicts.compare_verdicts(*folders) + groups
    return groups


def run(argv):
    args = parse_args(argv)
    labels = labels_for(args)
    folders = [Folder(args.dir, labels[0])]
    if args.compare:
        folders.append(Folder(args.compare, labels[1]))
    snapshot_times = parse_times(args.snapshot_times)
    outdir = _output_folder(args)

    _refuse_different_scenarios(folders, args.force)
    if args.movie:
        from analysis import movie
        movie.check(folders)  # bad input writes nothing: refused before any plot

    # plotting starts only once every input has been read and checked
    from analysis import page, player, verdicts
    from analysis.plots import ALL, Context, style

    ctx = Context(outdir, args.svg, style.Colors(_colored_keys(folders, style)), snapshot_times,
                  args.tolerance)
    figures = _figures(folders, ctx, ALL)
    groups = _verdict_groups(folders, verdicts)
    params = [(f.label, style.scenario_params(f)) for f in folders]
    text = page.build(folders, figures, groups, notes_for(folders), params,
                      player.section(folders, ctx.colors))

    target = os.path.join(outdir, "report.html")
    tmp = target + ".tmp"
    try:
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(text)
        os.replace(tmp, target)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)  # interrupted: no half-written page is left
    if args.movie:
        from analysis import movie
        print(f"wrote {movie.write(folders, outdir, ctx.colors)}")
    drawn = [os.path.basename(p) for _, _, _, p in figures if p]
    left_out = [t for _, t, _, p in figures if not p]
    print(f"wrote {target} ({len(drawn)} plots: {', '.join(drawn)}"
          + (f"; not drawn: {', '.join(left_out)}" if left_out else "") + ")")
    return 0


def _interrupt(signum, frame):
    """SIGTERM as Ctrl-C: the same clean-up, then exit 143 (130 for Ctrl-C)."""
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
    except Exception as e:  # a bug here, not the user's input: one line, the traceback on demand
        if "--debug" in argv or os.environ.get(DEBUG_ENV, "") not in ("", "0"):
            raise
        where = ""
        tb = e.__traceback__
        while tb is not None:
            where = f" at {os.path.basename(tb.tb_frame.f_code.co_filename)}:{tb.tb_lineno}"
            tb = tb.tb_next
        text = " ".join(str(e).split())
        print(message(PROG, f"internal error: {type(e).__name__}: {text}{where} (a bug in the "
                            f"report; rerun with --debug or {DEBUG_ENV}=1 for the traceback)"),
              file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
