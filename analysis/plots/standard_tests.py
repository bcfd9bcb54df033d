"""The textile standard test's metrics (tests.csv): one bar chart per metric, a bar per engine."""

import math

import matplotlib.pyplot as plt
import numpy as np

from . import style

STEM = "tests"
TITLE = "Standard test metrics"
CAPTION = ("The scenario's textile standard test measured on every engine's final state "
           "(tests.csv), one panel per metric with a bar per engine and its value. For the "
           "cantilever: the chord angle below the horizontal from the last held column to the "
           "tip, the tip's drop, the overhang, the bending length c of the heavy elastica with "
           "that chord angle at that overhang, Peirce's c, and the flexural rigidity "
           "areal weight × c³. An engine without a value (it blew up, or its chord angle is "
           "outside the elastica's range) is marked \"no value\".")

COLUMNS = 3


def available(folder):
    return folder.has("tests.csv")


def metrics(folder):
    """[(metric, unit, {engine: value})] in the order tests.csv lists them (NaN: no value)."""
    table = folder.table("tests.csv")
    out = []
    for metric in table.unique("metric"):
        rows = list(table.select(metric=metric).rows())
        values = {str(r["engine"]): float(r["value"]) for r in rows}
        out.append((str(metric), str(rows[0]["unit"]), values))
    return out


def _bars(ax, metric, unit, values, colors, engines):
    """One metric's panel: horizontal bars per engine, the value written beside each."""
    y = np.arange(len(engines))
    finite = [v for v in values.values() if math.isfinite(v)]
    top = max((abs(v) for v in finite), default=1.0) or 1.0
    for k, e in enumerate(engines):
        v = values.get(e, math.nan)
        if math.isfinite(v):
            ax.barh(k, v, color=colors[e], alpha=0.8)
            ax.text(v + 0.02 * top, k, f"{v:.4g}", va="center", fontsize=style.FONT - 1)
        else:
            ax.text(0.02 * top, k, "no value", va="center", fontsize=style.FONT - 1, color="0.4")
    ax.set_yticks(y)
    ax.set_yticklabels(engines, fontsize=style.FONT - 1)
    ax.invert_yaxis()
    ax.set_xlim(min(0.0, min(finite, default=0.0)) * 1.3, top * 1.35)
    ax.set_title(f"{metric} ({unit})", fontsize=style.FONT)
    ax.grid(axis="x", alpha=0.3)


def draw(folders, ctx):
    panels = [f for f in folders if f.has("tests.csv")]
    rows = [(f, m) for f in panels for m in metrics(f)]
    n = len(rows)
    cols = min(COLUMNS, n)
    lines = (n + cols - 1) // cols
    engines_per = max(len(values) for _, (_, _, values) in rows)
    fig, axes = plt.subplots(lines, cols, figsize=(13, 1.2 + lines * (0.9 + 0.32 * engines_per)),
                             squeeze=False, layout="constrained")
    for ax, (f, (metric, unit, values)) in zip(axes.flat, rows):
        engines = list(f.table("tests.csv").unique("engine"))
        _bars(ax, metric, unit, values, ctx.colors, engines)
        if len(panels) > 1:
            ax.set_title(f"{f.label}: {metric} ({unit})", fontsize=style.FONT)
    for ax in list(axes.flat)[n:]:
        ax.set_axis_off()
    style.title(fig, TITLE, folders, compare="labelled")
    return style.save(fig, ctx.outdir, STEM, ctx.svg)
