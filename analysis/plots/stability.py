"""Stability: measured against predicted largest stable time step per engine and integrator."""

import matplotlib.pyplot as plt
import numpy as np

from . import style
from ..verdicts import STABILITY_GOAL

STEM = "stability"
TITLE = "Stability limits"
CAPTION = ("Largest stable time step per engine and integrator. Top: measured (circle; the red "
           "triangle above it is the first failing time step) beside the prediction from the "
           "linearised scene's extreme eigenvalues (diamond); an arrow means no failure up to the "
           "largest step tried, so the measured step is a lower bound. An integrator that is "
           "unconditionally stable in linear theory (predicted dt infinite) is labelled so. "
           "Bottom: measured / predicted, with the ±10 % band shaded; an upward arrow marks a "
           "lower bound.")

GOAL = STABILITY_GOAL  # relative agreement asked for on scenes without contact (the ±10 % band)


def available(folder):
    return folder.has("stability.csv")


def _keys(panels):
    keys = []
    for f in panels:
        for e, i in style.configs(f.table("stability.csv")):
            if (e, i) not in keys:
                keys.append((e, i))
    return keys


def _labeller(suffix):
    """lab(what): the legend label of what the first time it is asked for, then None."""
    labelled = set()

    def lab(what):
        if what in labelled:
            return None
        labelled.add(what)
        return what + suffix
    return lab


def _draw_measured(ax, xm, meas, fail, hollow, lab, values):
    """The measured stable dt (circle), the first failing dt above it (triangle) or an arrow
    when nothing failed; 'never stable' without a measured dt."""
    if not np.isfinite(meas):
        ax.text(xm, 0.5, "never stable", rotation=90, ha="center", va="center",
                transform=ax.get_xaxis_transform(), color="tab:red")
        return
    ax.plot([xm], [meas], marker="o", ms=10, ls="none", color="tab:blue",
            mfc="white" if hollow else "tab:blue", mew=2,
            label=lab("measured stable dt"))
    values.append(meas)
    if np.isfinite(fail):
        ax.plot([xm, xm], [meas, fail], color="0.4", lw=1.2)
        ax.plot([xm], [fail], marker="v", ms=9, ls="none", color="tab:red",
                mfc="white" if hollow else "tab:red", mew=2,
                label=lab("first unstable dt"))
        values.append(fail)
    else:
        ax.annotate("", (xm, meas * 2.0), (xm, meas * 1.12),
                    arrowprops={"arrowstyle": "-|>", "color": "tab:blue", "lw": 1.6})
        values.append(meas * 2.0)


def _draw_predicted(ax, xp, pred, meas, hollow, lab, values):
    """The predicted stable dt (diamond), or why there is none."""
    if np.isfinite(pred):
        ax.plot([xp], [pred], marker="D", ms=9, ls="none",
                mfc="white" if hollow else "none",
                mec="tab:orange", mew=2.2, label=lab("predicted largest stable dt"))
        values.append(pred)
    elif np.isfinite(meas):
        unconditional = np.isinf(pred) and pred > 0
        text = "unconditionally stable\n(linear theory: no limit)" if unconditional \
            else "no prediction"
        ax.annotate(text, (xp, meas), ha="center", va="center", rotation=90,
                    fontsize=style.FONT - 1,
                    color="tab:orange" if unconditional else "0.45")


def _draw_ratio(ax_r, xr, ratio, censored, hollow, lab, ratios):
    """measured / predicted in the lower panel, with an upward arrow for a lower bound."""
    ax_r.plot([xr], [ratio], marker="o" if not hollow else "s", ms=8,
              ls="none", color="tab:purple", mfc="white" if hollow else "tab:purple",
              mew=2, label=lab("measured / predicted"))
    if censored:
        ax_r.annotate("", (xr, ratio + 0.12), (xr, ratio + 0.02),
                      arrowprops={"arrowstyle": "-|>", "color": "tab:purple",
                                  "lw": 1.6})
        ax_r.plot([], [], marker="$\\uparrow$", ms=10, ls="none", color="tab:purple",
                  label=lab("lower bound (no failure up to the largest dt)"))
    ax_r.annotate(f"≥ {ratio:.2f}" if censored else f"{ratio:.2f}", (xr, ratio),
                  xytext=(10, 0) if censored else (0, 8), textcoords="offset points",
                  ha="left" if censored else "center",
                  va="center" if censored else "baseline",
                  fontsize=style.FONT - 1)
    ratios.append(ratio)
    if censored:
        ratios.append(ratio + 0.12)


