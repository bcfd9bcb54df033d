"""Convergence: error against time step per configuration, with the fitted orders."""

import matplotlib.pyplot as plt
import numpy as np

from . import style

STEM = "convergence"
TITLE = "Convergence"
CAPTION = ("Convergence: final RMS position error against the time step for every stable run, "
           "log-log, with the fitted line of slope equal to the order (from convergence.csv, or "
           "fitted here when the folder has none). An integrator of order p has slope p.")


def available(folder):
    return folder.has("work_precision.csv") or folder.has("convergence.csv")


def fitted_order(folder, engine, integrator):
    """(order, source) from convergence.csv, or (None, None)."""
    if folder.has("convergence.csv"):
        conv = folder.table("convergence.csv")
        rows = conv.where((conv["engine"] == engine) & (conv["integrator"] == integrator))
        if len(rows) and np.isfinite(rows["order"][0]):
            return float(rows["order"][0]), "convergence.csv"
    return None, None


def draw(folders, ctx):
    panels = [f for f in folders if available(f)]
    fig, axes = plt.subplots(1, len(panels), figsize=(12, 7.0), squeeze=False,
                             layout="constrained", sharey=True)
    for ax, f in zip(axes[0], panels):
        if f.has("work_precision.csv"):
            _draw_points(ax, f, ctx)
        else:
            _draw_orders(ax, f, ctx)
        if len(panels) > 1:
            ax.set_title(f.label)
    style.title(fig, TITLE, panels, engines_line=style.sweep_line(panels), compare="panels")
    return style.save(fig, ctx.outdir, STEM, ctx.svg)


def _draw_points(ax, f, ctx):
    wp = f.table("work_precision.csv")
    ok = (wp["stable"] >= 0.5) & np.isfinite(wp["error_final"]) & (wp["error_final"] > 0)
    for e, i in style.configs(wp):
        key = style.config_key(e, i)
        m = np.flatnonzero(ok & (wp["engine"] == e) & (wp["integrator"] == i))
        if not len(m):
            continue
        dt, err = wp["dt"][m], wp["error_final"][m]
        order = np.argsort(dt)
        dt, err = dt[order], err[order]
        p, source = fitted_order(f, e, i)
        if p is None and len(dt) >= 2:
            p, source = float(np.polyfit(np.log(dt), np.log(err), 1)[0]), "fitted here"
        color = ctx.colors[key]
        ax.plot(dt, err, marker="o", ms=5, ls="none", color=color)
        if p is not None:
            b = np.mean(np.log(err) - p * np.log(dt))
            line = np.exp(b) * dt ** p
            suffix = "" if source == "convergence.csv" else f", {source}"
            ax.plot(dt, line, color=color, lw=1.5, label=f"{key}: order {p:.2f}{suffix}")
        else:
            ax.plot([], [], color=color, marker="o", label=f"{key}: one point, no fit")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("time step dt (s)")
    ax.set_ylabel("final RMS error vs reference (m)")
    style.legend(ax, loc="lower right", fontsize=style.FONT - 1)


def _draw_orders(ax, f, ctx):
    conv = f.table("convergence.csv")
    keys = [style.config_key(e, i) for e, i in zip(conv["engine"], conv["integrator"])]
    ax.bar(range(len(keys)), conv["order"], color=[ctx.colors[k] for k in keys])
    for k, p in enumerate(conv["order"]):
        ax.text(k, p, f"{p:.2f}", ha="center", va="bottom")
    ax.set_xticks(range(len(keys)), keys, rotation=20, ha="right")
    ax.set_xlabel("engine / integrator")
    ax.set_ylabel("fitted order of convergence (dimensionless)")
