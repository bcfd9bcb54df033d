"""The report's verdicts in words: stability, energy, divergence, drape, sweeps, and changes.

Each function returns a list of (heading, [(kind, text), ...]) where kind is "ok", "bad" or
"info" (how the page colours the line). Text is plain (the page escapes it).
"""

import math
import re

import numpy as np

from .attribution import attribution_verdicts
from .quantities import length, num


def _finite(v):
    return isinstance(v, (int, float)) and math.isfinite(v)


def _sorted_rows(table, engine):
    rows = table.select(engine=engine)
    return rows.where(np.argsort(rows["t"], kind="stable"))


# --- one run --------------------------------------------------------------------------------

def _force_evals_text(n, kind):
    """How many force evaluations a run made, as the cost line says it: Bullet engines do not
    count theirs (their summary holds 0), so theirs are "not counted", never "0"."""
    if kind.startswith("bullet") or (_finite(n) and n == 0 and kind != "custom"):
        return " (force evaluations not counted)"
    return f" ({int(n)} force evaluations)" if _finite(n) else ""


def _stability_lines(f, engines, duration):
    lines = []
    if f.has("summary.csv") or f.has("frames.csv"):
        for e in engines:
            t = f.blowup(e)
            if t is None:
                span = f" ({num(float(duration))} s simulated)" if _finite(duration) else ""
                lines.append(("ok", f"{e}: stable for the whole run{span}."))
            else:
                when = f"at t = {num(t)} s" if _finite(t) else "(time unknown)"
                lines.append(("bad", f"{e}: UNSTABLE, blew up {when}: the largest stretch passed "
                              f"{num(f.blowup_strain())} or a coordinate became non-finite; its "
                              f"results stop there."))
    return lines


def energy_scale(rows):
    """The most energy a run moves (J): its largest kinetic energy, or change in gravity or
    elastic potential since the start. Unlike the initial total energy it does not depend on
    where a potential's zero lies (a cloth on a floor at y = 0 has almost none)."""
    if not len(rows):
        return math.nan
    moved = [np.abs(rows["kinetic"])]
    for name in ("gravity_potential", "elastic_potential"):
        moved.append(np.abs(rows[name] - rows[name][0]))
    values = np.concatenate(moved)
    values = values[np.isfinite(values)]
    return float(values.max()) if len(values) else math.nan


def _energy_line(f, frames, e):
    """The energy line of engine e from frames.csv, or None (no finite error)."""
    gated, note = f.energy_gated(e)
    if not gated:
        # run.json says why (for a position-based soft body: no spring damper, its
        # dissipated column is each step's energy balance)
        return ("info", f"{e}: no energy check: its energy error is {note}.")
    rows = _sorted_rows(frames, e)
    rows = rows.where(rows["stable"] >= 0.5)
    err = np.abs(rows["energy_error"])
    err = err[np.isfinite(err)]
    if not len(err):
        return None
    scale = energy_scale(rows)
    rel = f" ({num(100 * err.max() / scale, 2)} % of {num(scale)} J, the most energy the run " \
          "moves)" if _finite(scale) and scale > 0 else ""
    until = "" if f.blowup(e) is None else " before the blow-up"
    return ("info", f"{e}: energy error at most {num(float(err.max()))} J{rel}{until}.")


def _energy_lines(f, engines):
    lines = []
    if f.has("frames.csv"):
        frames = f.table("frames.csv")
        lines = [line for line in (_energy_line(f, frames, e) for e in engines) if line]
    elif f.has("summary.csv"):
        for row in f.table("summary.csv").rows():
            if _finite(row["max_energy_error"]):
                lines.append(("info", f"{row['engine']}: energy error at most "
                              f"{num(abs(row['max_energy_error']))} J."))
    return lines


def _divergence_line(f, div, e):
    """The divergence line of engine e from divergence.csv."""
    rows = _sorted_rows(div, e)
    ref = rows["reference"][0]
    blow = f.blowup(e)
    if blow is not None and _finite(blow):
        rows = rows.where(rows["t"] < blow)
    rms = rows["rms_distance"]
    if not len(rows) or not np.any(np.isfinite(rms)):
        return ("bad", f"{e} vs {ref}: no finite distance before the blow-up.")
    k = int(np.nanargmax(rms))
    end = "before the blow-up" if blow is not None else "at the end"
    return ("info", f"{e} vs {ref}: RMS distance {length(float(rms[-1]))} {end} "
                    f"(t = {num(float(rows['t'][-1]))} s), at most {length(float(rms[k]))} "
                    f"(t = {num(float(rows['t'][k]))} s); largest particle distance at most "
                    f"{length(float(np.nanmax(rows['max_distance'])))}; centres of mass "
                    f"{length(float(rows['com_distance'][-1]))} apart {end}.")


