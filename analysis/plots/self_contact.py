"""Self-intersection over time: crossings and the smallest gap between layers, per engine."""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import MaxNLocator

from . import style
from .energy import frame_engines, mark_blowup

STEM = "self_contact"
TITLE = "Self-intersection over time"
CAPTION = ("Left: edge-triangle crossings of the cloth with itself per frame (an edge that passes "
           "through a triangle it shares no vertex with, decided with exact predicates; two "
           "triangles that pass through each other usually count 2). Every engine is measured "
           "the same way, from its positions alone. Right: the smallest vertex-triangle or "
           "edge-edge distance between parts of the cloth more than two rings apart, capped at "
           "half the mean rest edge length; near 0 where layers meet.")


def available(folder):
    return folder.has("frames.csv") and "self_intersections" in folder.table("frames.csv")


def _engine_rows(folders, engines):
    """(folder index, folder, engine, rows sorted by t) for every engine with frames."""
    for k, f in enumerate(folders):
        if not available(f):
            continue
        frames = f.table("frames.csv")
        for engine in engines:
            rows = frames.select(engine=engine)
            if len(rows):
                yield k, f, engine, rows.where(np.argsort(rows["t"], kind="stable"))


def draw(folders, ctx):
    engines = frame_engines(folders)
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.6), layout="constrained")
    gaps = []
    for k, f, engine, rows in _engine_rows(folders, engines):
        ls = style.RUN_STYLES[k]
        color = ctx.colors[engine]
        label = engine if len(folders) == 1 else f"{engine} ({f.label})"
        axes[0].plot(rows["t"], rows["self_intersections"], color=color, ls=ls, lw=1.5,
                     label=label, drawstyle="steps-post")
        axes[1].plot(rows["t"], rows["min_self_distance"], color=color, ls=ls, lw=1.5,
                     label=label)
        gaps.extend(rows["min_self_distance"])
        for ax in axes:
            mark_blowup(ax, f, engine, ls, label=False)
    axes[0].set_title("crossings")
    axes[0].set_ylabel("edge-triangle crossings (count)")
    # whole numbers from 0 up, even when no engine crossed (all zero: no negative counts)
    axes[0].set_ylim(bottom=-0.5, top=max(1.0, axes[0].get_ylim()[1]))
    axes[0].yaxis.set_major_locator(MaxNLocator(integer=True))
    axes[1].set_title("smallest distance between layers")
    axes[1].set_ylabel("distance (m)")
    if np.any(style.finite(gaps) > 0) and style.use_log(gaps):
        axes[1].set_yscale("log", nonpositive="mask")
    for ax in axes:
        ax.set_xlabel("time t (s)")
        style.legend(ax, loc="best")
    style.title(fig, TITLE, folders)
    return style.save(fig, ctx.outdir, STEM, ctx.svg)
