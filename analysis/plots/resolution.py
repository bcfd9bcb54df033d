"""Resolution: error and cost against the grid size per engine and integrator (resolution.csv)."""

import matplotlib.pyplot as plt
import numpy as np

from . import style

STEM = "resolution"
TITLE = "Grid resolution"
CAPTION = ("Grid resolution (clothbench accuracy --resolutions): the same scene on square grids "
           "of r × r particles with the same size and total mass, every configuration at its "
           "engine's own time step; h is the particle spacing along the cloth's longer side. "
           "Left: final RMS position error against the reference, rk4 on the finest grid at the "
           "smallest time step, measured at common material points; on the finest grid the "
           "error is the time-stepping error alone. Right: wall time per simulated second. Both "
           "log-log; crosses on the dotted line are unstable runs.")


def available(folder):
    return folder.has("resolution.csv")


def side(particles):
    """Particles per side r of an r by r grid of #P particles."""
    return np.sqrt(np.asarray(particles, dtype=float))


def spacing_label(folder, r):
    """Tick text of grid size r: 'r × r' and the spacing along the cloth's longer side (m)."""
    size = folder.scenario.get("cloth", {}).get("size")
    text = f"{int(round(r))} × {int(round(r))}"
    if isinstance(size, list) and len(size) == 2 and r > 1:
        try:
            longest = max(float(v) for v in size)
        except (TypeError, ValueError):
            return text
        if longest > 0:
            text += f"\nh {style.fmt(longest / (r - 1))} m"
    return text


def _draw_folder(axes, k, f, npanels, colors, top):
    """Folder k's error and cost lines, one per engine and integrator (line style k), and its
    unstable grids as crosses at height top; returns (grid sides, whether any was unstable)."""
    ax_e, ax_c = axes
    res = f.table("resolution.csv")
    r = side(res["particles"])
    y = res["error_final"]
    cost = res["wall_s_per_sim_s"]
    ok = (res["stable"] >= 0.5) & np.isfinite(y) & (y > 0)
    ls = style.RUN_STYLES[k]
    mfc = None if k == 0 else "white"
    any_unstable = False
    for e, i in style.configs(res):
        key = style.config_key(e, i)
        color = colors[key]
        label = key if npanels == 1 else f"{key} ({f.label})"
        m = (res["engine"] == e) & (res["integrator"] == i)
        s = np.flatnonzero(m & ok)
        s = s[np.argsort(r[s])]
        ax_e.plot(r[s], y[s], marker=style.RUN_MARKERS[k], ms=6, lw=1.5, ls=ls, color=color,
                  mfc=mfc, label=label)
        u = np.flatnonzero(m & ~ok)
        if len(u):
            any_unstable = True
            ax_e.plot(r[u], np.full(len(u), top), marker="x", ms=8, mew=2, ls="none",
                      color=color)
        c = np.flatnonzero(m & (res["stable"] >= 0.5) & np.isfinite(cost) & (cost > 0))
        c = c[np.argsort(r[c])]
        ax_c.plot(r[c], cost[c], marker=style.RUN_MARKERS[k], ms=6, lw=1.5, ls=ls,
                  color=color, mfc=mfc, label=label)
    return r, any_unstable


def _finish_axes(ax_e, ax_c, panels, sides):
    """Log scales, the grid sizes as ticks, labels, titles and the one legend."""
    for ax in (ax_e, ax_c):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("grid r × r particles, h = spacing (log scale)")
        ax.grid(True, which="minor", alpha=0.12)
    if sides:
        sides.sort()
        ax_e.set_xticks(sides, [spacing_label(panels[0], r) for r in sides])
        ax_e.xaxis.set_minor_formatter(plt.NullFormatter())
        ax_c.xaxis.set_minor_formatter(plt.NullFormatter())
        ax_e.set_xlim(sides[0] / 1.15, sides[-1] * 1.15)
    ax_e.set_ylabel("final RMS error vs finest-grid reference (m)")
    ax_c.set_ylabel("wall time per simulated second (s/s)")
    ax_e.set_title("error against grid size")
    ax_c.set_title("cost against grid size")
    # colours are shared: one legend, right of the cost panel
    handles, labels = ax_e.get_legend_handles_labels()
    ax_c.legend(handles, labels, loc="upper left", bbox_to_anchor=(1.01, 1.0),
                fontsize=style.FONT - 1)


def draw(folders, ctx):
    panels = [f for f in folders if f.has("resolution.csv")]
    fig, (ax_e, ax_c) = plt.subplots(1, 2, figsize=(12, 6.0), sharex=True, layout="constrained")
    errs = np.concatenate([f.table("resolution.csv")["error_final"] for f in panels])
    good = errs[np.isfinite(errs) & (errs > 0)]
    top = good.max() * 6 if len(good) else 1.0
    sides = []
    any_unstable = False
    for k, f in enumerate(panels):
        r, unstable = _draw_folder((ax_e, ax_c), k, f, len(panels), ctx.colors, top)
        sides += [float(v) for v in r if np.isfinite(v) and float(v) not in sides]
        any_unstable = any_unstable or unstable
    if any_unstable:
        ax_e.axhline(top, color="0.5", ls=":", lw=1)
        ax_e.plot([], [], marker="x", ms=8, mew=2, ls="none", color="0.3",
                  label="unstable (no error)")
    _finish_axes(ax_e, ax_c, panels, sides)
    style.title(fig, TITLE, panels, engines_line=style.sweep_line(panels, ("resolution.csv",)),
                compare="lines")
    return style.save(fig, ctx.outdir, STEM, ctx.svg)
