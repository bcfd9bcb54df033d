"""Work-precision: error against cost per configuration, Pareto front, tolerance, recommendation."""

import math

import matplotlib.pyplot as plt
import numpy as np

from . import style
from ..verdicts import recommendation_found

STEM = "work_precision"
TITLE = "Work-precision"
CAPTION = ("Work-precision: largest RMS position error over the run against the reference solution versus wall "
           "time per simulated second, one line per engine and integrator (points are time "
           "steps). Crosses on the dotted line are unstable time steps (no error). The grey band "
           "is the Pareto front; the dashed line is the tolerance and the star the recommended "
           "configuration (none when nothing meets the tolerance).")

TOL_RANGE = 1e3  # a tolerance this far beyond every error is named in the legend, not drawn


def available(folder):
    return folder.has("work_precision.csv")


def pareto(x, y):
    """Indices of the points not dominated in (cost x, error y), in order of increasing cost."""
    order = np.lexsort((y, x))
    front, best = [], math.inf
    for k in order:
        if y[k] < best:
            front.append(k)
            best = y[k]
    return front


def tolerance(folder, ctx):
    if ctx.tolerance is not None:
        return ctx.tolerance
    if folder.has("recommendation.csv"):
        tol = style.finite(folder.table("recommendation.csv")["tolerance"])
        if len(tol):
            return float(tol[0])
    return None


def _draw_configs(ax, wp, x, y, ok, colors, top):
    """One line per engine and integrator, its unstable time steps as crosses (at top when
    they have no error)."""
    any_unstable = False
    for e, i in style.configs(wp):
        key = style.config_key(e, i)
        m = (wp["engine"] == e) & (wp["integrator"] == i)
        s = np.flatnonzero(m & ok)
        s = s[np.argsort(x[s])]
        ax.plot(x[s], y[s], marker="o", ms=5, lw=1.5, color=colors[key], label=key)
        u = np.flatnonzero(m & ~ok & np.isfinite(x) & (x > 0))
        if len(u):
            any_unstable = True
            yu = np.where(np.isfinite(y[u]) & (y[u] > 0), y[u], top)
            ax.plot(x[u], yu, marker="x", ms=8, mew=2, ls="none", color=colors[key])
    if any_unstable:
        ax.axhline(top, color="0.5", ls=":", lw=1)
        ax.plot([], [], marker="x", ms=8, mew=2, ls="none", color="0.3",
                label="unstable (no error)")


def _draw_tolerance(ax, tol, good, top):
    """The tolerance as a dashed line, or only named in the legend when it is far from every
    error (good: the finite positive errors)."""
    # a line far below (or above) the data would squash every point into one band
    far = len(good) and not good.min() / TOL_RANGE <= tol <= top * TOL_RANGE
    if far:
        where = "below" if tol < good.min() else "above"
        ax.plot([], [], color="tab:red", ls="--", lw=1.3,
                label=f"tolerance {style.fmt(tol)} m (far {where} every error, not drawn)")
    else:
        ax.axhline(tol, color="tab:red", ls="--", lw=1.3,
                   label=f"tolerance {style.fmt(tol)} m")


def _draw_recommendations(ax, rec):
    """A star at each configuration recommendation.csv names (once each), or a legend line
    saying that nothing meets the tolerance."""
    shown = set()
    for row in sorted(rec.rows(), key=lambda r: r["scope"] != "overall"):
        if not recommendation_found(row):
            scope = "overall" if row["scope"] == "overall" else f"for {row['engine']}"
            ax.plot([], [], ls="none", label=f"nothing meets the tolerance {scope}")
            continue
        key = (row["engine"], row["integrator"], row["dt"])
        if key in shown:
            continue
        shown.add(key)
        overall = row["scope"] == "overall"
        what = "recommended" if overall else f"cheapest for {row['engine']}"
        label = (f"{what}: {style.config_key(row['engine'], row['integrator'])}, "
                 f"dt {style.fmt(row['dt'])} s")
        ax.plot([row["wall_s_per_sim_s"]], [row["error_max"]], marker="*",
                ms=22 if overall else 15, color="gold", mec="black", ls="none",
                zorder=5, label=label)
        ax.annotate(f"dt {style.fmt(row['dt'])} s", (row["wall_s_per_sim_s"],
                    row["error_max"]), xytext=(12, -2), textcoords="offset points",
                    va="top", fontsize=style.FONT - 1)


def _draw_panel(ax, f, ctx, good, top):
    """One folder's work-precision panel."""
    wp = f.table("work_precision.csv")
    x, y = wp["wall_s_per_sim_s"], wp["error_max"]
    ok = (wp["stable"] >= 0.5) & np.isfinite(y) & (y > 0) & np.isfinite(x) & (x > 0)
    _draw_configs(ax, wp, x, y, ok, ctx.colors, top)
    front = pareto(x[ok], y[ok])
    if front:
        fx, fy = x[ok][front], y[ok][front]
        ax.step(fx, fy, where="post", color="black", lw=7, alpha=0.13, zorder=0,
                label="Pareto front", solid_capstyle="round")
    tol = tolerance(f, ctx)
    if tol is not None and tol > 0:
        _draw_tolerance(ax, tol, good, top)
    if f.has("recommendation.csv"):
        _draw_recommendations(ax, f.table("recommendation.csv"))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time per simulated second (s/s)")
    ax.set_ylabel("max RMS error vs reference (m)")


def draw(folders, ctx):
    panels = [f for f in folders if f.has("work_precision.csv")]
    fig, axes = plt.subplots(1, len(panels), figsize=(12, 7.4), squeeze=False, sharex=True,
                             sharey=True, layout="constrained")
    # one error scale for both panels: unstable points sit just above the largest error
    errs = np.concatenate([f.table("work_precision.csv")["error_max"] for f in panels])
    good = errs[np.isfinite(errs) & (errs > 0)]
    top = good.max() * 6 if len(good) else 1.0
    for ax, f in zip(axes[0], panels):
        _draw_panel(ax, f, ctx, good, top)
        if len(panels) > 1:
            ax.set_title(f.label)
        if f is panels[-1]:  # colours are shared: one legend, right of the last panel
            style.legend(ax, loc="upper left", bbox_to_anchor=(1.01, 1.0),
                         fontsize=style.FONT - 1)
    style.title(fig, TITLE, panels, engines_line=style.sweep_line(panels), compare="panels")
    return style.save(fig, ctx.outdir, STEM, ctx.svg)
