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
           "lower bound. Where the sweep also measured by growth (--method growth or both), the "
           "square is the largest dt at which no small disturbance grows faster than the "
           "physics lets it (the green triangle above it: the first dt where one does), "
           "labelled 'contact' when a state in contact sets it and 'near physics' when the "
           "step grows at most 20 % faster than the physics there (a limit to check against "
           "the blow-up search); its ratio to the prediction is "
           "the square in the bottom panel. The prediction holds for the free scene, so a "
           "limit set by contact may lie below it.")

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


def has_growth(table):
    """True when stability.csv holds a growth limit in some row (a sweep run with --method
    growth or both; older folders have no such column)."""
    return "growth_stable_dt" in table and bool(
        np.any(np.isfinite(table["growth_stable_dt"])
               | np.isfinite(table["growth_first_unstable_dt"])))


def _blowup_ran(rows):
    """False for a row of --method growth, whose blow-up columns are empty by design."""
    return "method" not in rows or rows["method"][0] != "growth"


def _draw_growth(ax, xg, row, hollow, lab, values):
    """The growth limit (square), the first dt where a disturbance grows too fast above it
    (triangle) or an arrow when none did, and 'contact' when a state in contact sets it."""
    meas, fail = row["growth_stable_dt"], row["growth_first_unstable_dt"]
    if not np.isfinite(meas):
        if np.isfinite(fail):
            ax.plot([xg], [fail], marker="^", ms=9, ls="none", color="tab:green",
                    mfc="white" if hollow else "tab:green", mew=2,
                    label=lab("growth: first dt with a growing mode"))
            values.append(fail)
        return
    ax.plot([xg], [meas], marker="s", ms=9, ls="none", color="tab:cyan",
            mfc="white" if hollow else "tab:cyan", mew=2, mec="teal",
            label=lab("growth limit (no disturbance grows too fast)"))
    values.append(meas)
    if np.isfinite(fail):
        ax.plot([xg, xg], [meas, fail], color="0.4", lw=1.2)
        ax.plot([xg], [fail], marker="^", ms=9, ls="none", color="tab:green",
                mfc="white" if hollow else "tab:green", mew=2,
                label=lab("growth: first dt with a growing mode"))
        values.append(fail)
    else:
        ax.annotate("", (xg, meas * 2.0), (xg, meas * 1.12),
                    arrowprops={"arrowstyle": "-|>", "color": "teal", "lw": 1.6})
        values.append(meas * 2.0)
    notes = [word for word, said in
             (("contact", str(row["growth_cause"]).startswith("set by contact")),
              ("near physics", "near the physics" in str(row["growth_cause"]))) if said]
    if notes:
        ax.annotate("\n".join(notes), (xg, meas), xytext=(0, -14), textcoords="offset points",
                    ha="center", va="top", fontsize=style.FONT - 2, color="teal")


def _draw_growth_ratio(ax_r, xr, row, pred, hollow, lab, ratios):
    """growth limit / predicted in the lower panel (a lower bound when nothing grew)."""
    ratio = row["growth_ratio"]
    if not np.isfinite(ratio) and np.isfinite(row["growth_stable_dt"]):
        ratio = row["growth_stable_dt"] / pred
    if not np.isfinite(ratio):
        return
    censored = not np.isfinite(row["growth_first_unstable_dt"])
    ax_r.plot([xr], [ratio], marker="s", ms=8, ls="none", color="tab:cyan", mec="teal",
              mfc="white" if hollow else "tab:cyan", mew=2, label=lab("growth limit / predicted"))
    ax_r.annotate(f"≥ {ratio:.2f}" if censored else f"{ratio:.2f}", (xr, ratio),
                  xytext=(0, 8), textcoords="offset points", ha="center", va="baseline",
                  fontsize=style.FONT - 1, color="teal")
    ratios.append(ratio)


def _draw_folder(axes, f, keys, base, step, hollow, lab, values, ratios):
    """One folder's markers in every engine / integrator's slot: blow-up limit, growth limit
    (when measured) and prediction, side by side."""
    ax, ax_r = axes
    st = f.table("stability.csv")
    growth = has_growth(st)
    for n, (e, i) in enumerate(keys):
        rows = st.where((st["engine"] == e) & (st["integrator"] == i))
        if not len(rows):
            continue
        xm, xg = n + base, n + base + step
        xp = n + base + (2 if growth else 1) * step
        meas, fail = rows["stable_dt"][0], rows["first_unstable_dt"][0]
        pred, ratio = rows["predicted_dt"][0], rows["ratio_measured_to_predicted"][0]
        finite_pred = bool(np.isfinite(pred) and pred > 0)
        if not finite_pred:
            ratio = np.nan  # no finite prediction: nothing to compare with
        elif not np.isfinite(ratio) and np.isfinite(meas):
            ratio = meas / pred
        # no failure up to the largest step tried: measured dt and ratio are lower bounds
        censored = not np.isfinite(fail)
        if _blowup_ran(rows):
            _draw_measured(ax, xm, meas, fail, hollow, lab, values)
        row = next(rows.rows())
        if growth:
            _draw_growth(ax, xg, row, hollow, lab, values)
        _draw_predicted(ax, xp, pred, meas if np.isfinite(meas) else row.get(
            "growth_stable_dt", meas), hollow, lab, values)
        if np.isfinite(ratio):
            # between its two markers, or under the blow-up one when the growth one is beside
            _draw_ratio(ax_r, xm if growth else xm + step / 2, ratio, censored, hollow, lab,
                        ratios)
        if growth and finite_pred:
            _draw_growth_ratio(ax_r, xg, row, pred, hollow, lab, ratios)


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
    # horizontal slots inside each category: (measured, growth, predicted) per folder, the
    # growth slot only when some folder measured it
    slots = 3 if any(has_growth(f.table("stability.csv")) for f in panels) else 2
    step = 0.6 / (slots * len(panels)) if slots == 3 else (0.22 if len(panels) == 1 else 0.16)
    values, ratios = [], []
    for k, f in enumerate(panels):
        base = (-(slots * len(panels) - 1) / 2 + slots * k) * step
        lab = _labeller(f" ({f.label})" if len(panels) > 1 else "")
        _draw_folder((ax, ax_r), f, keys, base, step, k == 1, lab, values, ratios)
    _finish_axes(ax, ax_r, keys, panels, values, ratios)
    style.title(fig, TITLE, panels, engines_line=style.sweep_line(panels, ("stability.csv",)),
                compare="markers")
    return style.save(fig, ctx.outdir, STEM, ctx.svg)
