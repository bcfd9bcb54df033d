"""Divergence over time: distance of each engine from the reference engine."""

import matplotlib.pyplot as plt
import numpy as np

from . import style
from .energy import mark_blowup

STEM = "divergence"
TITLE = "Divergence from the reference"
CAPTION = ("Divergence from the reference engine over time: RMS and largest particle-to-particle "
           "distance, distance between the centres of mass, and the differences in total energy "
           "and shadow area (engine minus reference). Rows after a blow-up are left out; the "
           "blow-up time is marked.")

# divergence.csv column, panel title, axis label
PANELS = [
    ("rms_distance", "RMS distance", "RMS distance (m)"),
    ("max_distance", "largest distance", "max distance (m)"),
    ("com_distance", "centre-of-mass distance", "COM distance (m)"),
    ("energy_difference", "total energy difference", "energy difference (J)"),
    ("shadow_area_difference", "shadow area difference", "shadow area difference (m²)"),
]


def available(folder):
    return folder.has("divergence.csv")


def symlog_threshold(peaks, span=20.0):
    """Linear range (J) of a symmetric log axis on which every engine's curve reads, given each
    engine's largest |difference|; None when the peaks span less than `span` (linear is fine)."""
    if len(peaks) < 2 or max(peaks) / min(peaks) <= span:
        return None
    return min(peaks) / 4


def draw(folders, ctx):
    fig = plt.figure(figsize=(12, 8.2), layout="constrained")
    grid = fig.add_gridspec(2, 6)
    axes = [fig.add_subplot(grid[0, 0:2]), fig.add_subplot(grid[0, 2:4]),
            fig.add_subplot(grid[0, 4:6]), fig.add_subplot(grid[1, 0:3]),
            fig.add_subplot(grid[1, 3:6])]
    refs = []
    for ax, (col, name, unit) in zip(axes, PANELS):
        values, peaks = [], []
        for k, f in enumerate(folders):
            if not f.has("divergence.csv"):
                continue
            div = f.table("divergence.csv")
            for engine in div.unique("engine"):
                rows = div.select(engine=engine)
                rows = rows.where(np.argsort(rows["t"], kind="stable"))
                blow = f.blowup(engine)
                if blow is not None and not np.isnan(blow):
                    rows = rows.where(rows["t"] < blow)
                label = engine if len(folders) == 1 else f"{engine} ({f.label})"
                ax.plot(rows["t"], rows[col], color=ctx.colors[engine], ls=style.RUN_STYLES[k],
                        lw=1.5, label=label)
                values.extend(rows[col])
                peak = style.finite(np.abs(rows[col]))
                if len(peak) and peak.max() > 0:
                    peaks.append(float(peak.max()))
                mark_blowup(ax, f, engine, style.RUN_STYLES[k], label=(col == "rms_distance"),
                            name=True)
                for ref in rows["reference"]:
                    if ref not in refs:
                        refs.append(ref)
        if col.endswith("distance") and style.use_log(values):
            ax.set_yscale("log", nonpositive="mask")
        else:
            ax.axhline(0.0, color="0.5", lw=0.8)
        if col == "energy_difference":
            linthresh = symlog_threshold(peaks)
            if linthresh:
                # one engine's peak would flatten the others to zero on a linear axis
                ax.set_yscale("symlog", linthresh=linthresh)
                name = f"{name} (symmetric log axis, linear within ±{style.fmt(linthresh)} J)"
        if col == "shadow_area_difference" and len(style.finite(values)) and \
                not np.any(style.finite(values)):
            # a chain, or a cloth edge-on from above, casts no shadow in any engine
            style.note(ax, "zero throughout: no engine's cloth casts a shadow from above")
        ax.set_title(name)
        ax.set_ylabel(unit)
        ax.set_xlabel("time t (s)")
    style.legend(axes[0], loc="best")
    engines_line = (f"distance of each engine from the reference {', '.join(refs)}; engines: "
                    + ", ".join(e for f in folders for e in f.engines() if e not in refs))
    style.title(fig, TITLE, folders, engines_line=engines_line)
    return style.save(fig, ctx.outdir, STEM, ctx.svg)
