"""Reference: where each accuracy study's reference sits against the runs it judges
(reference.csv, with work_precision.csv and resolution.csv)."""

import matplotlib.pyplot as plt
import numpy as np

from . import style

STEM = "reference"
TITLE = "Accuracy reference"
CAPTION = ("Accuracy reference (reference.csv): every error of an accuracy sweep is a distance "
           "from a reference solution, rk4 on the custom engine. Left, the time-step study: the "
           "largest error of every stable run against its dt, with the reference's dt (star) "
           "at its error floor, the distance between the reference and the same rk4 run at "
           "half its step; an error near the floor is not resolved. Right, the resolution study: "
           "final errors against the particle count, with the reference's grid (star, on the "
           "axis: it is its own reference). Log-log.")


def available(folder):
    return folder.has("reference.csv")


def _study(refs, name):
    rows = refs.where(refs["study"] == name)
    return rows if len(rows) else None


def draw(folders, ctx):
    panels = [f for f in folders if available(f)]
    fig, axes = plt.subplots(len(panels), 2, figsize=(12, 5.5 * len(panels)), squeeze=False,
                             layout="constrained")
    for (ax_dt, ax_res), f in zip(axes, panels):
        refs = f.table("reference.csv")
        _draw_dt(ax_dt, f, _study(refs, "dt"), ctx)
        _draw_resolution(ax_res, f, _study(refs, "resolution"), ctx)
        if len(panels) > 1:
            ax_dt.set_title(f"{f.label}: time-step study")
            ax_res.set_title(f"{f.label}: resolution study")
    style.title(fig, TITLE, panels, engines_line=style.sweep_line(panels, ("reference.csv",)),
                compare="panels")
    return style.save(fig, ctx.outdir, STEM, ctx.svg)


def _draw_dt(ax, f, ref, ctx):
    ax.set_title("time-step study")
    if f.has("work_precision.csv"):
        wp = f.table("work_precision.csv")
        ok = (wp["stable"] >= 0.5) & np.isfinite(wp["error_max"]) & (wp["error_max"] > 0)
        for e, i in style.configs(wp):
            key = style.config_key(e, i)
            m = np.flatnonzero(ok & (wp["engine"] == e) & (wp["integrator"] == i))
            if len(m):
                ax.plot(wp["dt"][m], wp["error_max"][m], marker="o", ms=5, ls="none",
                        color=ctx.colors[key], label=key)
    if ref is None:
        style.note(ax, "no time-step reference in reference.csv")
        return
    dt = float(ref["dt"][0])
    floor = float(ref["error_floor"][0])
    if np.isfinite(floor) and floor > 0:
        ax.plot([dt], [floor], marker="*", ms=16, ls="none", color="black",
                label=f"reference rk4 at dt = {style.fmt(dt)} s, floor {floor:.2g} m")
        ax.axhline(floor, color="0.4", ls=":", lw=1)
    else:
        ax.axvline(dt, color="black", ls=":", lw=1.5, label=f"reference dt = {style.fmt(dt)} s")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("time step dt (s)")
    ax.set_ylabel("largest RMS error vs reference (m)")
    style.legend(ax, loc="lower right", fontsize=style.FONT - 1)


def _draw_resolution(ax, f, ref, ctx):
    ax.set_title("resolution study")
    if ref is None:
        style.note(ax, "no resolution study (accuracy --resolutions)")
        return
    if f.has("resolution.csv"):
        res = f.table("resolution.csv")
        ok = (res["stable"] >= 0.5) & np.isfinite(res["error_final"]) & (res["error_final"] > 0)
        for e, i in style.configs(res):
            key = style.config_key(e, i)
            m = np.flatnonzero(ok & (res["engine"] == e) & (res["integrator"] == i))
            if len(m):
                ax.plot(res["particles"][m], res["error_final"][m], marker="o", ms=5, lw=1,
                        color=ctx.colors[key], label=key)
    n = float(ref["particles"][0])
    dt = float(ref["dt"][0])
    ax.axvline(n, color="black", ls=":", lw=1.5,
               label=f"reference: rk4 on {int(n)} particles at dt = {style.fmt(dt)} s")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("particles (log scale)")
    ax.set_ylabel("final RMS error vs reference (m)")
    style.legend(ax, loc="lower left", fontsize=style.FONT - 1)