def _draw_folder(axes, f, keys, base, step, hollow, lab, values, ratios):
    """One folder's markers in every engine / integrator's slot."""
    ax, ax_r = axes
    st = f.table("stability.csv")
    for n, (e, i) in enumerate(keys):
        rows = st.where((st["engine"] == e) & (st["integrator"] == i))
        if not len(rows):
            continue
        xm, xp = n + base, n + base + step
        meas, fail = rows["stable_dt"][0], rows["first_unstable_dt"][0]
        pred, ratio = rows["predicted_dt"][0], rows["ratio_measured_to_predicted"][0]
        if not (np.isfinite(pred) and pred > 0):
            ratio = np.nan  # no finite prediction: nothing to compare with
        elif not np.isfinite(ratio) and np.isfinite(meas):
            ratio = meas / pred
        # no failure up to the largest step tried: measured dt and ratio are lower bounds
        censored = not np.isfinite(fail)
        _draw_measured(ax, xm, meas, fail, hollow, lab, values)
        _draw_predicted(ax, xp, pred, meas, hollow, lab, values)
        if np.isfinite(ratio):
            _draw_ratio(ax_r, n + base + step / 2, ratio, censored, hollow, lab, ratios)


def _finish_axes(ax, ax_r, keys, panels, values, ratios):
    """Scales, limits, labels and legends of both panels."""
    ax.set_yscale("log")
    if values:
        ax.set_ylim(min(values) / 2.0, max(values) * 2.5)
    ax.set_xlim(-0.6, len(keys) - 0.4)
    ax.set_ylabel("time step dt (s)")
    style.legend(ax, loc="upper left", ncol=2 if len(panels) > 1 else 1)
    ax_r.axhspan(1 - GOAL, 1 + GOAL, color="tab:green", alpha=0.12, label="±10 %")
    ax_r.axhline(1.0, color="0.4", lw=1)
    lo = min(ratios + [1 - GOAL]) - 0.1
    hi = max(ratios + [1 + GOAL]) + 0.15
    ax_r.set_ylim(lo, hi)
    ax_r.set_ylabel("measured / predicted (ratio)")
    ax_r.set_xticks(range(len(keys)), [style.config_key(e, i) for e, i in keys], rotation=15,
                    ha="right")
    ax_r.set_xlabel("engine / integrator")
    style.legend(ax_r, loc="best", ncol=3)


def draw(folders, ctx):
    panels = [f for f in folders if f.has("stability.csv")]
    keys = _keys(panels)
    fig, (ax, ax_r) = plt.subplots(2, 1, figsize=(12, 8.4), sharex=True, layout="constrained",
                                   gridspec_kw={"height_ratios": [2.6, 1]})
    # horizontal slots inside each category: (measured, predicted) per folder
    step = 0.22 if len(panels) == 1 else 0.16
    values, ratios = [], []
    for k, f in enumerate(panels):
        base = -step / 2 if len(panels) == 1 else (-1.5 + 2 * k) * step
        lab = _labeller(f" ({f.label})" if len(panels) > 1 else "")
        _draw_folder((ax, ax_r), f, keys, base, step, k == 1, lab, values, ratios)
    _finish_axes(ax, ax_r, keys, panels, values, ratios)
    style.title(fig, TITLE, panels, engines_line=style.sweep_line(panels, ("stability.csv",)),
                compare="markers")
    return style.save(fig, ctx.outdir, STEM, ctx.svg)