def _divergence_lines(f):
    lines = []
    if f.has("divergence.csv"):
        div = f.table("divergence.csv")
        lines = [_divergence_line(f, div, e) for e in div.unique("engine")]
    elif f.has("summary.csv"):
        ref = f.reference()
        for row in f.table("summary.csv").rows():
            if row["engine"] != ref and _finite(row["final_rms_vs_reference"]):
                lines.append(("info", f"{row['engine']} vs {ref}: final RMS distance "
                              f"{length(row['final_rms_vs_reference'])}, at most "
                              f"{length(row['max_rms_vs_reference'])}."))
    return lines


def _drape_and_cost_lines(f):
    lines = []
    if not f.has("summary.csv"):
        return lines
    coeffs = [(r["engine"], r["drape_coefficient"]) for r in f.table("summary.csv").rows()
              if _finite(r["drape_coefficient"])]
    if coeffs:
        values = [c for _, c in coeffs]
        text = "Drape coefficients: " + ", ".join(f"{e} {c:.3f}" for e, c in coeffs)
        if len(values) > 1:
            text += f" (spread {max(values) - min(values):.3f})"
        if f.mesh_faces() is None:
            # a grid's square cloth, not the Cusick test's disk specimen
            text += "; a grid approximation of the Cusick test"
        lines.append(("info", text + "."))
    cost = [(r["engine"], r["us_per_step"], r["force_evals"], str(r.get("kind", "")))
            for r in f.table("summary.csv").rows() if _finite(r["us_per_step"])]
    if cost:
        lines.append(("info", "Cost per step: " + ", ".join(
            f"{e} {num(us)} µs" + _force_evals_text(n, kind)
            for e, us, n, kind in cost) + "."))
    return lines


def _self_collision_text(state):
    """What the engine's self-collision was, as a parenthesis after its name."""
    return {"on": " (self-contact on)", "off": " (self-contact off)",
            "not available": " (self-contact not available in this engine)"}.get(state, "")


def _layer_lines(f, engines):
    """Which engines let the cloth pass through itself (frames.csv's self_intersections), and
    how close the layers of the others came; nothing for runs written before it was measured."""
    if not f.has("frames.csv") or "self_intersections" not in f.table("frames.csv"):
        return []
    frames = f.table("frames.csv")
    thickness = f.scenario.get("cloth", {}).get("thickness")
    crossed, lines = [], []
    for e in engines:
        rows = _sorted_rows(frames, e)
        counts = rows["self_intersections"]
        seen = np.isfinite(counts)
        if not np.any(seen):
            continue
        name = e + _self_collision_text(f.self_collision(e))
        if np.any(counts[seen] > 0):
            first = rows["t"][seen][counts[seen] > 0][0]
            worst = int(counts[seen].max())
            last = counts[seen][-1]
            crossed.append(e)
            lines.append(("bad", f"{name}: LAYERS CROSSED from t = {num(first)} s: up to {worst} "
                          f"edge-triangle crossings in a frame, {int(last)} in its last measured "
                          "frame."))
        else:
            gap = rows["min_self_distance"][seen]
            gap = gap[np.isfinite(gap)]
            closest = ""
            if len(gap):
                touch = " (layers touching, none crossing)" if gap.min() == 0 else ""
                closest = f"; closest approach {length(float(gap.min()))}{touch}"
                if f.self_collision(e) == "on" and thickness:
                    share = float(np.mean(gap >= 0.5 * thickness))
                    closest += (f"; {100 * share:.0f} % of frames at or above half the thickness "
                                f"({length(0.5 * float(thickness))})")
            lines.append(("ok", f"{name}: no crossing in any frame{closest}."))
    if crossed:
        lines.insert(0, ("bad", "Engines that let the cloth pass through itself: "
                         + ", ".join(crossed) + "."))
    return lines


def run_verdicts(f):
    """Verdicts of one run folder (any of frames, divergence, summary, snapshots)."""
    engines = f.engines()
    groups = [("Stability", _stability_lines(f, engines, f.scenario.get("duration"))),
              ("Energy", _energy_lines(f, engines)),
              ("Divergence from the reference", _divergence_lines(f)),
              ("Layers (self-intersection)", _layer_lines(f, engines)),
              ("Drape and cost", _drape_and_cost_lines(f))]
    groups = [(heading, lines) for heading, lines in groups if lines]
    return groups + [g for g in [attribution_verdicts(f)] if g]


