"""Strain over time: largest and mean spring strain per engine, blow-ups marked."""

import matplotlib.pyplot as plt
import numpy as np

from . import style
from .energy import frame_engines

STEM = "strain"
TITLE = "Strain over time"
CAPTION = ("Left: the largest stretch l/l0 − 1 of a structural or shear spring (edge springs on "
           "a mesh; bend springs, which close up across a fold, left out) over time per engine. "
           "Right: the mean spring strain |l/l0 − 1| over every spring. A run is unstable from "
           "the first step where the largest stretch passes the blow-up threshold (or a "
           "coordinate is not finite); that point is marked with a cross. Runs written before "
           "stretch was measured show the largest strain over every spring instead.")


def _largest_column(folders):
    """max_stretch where every folder has it, else max_strain (older runs)."""
    ok = all("max_stretch" in f.table("frames.csv") for f in folders if f.has("frames.csv"))
    return ("max_stretch", "largest stretch") if ok else ("max_strain", "largest strain")


def available(folder):
    return folder.has("frames.csv")


def draw(folders, ctx):
    engines = frame_engines(folders)
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.6), layout="constrained")
    largest, largest_name = _largest_column(folders)
    for ax, col, name in ((axes[0], largest, largest_name),
                          (axes[1], "mean_strain", "mean strain")):
        values = []
        for k, f in enumerate(folders):
            if not f.has("frames.csv"):
                continue
            frames = f.table("frames.csv")
            for engine in engines:
                rows = frames.select(engine=engine)
                if not len(rows):
                    continue
                rows = rows.where(np.argsort(rows["t"], kind="stable"))
                ls = style.RUN_STYLES[k]
                color = ctx.colors[engine]
                label = engine if len(folders) == 1 else f"{engine} ({f.label})"
                t, y = rows["t"], rows[col]
                ax.plot(t, y, color=color, ls=ls, lw=1.5, label=label)
                values.extend(y)
                blow = f.blowup(engine)
                if blow is not None:
                    bad = rows["stable"] < 0.5
                    if np.any(bad):
                        tb, yb = t[bad][0], y[bad][0]
                    else:
                        tb, yb = t[-1], y[-1]
                    if not np.isfinite(yb):
                        yb = np.nanmax(style.finite(y)) if len(style.finite(y)) else 1.0
                    ax.plot([tb], [yb], marker="X", ms=11, color="tab:red", mec="black", ls="none")
                    ax.annotate(f"{engine} blew up, t = {style.fmt(tb)} s", (tb, yb),
                                xytext=(10, 0), textcoords="offset points", va="center",
                                color="tab:red", fontsize=style.FONT - 1)
        # the largest strain is read against the blow-up threshold: log scale when positive
        positive = style.finite(values)
        if (col == largest and np.any(positive > 0)) or style.use_log(values, span=30.0):
            ax.set_yscale("log", nonpositive="mask")
        if col == largest:
            limit = max(f.blowup_strain() for f in folders)
            ax.axhline(limit, color="tab:red", ls=":", lw=1.2,
                       label=f"blow-up threshold {style.fmt(limit)}")
        ax.set_title(name)
        ax.set_xlabel("time t (s)")
        ax.set_ylabel("strain |l|/l0 − 1 (dimensionless)")
        style.legend(ax, loc="best")
    style.title(fig, TITLE, folders)
    return style.save(fig, ctx.outdir, STEM, ctx.svg)
