"""Resolution recommendation: error against cost of every grid and time step configuration,
with the tolerance and the configurations resolution_recommendation.csv picks."""

import matplotlib.pyplot as plt
import numpy as np

from . import style

STEM = "resolution_recommendation"
TITLE = "Resolution recommendation"
CAPTION = ("Resolution recommendation (resolution_recommendation.csv, written by clothbench "
           "accuracy --resolutions with --tolerance): the final RMS error of every stable "
           "configuration of the resolution study against its wall time per simulated second, "
           "log-log, one line per engine and integrator through its grid sizes (labelled with "
           "the particle count). The dashed line is the tolerance; the ringed points are the "
           "recommendations, the cheapest configuration within the tolerance per engine and "
           "overall (cheapest by counted work, see clothbench accuracy --help).")


def available(folder):
    return folder.has("resolution_recommendation.csv")


def draw(folders, ctx):
    panels = [f for f in folders if available(f)]
    fig, axes = plt.subplots(1, len(panels), figsize=(12, 6.5), squeeze=False,
                             layout="constrained")
    for ax, f in zip(axes[0], panels):
        _draw_one(ax, f, ctx)
        if len(panels) > 1:
            ax.set_title(f.label)
    style.title(fig, TITLE, panels,
                engines_line=style.sweep_line(panels, ("resolution.csv",)), compare="panels")
    return style.save(fig, ctx.outdir, STEM, ctx.svg)


def _draw_one(ax, f, ctx):
    rec = f.table("resolution_recommendation.csv")
    if f.has("resolution.csv"):
        res = f.table("resolution.csv")
        ok = ((res["stable"] >= 0.5) & np.isfinite(res["error_final"]) & (res["error_final"] > 0)
              & np.isfinite(res["wall_s_per_sim_s"]) & (res["wall_s_per_sim_s"] > 0))
        for e, i in style.configs(res):
            key = style.config_key(e, i)
            m = np.flatnonzero(ok & (res["engine"] == e) & (res["integrator"] == i))
            m = m[np.argsort(res["particles"][m])]
            if not len(m):
                continue
            x, y = res["wall_s_per_sim_s"][m], res["error_final"][m]
            ax.plot(x, y, marker="o", ms=5, lw=1, color=ctx.colors[key], label=key)
            for xi, yi, n in zip(x, y, res["particles"][m]):
                ax.annotate(f"{int(n)}", (xi, yi), textcoords="offset points", xytext=(4, 4),
                            fontsize=style.FONT - 2, color=ctx.colors[key])
    tol = style.finite(rec["tolerance"])
    if len(tol) and tol[0] > 0:
        ax.axhline(tol[0], color="0.3", ls="--", lw=1.2, label=f"tolerance {tol[0]:.3g} m")
    found = np.flatnonzero(np.isfinite(rec["error_final"]) & np.isfinite(rec["wall_s_per_sim_s"]))
    for k in found:
        scope = rec["scope"][k]
        who = "overall" if scope == "overall" else f"{rec['engine'][k]}"
        ax.plot([rec["wall_s_per_sim_s"][k]], [rec["error_final"][k]], marker="o", ms=16,
                mfc="none", mec="black", mew=2 if scope == "overall" else 1, ls="none",
                label=f"recommended ({who}): {int(rec['particles'][k])} particles, "
                      f"dt {style.fmt(float(rec['dt'][k]))} s")
    if not len(found):
        style.note(ax, "no configuration meets the tolerance")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time per simulated second (s/s)")
    ax.set_ylabel("final RMS error vs finest-grid reference (m)")
    style.legend(ax, loc="upper right", fontsize=style.FONT - 1)
