"""The strip-tensile test's force-strain curves (tensile.csv), one line per engine, with each
engine's tensile stiffness (tests.csv) in the legend and its fit range marked."""

import math

import matplotlib.pyplot as plt
import numpy as np

from . import style

STEM = "tensile"
TITLE = "Strip tensile test: force per width against strain"
CAPTION = ("The strip-tensile test (ISO 13934-1 strip geometry): each custom engine's tension "
           "across the strip's central section per unit width (the scene's springs at the "
           "engine's positions, dampers left out) against the strain the handle imposes, a point "
           "per frame (tensile.csv). The legend gives each engine's tensile_stiffness, the "
           "least-squares slope over 0 < strain <= fit_strain (the shaded range). Engines whose "
           "forces are not the scene's springs (the Bullet engines) have no curve.")


def available(folder):
    return folder.has("tensile.csv")


def stiffness(folder):
    """{engine: (tensile_stiffness in N/m, fit_strain)} from tests.csv (NaN: no value)."""
    out = {}
    if not folder.has("tests.csv"):
        return out
    table = folder.table("tests.csv")
    for r in table.rows():
        k, fit = out.get(str(r["engine"]), (math.nan, math.nan))
        if r["metric"] == "tensile_stiffness":
            k = float(r["value"])
        if r["metric"] == "fit_strain":
            fit = float(r["value"])
        out[str(r["engine"])] = (k, fit)
    return out


def draw(folders, ctx):
    fig, ax = plt.subplots(figsize=(9, 5.5), layout="constrained")
    dashes = ["-", "--"]
    fit_max = 0.0
    for n, f in enumerate(f for f in folders if available(f)):
        table = f.table("tensile.csv")
        slopes = stiffness(f)
        for e in table.unique("engine"):
            rows = table.select(engine=e)
            k, fit = slopes.get(str(e), (math.nan, math.nan))
            if math.isfinite(fit):
                fit_max = max(fit_max, fit)
            value = f"{k:.4g} N/m" if math.isfinite(k) else "no value"
            label = f"{e}: tensile_stiffness {value}"
            if len(folders) > 1:
                label = f"{f.label}: {label}"
            ax.plot(np.asarray(rows["strain"]) * 100, rows["force_per_width"], dashes[n % 2],
                    color=ctx.colors[e], label=label, lw=1.4)
    if fit_max > 0:
        ax.axvspan(0, fit_max * 100, color="0.9", zorder=0, label="fit range")
    ax.set_xlabel("strain (%)")
    ax.set_ylabel("force per width (N/m)")
    ax.grid(alpha=0.3)
    style.legend(ax, loc="upper left", fontsize=style.FONT - 1)
    style.title(fig, TITLE, folders)
    return style.save(fig, ctx.outdir, STEM, ctx.svg)