def compare_verdicts(a, b):
    """What changed from folder a to folder b, engine by engine."""
    lines = []
    ea, eb = a.engines(), b.engines()
    for e in ea:
        if e not in eb:
            lines.append(("info", f"{e}: only in {a.label}."))
            continue
        ta, tb = a.blowup(e), b.blowup(e)
        if (ta is None) != (tb is None):
            became = "stable" if tb is None else f"unstable (blew up at t = {num(tb)} s)"
            was = "stable" if ta is None else f"unstable (blew up at t = {num(ta)} s)"
            lines.append(("ok" if tb is None else "bad",
                          f"{e}: {was} in {a.label}, {became} in {b.label}."))
        elif ta is not None:
            lines.append(("bad", f"{e}: unstable in both (blew up at t = {num(ta)} s in {a.label}, "
                          f"t = {num(tb)} s in {b.label})."))
        else:
            lines.append(("ok", f"{e}: stable in both."))
        if ta is not None or tb is not None:
            continue  # numbers of a run that blew up do not compare with a finished one
        ia, ib = a.engine_info(e), b.engine_info(e)
        for col, what, fmt in (
                ("final_rms_vs_reference", "final RMS distance from the reference", length),
                ("max_energy_error", "largest energy error", lambda x: f"{num(x)} J"),
                ("drape_coefficient", "drape coefficient", lambda x: f"{x:.3f}")):
            va, vb = ia.get(col, math.nan), ib.get(col, math.nan)
            if _finite(va) and _finite(vb) and (va != 0 or vb != 0):
                pct = 100 * (vb - va) / abs(va) if va != 0 else math.nan
                change = "" if math.isnan(pct) else \
                    f" ({pct:+.1f} %)" if abs(pct) < 10 else f" ({pct:+.0f} %)"
                lines.append(("info", f"{e}: {what} {fmt(va)} → {fmt(vb)}{change}."))
    for e in eb:
        if e not in ea:
            lines.append(("info", f"{e}: only in {b.label}."))
    return [(f"Changes from {a.label} to {b.label}", lines)] if lines else []


# --- sweeps ---------------------------------------------------------------------------------

def _key(engine, integrator):
    return f"{engine} / {integrator}" if integrator else str(engine)


STABILITY_GOAL = 0.10  # relative agreement asked of measured and predicted stable time steps


def stability_agreement(measured, predicted, ratio, censored):
    """(kind, text) comparing one measured stable dt (s) with linear theory's prediction.

    predicted  s; inf: unconditionally stable in linear theory; NaN: no theory (Bullet)
    ratio      measured / predicted from the CSV, or NaN (then computed here)
    censored   True when the search stopped at the largest dt tried without a failure, so
               the measured dt, and the ratio, are lower bounds
    """
    if isinstance(predicted, float) and math.isinf(predicted) and predicted > 0:
        theory = "; unconditionally stable in linear theory (predicted dt infinite)"
        if censored:
            return "ok", theory + ", which agrees"
        return "bad", theory + ", yet a larger step failed"
    if not _finite(predicted) or predicted <= 0:
        return "info", "; no predicted limit"
    if not _finite(ratio):
        ratio = measured / predicted
    text = f"; predicted {num(predicted)} s, measured / predicted "
    if censored:
        if ratio > 1.0 + STABILITY_GOAL:
            return "bad", text + (f"at least {ratio:.2f} (a lower bound, already above "
                                  f"{100 * STABILITY_GOAL:.0f} %)")
        return "info", text + (f"at least {ratio:.2f} (a lower bound: raise --dt-max above "
                               f"the prediction to measure the limit)")
    within = abs(ratio - 1.0) <= STABILITY_GOAL
    return ("ok" if within else "bad"), text + (f"{ratio:.2f} ({'within' if within else 'outside'} "
                                                f"{100 * STABILITY_GOAL:.0f} %)")


def recommendation_found(row):
    """True when a recommendation.csv row names a configuration (its dt is there)."""
    return _finite(row["dt"])


