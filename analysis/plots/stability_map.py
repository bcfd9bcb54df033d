"""Stability map (`clothbench map`): the largest stable time step over one or two varied keys.

One varied key: stable dt against the key, log-log, the measured points over the predicted
curve, one colour per engine and integrator. Two: one heat map of the measured limit per
engine and integrator, with the predicted limit's contours at the colour bar's levels.
"""

import math

import matplotlib.pyplot as plt
import numpy as np

from . import style

STEM = "stability_map"
TITLE = "Stability map"
CAPTION = ("Largest stable time step over the varied scenario keys (map.csv). One key: measured "
           "(circles; hollow where nothing failed up to the largest step tried, a lower bound) "
           "over the prediction of linear theory (line), log-log. Two keys: a heat map of the "
           "measured limit per engine and integrator (grey: no stable step found) with the "
           "predicted limit's contours, labelled in seconds, at the colour bar's levels.")

STABILITY_COLUMNS = ("engine", "integrator", "stable_dt", "first_unstable_dt", "predicted_dt")


def available(folder):
    return folder.has("map.csv")


def varied_keys(table):
    """The varied key columns of map.csv: those before 'engine'."""
    return table.order[:table.order.index("engine")]


def _numbers(values):
    """The values as floats, or None when one is not a number (a categorical key)."""
    try:
        return np.array([float(v) for v in values])
    except ValueError:
        return None


def skip_reason(folders):
    for f in folders:
        if f.has("map.csv") and len(varied_keys(f.table("map.csv"))) not in (1, 2):
            return "map.csv varies neither one nor two keys"
    return None


def _positions(values):
    """x positions and tick labels of a key's values: the numbers, or indices for words."""
    unique = list(dict.fromkeys(values))
    nums = _numbers(unique)
    if nums is None:
        index = {v: k for k, v in enumerate(unique)}
        return np.array([index[v] for v in values], dtype=float), unique
    return np.array([float(v) for v in values]), None


def _draw_one_key(ax, table, key, colors):
    x_all, labels = _positions(list(table[key]))
    for e, i in style.configs(table):
        mask = (table["engine"] == e) & (table["integrator"] == i)
        x, meas = x_all[mask], table["stable_dt"][mask]
        pred, fail = table["predicted_dt"][mask], table["first_unstable_dt"][mask]
        order = np.argsort(x)
        c = colors[style.config_key(e, i)]
        finite_pred = np.isfinite(pred[order]) & (pred[order] > 0)
        if finite_pred.any():
            ax.plot(x[order][finite_pred], pred[order][finite_pred], "-", color=c, lw=1.6,
                    label=f"{style.config_key(e, i)} predicted")
        bound = ~np.isfinite(fail)
        ax.plot(x[~bound], meas[~bound], "o", ms=8, color=c, ls="none",
                label=f"{style.config_key(e, i)} measured")
        if bound.any():
            ax.plot(x[bound], meas[bound], "o", ms=8, mfc="white", mec=c, mew=2, ls="none",
                    label=f"{style.config_key(e, i)} lower bound")
    if labels is None and style.use_log(x_all, span=3.0):
        ax.set_xscale("log")
    elif labels is not None:
        ax.set_xticks(range(len(labels)), labels)
    ax.set_yscale("log")
    ax.set_xlabel(key)
    ax.set_ylabel("largest stable dt (s)")
    style.legend(ax, fontsize=style.FONT - 2, loc="best", ncol=2)


def _grid(table, mask, keys, column):
    """The column as a 2-D array over the two keys' values (rows: second key)."""
    xs = list(dict.fromkeys(table[keys[0]]))
    ys = list(dict.fromkeys(table[keys[1]]))
    z = np.full((len(ys), len(xs)), np.nan)
    for a, b, v in zip(table[keys[0]][mask], table[keys[1]][mask], table[column][mask]):
        z[ys.index(b), xs.index(a)] = v
    return xs, ys, z


def _axis(values):
    nums = _numbers(values)
    return (nums, None) if nums is not None else (np.arange(len(values), dtype=float), values)


def _draw_heat(ax, fig, table, keys, e, i):
    mask = (table["engine"] == e) & (table["integrator"] == i)
    xs, ys, meas = _grid(table, mask, keys, "stable_dt")
    pred = _grid(table, mask, keys, "predicted_dt")[2]
    x, xl = _axis(xs)
    y, yl = _axis(ys)
    log_meas = np.log10(np.where(meas > 0, meas, np.nan))
    cmap = plt.get_cmap("viridis").copy()
    cmap.set_bad("0.8")
    mesh = ax.pcolormesh(x, y, np.ma.masked_invalid(log_meas), cmap=cmap, shading="nearest")
    bar = fig.colorbar(mesh, ax=ax)
    bar.set_label("log10 measured stable dt (s)")
    finite = np.isfinite(pred) & (pred > 0)
    if finite.sum() >= 4 and len(xs) > 1 and len(ys) > 1 and np.isfinite(log_meas).any():
        levels = bar.get_ticks()
        cs = ax.contour(x, y, np.log10(np.where(finite, pred, np.nan)), levels=levels,
                        colors="white", linewidths=1.4, linestyles="solid")
        ax.clabel(cs, fmt=lambda v: f"{10 ** v:.2g}", fontsize=style.FONT - 3)
    for values, axis, labels, setter in ((x, ax.xaxis, xl, ax.set_xscale),
                                         (y, ax.yaxis, yl, ax.set_yscale)):
        if labels is not None:
            axis.set_ticks(range(len(labels)), labels)
        elif style.use_log(values, span=3.0):
            setter("log")
    ax.set_xlabel(keys[0])
    ax.set_ylabel(keys[1])
    ax.set_title(style.config_key(e, i), fontsize=style.FONT)


def draw(folders, ctx):
    panels = [f for f in folders if f.has("map.csv")]
    f = panels[0]  # a map is drawn for the first folder (--compare maps are not overlaid)
    table = f.table("map.csv")
    keys = varied_keys(table)
    if len(keys) == 1:
        fig, ax = plt.subplots(figsize=(11, 7), layout="constrained")
        _draw_one_key(ax, table, keys[0], ctx.colors)
    else:
        configs = style.configs(table)
        cols = min(3, len(configs))
        rows = math.ceil(len(configs) / cols)
        fig, axes = plt.subplots(rows, cols, figsize=(5.2 * cols, 4.4 * rows + 1),
                                 layout="constrained", squeeze=False)
        for ax, (e, i) in zip(axes.flat, configs):
            _draw_heat(ax, fig, table, keys, e, i)
        for ax in list(axes.flat)[len(configs):]:
            ax.set_visible(False)
    style.title(fig, TITLE, [f], engines_line=style.sweep_line([f], ("map.csv",)))
    return style.save(fig, ctx.outdir, STEM, ctx.svg)
