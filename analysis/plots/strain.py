"""Strain over time: largest and mean spring strain per engine, blow-ups marked."""

import matplotlib.pyplot as plt
import numpy as np

from . import style
from .energy import frame_engines

STEM = "strain"
TITLE = "Strain over time"
CAPTION = ("Largest and mean spring strain |l|/l0 − 1 over time per engine. A run is unstable "
           "from the first step where the largest strain passes the blow-up threshold (or a "
           "coordinate is not finite); that point is marked with a cross.")


def available(folder):
    return folder.has("frames.csv")


def draw(folders, ctx):
    engines = frame_engines(folders)
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.6), layout="constrained")
    for ax, col, name in ((axes[0], "max_strain", "largest strain"),
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
        if (col == "max_strain" and np.any(positive > 0)) or style.use_log(values, span=30.0):
            ax.set_yscale("log", nonpositive="mask")
        if col == "max_strain":
            limit = max(f.blowup_strain() for f in folders)
            ax.axhline(limit, color="tab:red", ls=":", lw=1.2,
                       label=f"blow-up threshold {style.fmt(limit)}")
        ax.set_title(name)
        ax.set_xlabel("time t (s)")
        ax.set_ylabel("strain |l|/l0 − 1 (dimensionless)")
        style.legend(ax, loc="best")
    style.title(fig, TITLE, folders)
    return style.save(fig, ctx.outdir, STEM, ctx.svg)