def best_error(f, rec_row):
    """', the smallest max error reached is ... by ...' for a recommendation that found nothing,
    from work_precision.csv (its engine's rows, or every row for scope overall), or ''."""
    if not f.has("work_precision.csv"):
        return ""
    wp = f.table("work_precision.csv")
    ok = (wp["stable"] >= 0.5) & np.isfinite(wp["error_max"])
    if rec_row["scope"] != "overall":
        ok &= wp["engine"] == rec_row["engine"]
    if not np.any(ok):
        return ", and no configuration stayed stable"
    k = int(np.flatnonzero(ok)[np.argmin(wp["error_max"][ok])])
    return (f"; the smallest max error is {length(float(wp['error_max'][k]))}, by "
            f"{_key(wp['engine'][k], wp['integrator'][k])} at dt {num(float(wp['dt'][k]))} s")


def growth_setting(cause):
    """What sets a growth limit, from growth_cause: "contact", "free", "none" (nothing grew
    past the tolerance) or "" (not said); with " (non-smooth)" and " (near the physics)" when
    the cause says so."""
    cause = str(cause)
    what = ("contact" if cause.startswith("set by contact") else
            "free" if cause.startswith("free") else
            "none" if cause.startswith("no growth") else "")
    return (what + (" (non-smooth)" if "non-smooth" in cause else "")
            + (" (near the physics)" if "near the physics" in cause else ""))


def _growth_text(r):
    """'; growth limit ... s (...), growth / predicted ..., set by ...' of a stability.csv row
    measured by growth, or '' (an older folder, or --method blowup)."""
    if not _finite(r.get("growth_stable_dt")) and not _finite(r.get("growth_first_unstable_dt")):
        return ""
    if not _finite(r["growth_stable_dt"]):
        text = (f"; growth limit: a mode grows too fast already at "
                f"{num(r['growth_first_unstable_dt'])} s")
    else:
        text = f"; growth limit {num(r['growth_stable_dt'])} s"
        if _finite(r["growth_first_unstable_dt"]):
            rates = ""
            if _finite(r.get("growth_rate")) and _finite(r.get("physical_rate")):
                rates = (f": growth {num(r['growth_rate'])}/s against "
                         f"{num(r['physical_rate'])}/s physical")
            text += f" (first growing at {num(r['growth_first_unstable_dt'])} s{rates})"
        else:
            text += " (nothing grew up to the largest step tried, so at least that)"
    ratio = r.get("growth_ratio", math.nan)
    if not _finite(ratio) and _finite(r["growth_stable_dt"]) and _finite(r["predicted_dt"]) \
            and r["predicted_dt"] > 0:
        ratio = r["growth_stable_dt"] / r["predicted_dt"]
    if _finite(ratio):
        text += f", growth limit / predicted {ratio:.2f}"
    setting = growth_setting(r.get("growth_cause", ""))
    text += {"contact": ", set by contact (the prediction is for the free scene)",
             "free": ", set by the free cloth",
             "none": ", no growth past the tolerance"}.get(setting.split(" ")[0], "")
    if "non-smooth" in setting:
        text += " (non-smooth: the estimate crosses a contact switch)"
    if "near the physics" in setting:
        found = re.search(r"no state grows more than (\d+)% faster", r.get("growth_cause", ""))
        most = f"{found.group(1)} %" if found else "a fraction"
        text += (f" (near the physics: the step grows at most {most} faster than the state's "
                 "physical rate; compare with the blow-up search)")
    return text


def _growth_only_line(r, key):
    """The line of a --method growth row: its blow-up columns are empty by design."""
    text = f"{key}: measured by growth only" + _growth_text(r)
    if not _finite(r["growth_stable_dt"]):
        return ("bad", text + ".")
    if growth_setting(r["growth_cause"]).startswith("contact"):
        return ("info", text + ".")
    censored = not _finite(r["growth_first_unstable_dt"])
    kind, more = stability_agreement(r["growth_stable_dt"], r["predicted_dt"],
                                     r["growth_ratio"], censored)
    return (kind, text + more.replace("; predicted", "; against the prediction", 1) + ".")


def _stability_limit_line(r):
    """The line of one stability.csv row."""
    key = _key(r["engine"], r["integrator"])
    if r.get("method") == "growth":
        return _growth_only_line(r, key)
    if not _finite(r["stable_dt"]):
        return ("bad", f"{key}: no stable time step found{_growth_text(r)}.")
    text = f"{key}: largest stable dt {num(r['stable_dt'])} s"
    # a search that never failed stopped at --dt-max: the measured limit is a lower bound
    censored = not _finite(r["first_unstable_dt"])
    if censored:
        text += " (no failure up to the largest step tried, so the limit is at least that)"
    else:
        text += f" (first failure at {num(r['first_unstable_dt'])} s"
        text += f", {r['cause']})" if r["cause"] else ")"
    kind, more = stability_agreement(r["stable_dt"], r["predicted_dt"],
                                     r["ratio_measured_to_predicted"], censored)
    return (kind, text + more + _growth_text(r) + ".")


