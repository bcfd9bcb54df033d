"""The growing mode of each stability row (`clothbench stability --method growth|both`): where on
the cloth, and in which kind of spring, an instability starts at the first dt that grows."""

import math
import re
import textwrap

import matplotlib.pyplot as plt
import numpy as np

from . import style
from .stability import has_growth

STEM = "stability_mode"
TITLE = "Growing modes at the stability limit"
CAPTION = ("One panel per engine and integrator whose growing mode the sweep saved "
           "(stability_modes/ROW.npy): the cloth at rest seen along its thinnest axis, each "
           "particle coloured by its displacement |u_p| in the mode that grows fastest at the "
           "first time step found unstable by growth (the mode scaled to its largest "
           "component; the ringed particle moves most). Bright particles are where the "
           "instability starts; the title splits the mode's spring energy into structural, "
           "shear and bend springs, so the largest share names the kind of spring that goes "
           "first, and says whether a state in contact or the free cloth sets the limit.")

CAUSE_CHARS = 110  # the growth cause is shortened to about this many characters in a title
TITLE_CHARS = 62   # and wrapped to lines of this many, about a panel's width


def available(folder):
    return folder.has("stability.csv") and has_growth(folder.table("stability.csv"))


def skip_reason(folders):
    if not any(f.modes for f in folders if available(f)):
        return ("the stability sweep measured growth but saved no growing mode (no "
                "stability_modes/ROW.npy beside stability.csv)")
    return None


def short_cause(cause):
    """growth_cause with its numbers to 3 significant digits, cut to about CAUSE_CHARS
    characters (keeping the 'non-smooth' and 'near the physics' warnings), on one line."""
    text = re.sub(r"-?\d+\.\d{4,}(?:[eE][-+]?\d+)?",
                  lambda m: style.fmt(float(m.group(0))), str(cause))
    short = textwrap.shorten(text, CAUSE_CHARS, placeholder=" …")
    for warning in ("non-smooth", "near the physics"):
        if warning in text and warning not in short:
            short += f" ({warning})"
    return short


def _plane_axes(rest):
    """The two axes of largest extent of 3 by #P rest positions: the cloth seen along its
    thinnest one."""
    extent = rest.max(axis=1) - rest.min(axis=1)
    return sorted(np.argsort(extent)[1:])


def _title(row):
    """'ENGINE INTEGRATOR at dt = ...: structural a %, shear b %, bend c %' and the cause,
    wrapped to a panel's width."""
    shares = ", ".join(
        f"{kind} {100 * row[f'mode_{kind}']:.0f} %" if math.isfinite(row[f"mode_{kind}"])
        else f"{kind} n/a" for kind in ("structural", "shear", "bend"))
    head = (f"{row['engine']} {row['integrator']} at dt = "
            f"{style.fmt(row['growth_first_unstable_dt'])} s:")
    return "\n".join([head, shares] + textwrap.wrap(short_cause(row["growth_cause"]),
                                                     TITLE_CHARS))


def _draw_panel(ax, fig, rest, mode, row):
    """One row's mode: rest positions coloured by |u_p|, the particle that moves most ringed."""
    a, b = _plane_axes(rest)
    mag = np.linalg.norm(mode, axis=0)
    order = np.argsort(mag)  # brightest on top
    dots = ax.scatter(rest[a][order], rest[b][order], c=mag[order], cmap="viridis", s=26,
                      vmin=0.0, vmax=float(mag.max()) or 1.0, edgecolors="none")
    top = int(np.argmax(mag))
    ax.plot([rest[a][top]], [rest[b][top]], marker="o", ms=12, mfc="none", mec="tab:red",
            mew=2, ls="none")
    bar = fig.colorbar(dots, ax=ax, shrink=0.9)
    bar.set_label("|u_p| (mode scaled to largest component 1)")
    ax.set_aspect("equal")
    ax.set_xlabel(f"{'xyz'[a]} (m)")
    ax.set_ylabel(f"{'xyz'[b]} (m)")
    ax.set_title(_title(row), fontsize=style.FONT - 1)


def draw(folders, ctx):
    # one panel per row with a mode file, the rows of each folder in file order
    panels = []
    for f in folders:
        if available(f) and f.modes:
            rest, modes = f.modes
            table_rows = list(f.table("stability.csv").rows())
            panels += [(f, rest, modes[k], table_rows[k]) for k in sorted(modes)]
    cols = min(2, len(panels))
    nrows = math.ceil(len(panels) / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(6.2 * cols, 5.2 * nrows + 1.2),
                             layout="constrained", squeeze=False)
    for ax, (f, rest, mode, row) in zip(axes.flat, panels):
        _draw_panel(ax, fig, rest, mode, row)
        if len(folders) > 1:
            ax.set_title(f"[{f.label}] " + ax.get_title(), fontsize=style.FONT - 1)
    for ax in list(axes.flat)[len(panels):]:
        ax.set_visible(False)
    style.title(fig, TITLE, folders,
                engines_line=style.sweep_line(folders, ("stability.csv",)), compare="labelled")
    return style.save(fig, ctx.outdir, STEM, ctx.svg)
