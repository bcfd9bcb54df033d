"""Verdicts in words from attribution.csv (clothbench run --explain): how much of each Bullet
engine's distance from the reference is the time scheme and how much the model."""

import math

from .quantities import length


def _row(table, engine, at):
    rows = table.where((table["engine"] == engine) & (table["at"] == at))
    return next(rows.rows(), None) if len(rows) else None


def _sentence(r, when):
    total, scheme, model = r["total_rms"], r["scheme_rms"], r["model_rms"]
    if not math.isfinite(scheme) or not math.isfinite(model):
        return (f"{r['engine']} is {length(total)} from {r['reference']} {when}, not split: "
                f"{r['note']}.")
    return (f"{r['engine']} is {length(total)} from {r['reference']} {when}: of that, "
            f"{length(scheme)} is the time scheme ({r['matched']}, the same scheme and dt in our "
            f"model, is {length(scheme)} from {r['reference']}) and {length(model)} the model "
            f"({r['matched']} is {length(model)} from {r['engine']}: contact and parameters).")


def _largest(r):
    total, scheme, model = r["total_rms"], r["scheme_rms"], r["model_rms"]
    if not math.isfinite(scheme) or not math.isfinite(model):
        return f"{r['engine']}: largest distance from {r['reference']} over the frames {length(total)}."
    return (f"{r['engine']}: largest over the frames, each at its own worst frame: "
            f"{length(total)} from {r['reference']}, time scheme {length(scheme)}, "
            f"model {length(model)}.")


def attribution_verdicts(f):
    """The group ("Time scheme or model?", lines) of a run with attribution.csv, else None."""
    if not f.has("attribution.csv"):
        return None
    table = f.table("attribution.csv")
    lines = []
    for engine in table.unique("engine"):
        final, most = _row(table, engine, "final"), _row(table, engine, "max")
        if final is not None:
            lines.append(("info", _sentence(final, f"at the end (t = {final['t']:g} s)")))
        if most is not None:
            lines.append(("info", _largest(most)))
    lines.append(("info", "The three distances are RMS particle distances, so each is at most "
                  "the sum of the other two; they need not add up exactly."))
    return ("Time scheme or model? (clothbench run --explain)", lines)
