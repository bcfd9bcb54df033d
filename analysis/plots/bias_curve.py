"""The bias-extension test's curves (bias.csv): the clamp force against the displacement, the
shear force per unit length against the central zone's measured shear angle with each engine's
shear stiffness (tests.csv) in the legend, and the measured angle against the pin-jointed net's."""

import math

import matplotlib.pyplot as plt
import numpy as np

from . import style

STEM = "bias"
TITLE = "Bias-extension test: force, shear force and shear angle"
CAPTION = ("The bias-extension test (yarns at ±45° to a strip three times as long as wide, "
           "clamped at both ends, one end pulled): left, each custom engine's force along the "
           "strip across its central section (the scene's springs at the engine's positions, "
           "dampers left out) against the clamp's displacement; middle, the shear force per unit "
           "length, normalised by the energy balance of the pin-jointed net's zones, against the "
           "central zone's shear angle measured from its particles, with each engine's "
           "shear_stiffness, the least-squares slope over 0 < angle <= fit_angle (shaded); "
           "right, every engine's measured angle against the displacement, and the pin-jointed "
           "net's angle (dashed black, Cao et al. 2008). Engines whose forces are not the "
           "scene's springs (the Bullet engines) have angles only.")


def available(folder):
    return folder.has("bias.csv")


def stiffness(folder):
    """{engine: (shear_stiffness in N/m/rad, fit_angle in deg)} from tests.csv (NaN: none)."""
    out = {}
    if not folder.has("tests.csv"):
        return out
    for r in folder.table("tests.csv").rows():
        k, fit = out.get(str(r["engine"]), (math.nan, math.nan))
        if r["metric"] == "shear_stiffness":
            k = float(r["value"])
        if r["metric"] == "fit_angle":
            fit = float(r["value"])
        out[str(r["engine"])] = (k, fit)
    return out


def draw(folders, ctx):
    fig, (force, shear, angle) = plt.subplots(1, 3, figsize=(14, 4.8), layout="constrained")
    dashes = ["-", "--"]
    fit_max = 0.0
    for n, f in enumerate(f for f in folders if available(f)):
        table = f.table("bias.csv")
        slopes = stiffness(f)
        for e in table.unique("engine"):
            rows = table.select(engine=e)
            k, fit = slopes.get(str(e), (math.nan, math.nan))
            if math.isfinite(fit):
                fit_max = max(fit_max, fit)
            prefix = f"{f.label}: {e}" if len(folders) > 1 else str(e)
            value = f"{k:.4g} N/m/rad" if math.isfinite(k) else "no value"
            d_mm = np.asarray(rows["displacement"]) * 1000
            deg = np.degrees(np.asarray(rows["angle"]))
            style_of = dict(color=ctx.colors[e], lw=1.4)
            if np.isfinite(np.asarray(rows["force"], dtype=float)).any():
                force.plot(d_mm, rows["force"], dashes[n % 2], label=prefix, **style_of)
                shear.plot(deg, rows["shear_force"], dashes[n % 2],
                           label=f"{prefix}: shear_stiffness {value}", **style_of)
            angle.plot(d_mm, deg, dashes[n % 2], label=prefix, **style_of)
        # the pin-jointed net's angle, the same for every engine
        first = table.select(engine=table.unique("engine")[0])
        angle.plot(np.asarray(first["displacement"]) * 1000,
                   np.degrees(np.asarray(first["angle_pin_jointed"])), "k--", lw=1.0,
                   label="pin-jointed net" if n == 0 else None)
    if fit_max > 0:
        shear.axvspan(0, fit_max, color="0.9", zorder=0, label="fit range")
    force.set_xlabel("displacement (mm)")
    force.set_ylabel("force (N)")
    shear.set_xlabel("measured shear angle (deg)")
    shear.set_ylabel("shear force per unit length (N/m)")
    angle.set_xlabel("displacement (mm)")
    angle.set_ylabel("central shear angle (deg)")
    for ax in (force, shear, angle):
        ax.grid(alpha=0.3)
        style.legend(ax, loc="upper left", fontsize=style.FONT - 2)
    style.title(fig, TITLE, folders)
    return style.save(fig, ctx.outdir, STEM, ctx.svg)