def _convergence_line(f, r):
    """The line of one convergence.csv row."""
    key = _key(r["engine"], r["integrator"])
    if not _finite(r["order"]):
        return ("bad", f"{key}: no order fitted.")
    pts = f" from {int(r['points'])} points" if _finite(r["points"]) else ""
    text = f"{key}: measured order {r['order']:.2f}{pts}"
    expected = f.expected_order(r["integrator"]) if r["engine"] != "" else None
    kind = "info"
    if expected is not None:
        ok = abs(r["order"] - expected) <= 0.3
        kind = "ok" if ok else "bad"
        text += f" (expected {expected})"
    return (kind, text + ".")


def _recommendation_line(f, r):
    """The line of one recommendation.csv row."""
    scope = "overall" if r["scope"] == "overall" else f"for {r['engine']}"
    tol = f" within tolerance {num(r['tolerance'])} m" \
        if _finite(r["tolerance"]) else ""
    if not recommendation_found(r):
        return ("bad", f"Nothing meets the tolerance {scope}: no stable "
                       f"configuration{tol}{best_error(f, r)}.")
    return ("ok", f"Cheapest{tol} {scope}: {_key(r['engine'], r['integrator'])} "
                  f"at dt {num(r['dt'])} s (max error {length(r['error_max'])}, "
                  f"{num(r['wall_s_per_sim_s'])} s of wall time per simulated "
                  f"second).")


def _accuracy_lines(f):
    lines = []
    if f.has("work_precision.csv"):
        wp = f.table("work_precision.csv")
        unstable = int(np.sum(wp["stable"] < 0.5))
        lines.append(("info", f"{len(wp)} configurations run, {unstable} of them unstable."))
    if f.has("recommendation.csv"):
        rec = f.table("recommendation.csv")
        for r in sorted(rec.rows(), key=lambda r: r["scope"] != "overall"):
            lines.append(_recommendation_line(f, r))
        if f.has("work_precision.csv"):
            scopes = {r["engine"] for r in rec.rows() if r["scope"] != "overall"}
            for e in f.table("work_precision.csv").unique("engine"):
                if e not in scopes:
                    lines.append(("bad", f"{e}: no stable configuration meets the tolerance."))
    return lines


def _resolution_lines(f):
    lines = []
    res = f.table("resolution.csv")
    for e, i in dict.fromkeys(zip(res["engine"], res["integrator"])):
        key = _key(e, i)
        rows = res.where((res["engine"] == e) & (res["integrator"] == i))
        rows = rows.where(np.argsort(rows["particles"], kind="stable"))
        ok = (rows["stable"] >= 0.5) & np.isfinite(rows["error_final"])
        unstable = [_grid(p) for p in rows["particles"][rows["stable"] < 0.5]]
        parts = [f"{length(float(err))} on {_grid(p)}"
                 for p, err in zip(rows["particles"][ok], rows["error_final"][ok])]
        text = f"{key}: final error {', '.join(parts)}" if parts else f"{key}: no stable grid"
        if unstable:
            text += f"; unstable on {', '.join(unstable)}"
        lines.append(("bad" if unstable else "info", text + "."))
    return lines


def sweep_verdicts(f):
    """Verdicts of a sweep folder (any of stability, convergence, work-precision,
    recommendation and resolution CSV files)."""
    groups = []
    if f.has("stability.csv"):
        groups.append(("Stability limits",
                       [_stability_limit_line(r) for r in f.table("stability.csv").rows()]))
    if f.has("convergence.csv"):
        groups.append(("Convergence",
                       [_convergence_line(f, r) for r in f.table("convergence.csv").rows()]))
    if f.has("work_precision.csv") or f.has("recommendation.csv"):
        groups.append(("Accuracy and cost", _accuracy_lines(f)))
    if f.has("resolution.csv"):
        groups.append(("Grid resolution", _resolution_lines(f)))
    return groups


def _grid(particles):
    """'r × r' of an r by r grid of #P particles."""
    r = int(round(math.sqrt(particles)))
    return f"{r} × {r}"
