"""Energy over time per engine: kinetic, potentials and dissipated energy, and the energy error."""

import textwrap

import matplotlib.pyplot as plt
import numpy as np

from . import style

STEM = "energy"
TITLE = "Energy over time"
CAPTION = ("Energy over time per engine (left): kinetic, gravity potential relative to its initial "
           "value, elastic potential, the energy dissipated by dampers and drag, the net work of "
           "the contact response relative to the colliders, the work of the moving colliders' "
           "motion, the work of the handles' holders (the harness's, from the "
           "scene's forces on the handled particles) and, for a Bullet engine, the unbooked "
           "balance of its steps with a contact or a projected handle (each drawn where it is "
           "not zero). Right: the energy error, total + dissipated − contact work − collider work "
           "− handle work − unbooked − initial total, which is zero for an exact integrator.")

# frames.csv column, legend text, colour
QUANTITIES = [
    ("kinetic", "kinetic", "tab:blue"),
    ("gravity_potential", "gravity potential − initial", "tab:green"),
    ("elastic_potential", "elastic potential", "tab:orange"),
    ("dissipated", "dissipated", "tab:purple"),
    ("contact_work", "contact work", "tab:brown"),
    ("collider_work", "collider work", "tab:pink"),
    ("unbooked", "unbooked", "tab:gray"),
    ("handle_work", "handle work", "tab:olive"),
]


def available(folder):
    return folder.has("frames.csv")


def stable_rows(folder, engine):
    """frames.csv rows of an engine sorted by t, without the rows at or after a blow-up."""
    frames = folder.table("frames.csv").select(engine=engine)
    frames = frames.where(np.argsort(frames["t"], kind="stable"))
    return frames.where(frames["stable"] >= 0.5)


def frame_engines(folders):
    engines = []
    for f in folders:
        if f.has("frames.csv"):
            for e in f.table("frames.csv").unique("engine"):
                if e not in engines:
                    engines.append(e)
    return engines


def mark_blowup(ax, folder, engine, ls, label=True, name=False):
    """A red vertical line at the engine's blow-up time, labelled (with the engine's name)."""
    t = folder.blowup(engine)
    if t is None or np.isnan(t):
        return
    ax.axvline(t, color="tab:red", ls=ls, lw=1.2, alpha=0.8)
    if label:
        who = f"{engine} " if name else ""
        ax.annotate(f"{who}blew up, t = {style.fmt(t)} s", (t, 0.97),
                    xycoords=("data", "axes fraction"),
                    xytext=(4, 0), textcoords="offset points", ha="left", va="top",
                    color="tab:red", fontsize=style.FONT - 1)


def draw(folders, ctx):
    engines = frame_engines(folders)
    n = len(engines)
    fig, axes = plt.subplots(n, 2, figsize=(12, 1.3 + 2.5 * n), squeeze=False, sharex=True,
                             gridspec_kw={"width_ratios": [1.5, 1]}, layout="constrained")
    for r, engine in enumerate(engines):
        ax_e, ax_err = axes[r]
        for k, f in enumerate(folders):
            if not f.has("frames.csv") or engine not in f.table("frames.csv").unique("engine"):
                continue
            rows = stable_rows(f, engine)
            ls = style.RUN_STYLES[k]
            t = rows["t"]
            for col, text, color in QUANTITIES:
                if col not in rows.columns or not np.any(rows[col]):
                    continue  # a book the engine does not keep (or a folder from before it)
                y = rows[col]
                if col == "gravity_potential" and len(y):
                    y = y - y[0]
                ax_e.plot(t, y, color=color, ls=ls, lw=1.5, label=text if k == 0 else None)
            ax_err.plot(t, rows["energy_error"], color=ctx.colors[engine], ls=ls, lw=1.5,
                        label=f.label if len(folders) > 1 else None)
            for ax in (ax_e, ax_err):
                mark_blowup(ax, f, engine, ls, label=(ax is ax_e))
        ax_e.set_title(f"{engine}: energies")
        ax_e.set_ylabel("energy (J)")
        gated = [f.energy_gated(engine) for f in folders
                 if f.has("frames.csv") and engine in f.table("frames.csv").unique("engine")]
        if gated and not any(g for g, _ in gated):
            # zero by construction: say why on the plot, not only in the page
            why = next((n for _, n in gated if n), "0 by construction")
            ax_err.text(0.5, 0.7, textwrap.fill("not a measure of the time scheme: the energy "
                                                "error is " + why, 48),
                        ha="center", va="center", transform=ax_err.transAxes,
                        fontsize=style.FONT - 1, color="0.25",
                        bbox={"boxstyle": "round", "fc": "white", "ec": "0.7"})
        ax_err.set_title(f"{engine}: energy error")
        ax_err.set_ylabel("energy error (J)")
        ax_err.axhline(0.0, color="0.5", lw=0.8)
        if r == 0:
            handles, labels = ax_e.get_legend_handles_labels()
            if len(folders) > 1:
                for k, f in enumerate(folders):
                    handles.append(plt.Line2D([], [], color="0.3", ls=style.RUN_STYLES[k]))
                    labels.append(f.label)
            ax_e.legend(handles, labels, loc="best", ncol=2 if len(folders) > 1 else 1)
            if len(folders) > 1:
                style.legend(ax_err, loc="best")
    for ax in axes[-1]:
        ax.set_xlabel("time t (s)")
    style.title(fig, TITLE, folders)
    return style.save(fig, ctx.outdir, STEM, ctx.svg)
