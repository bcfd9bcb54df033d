"""Drape shape: the cloth of every engine at chosen snapshot times, side by side in 3D."""

import math

import matplotlib.pyplot as plt
import numpy as np

from . import colliders, style

STEM = "drape"
TITLE = "Drape shape"
CAPTION = ("The cloth at chosen snapshot times (columns) for every engine (rows), drawn with the "
           "same view and the same scale in every panel, coloured by each particle's distance to "
           "the reference engine at the same time (mm, one colour bar for every panel up to the "
           "95th percentile of the distances, larger ones in its top colour; the reference "
           "itself is uniformly 0); spheres, planes, boxes, capsules and cylinders are drawn "
           "where the scenario has them at that time, and a 1 × N grid (a chain) as its "
           "particles joined by a line. A panel stays "
           "empty where the engine had already blown up.")

ELEV, AZIM = 22.0, -58.0  # degrees, one view for every panel
MAX_COLUMNS = 4
MIN_SIDE = 0.35  # each side of the view box spans at least this fraction of the longest


def available(folder):
    return folder.has("snapshots.csv")


def choose_times(times, wanted=None, count=MAX_COLUMNS):
    """Snapshot times to show: the nearest to each wanted time, else spread evenly (both ends)."""
    times = sorted(times)
    if not times:
        return []
    if wanted:
        return sorted({min(times, key=lambda t: abs(t - w)) for w in wanted})
    if len(times) <= count:
        return times
    picks = np.linspace(0, len(times) - 1, count).round().astype(int)
    return [times[p] for p in sorted(set(picks))]


def rows_of(folders):
    """(folder, engine) pairs that have snapshots, in engine then folder order."""
    engines = []
    for f in folders:
        if f.has("snapshots.csv"):
            engines += [e for e in f.table("snapshots.csv").unique("engine") if e not in engines]
    # with two folders, an engine's rows sit together (before above after)
    return [(f, e) for e in engines for f in folders
            if f.has("snapshots.csv") and e in f.table("snapshots.csv").unique("engine")]


def spheres(folder, t):
    """(centre, radius) of the scenario's spheres at time t (moving spheres move linearly)."""
    out = []
    found = folder.scenario.get("sphere", [])
    for s in [found] if isinstance(found, dict) else found if isinstance(found, list) else []:
        if not isinstance(s, dict):
            continue
        try:
            c = np.array(s.get("center", [0, 0, 0]), dtype=float)
            v = np.array(s.get("velocity", [0, 0, 0]), dtype=float)
            out.append((c + v * t, float(s["radius"])))
        except (KeyError, TypeError, ValueError):
            continue
    return out


def view_box(folders, pairs, times_of):
    """Common axis limits (x, y, z) covering the finite cloths of stable engines and spheres."""
    pts = []
    for f, e in pairs:
        if f.blowup(e) is not None:
            continue
        for t in times_of[(f.label, e)]:
            g = f.snapshot(e, t).reshape(-1, 3)
            pts.append(g[np.all(np.isfinite(g), axis=1)])
    if not pts or not sum(len(p) for p in pts):
        for f, e in pairs:  # every engine blew up: use whatever is finite
            for t in times_of[(f.label, e)]:
                g = f.snapshot(e, t).reshape(-1, 3)
                pts.append(g[np.all(np.isfinite(g) & (np.abs(g) < 1e3), axis=1)])
    pts = np.concatenate(pts) if pts else np.zeros((0, 3))
    if not len(pts):
        pts = np.zeros((1, 3))
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    for f in folders:
        for c, r in spheres(f, 0.0):
            # only the part of the sphere near the cloth matters for the view
            lo = np.minimum(lo, [c[0] - r, c[1] - r, c[2] - r])
            hi = np.maximum(hi, [c[0] + r, max(c[1] + r, hi[1]), c[2] + r])
    # a chain or an edge-on cloth is flat along some axis: give every side some depth
    longest = max(max(hi - lo), 1e-3)
    grow = np.maximum(hi - lo, MIN_SIDE * longest) - (hi - lo)
    pad = 0.05 * longest
    return lo - grow / 2 - pad, hi + grow / 2 + pad


def draw_sphere(ax, c, r, box):
    u, v = np.meshgrid(np.linspace(0, 2 * math.pi, 28), np.linspace(0, math.pi, 15))
    x = c[0] + r * np.cos(u) * np.sin(v)
    y = c[1] + r * np.cos(v)
    z = c[2] + r * np.sin(u) * np.sin(v)
    inside = (y >= box[0][1]) & (y <= box[1][1])
    y = np.where(inside, y, np.nan)
    # matplotlib's 3D axes are (x, z-depth, y-up): the simulation's y is drawn upwards
    ax.plot_wireframe(x, z, y, color="0.55", lw=0.4, alpha=0.6)


def column_times(pairs, wanted):
    """Snapshot times of the columns, shared by every row: chosen among the times of the
    engines that stayed stable (their snapshot grid), or of every engine if none did."""
    stable = [(f, e) for f, e in pairs if f.blowup(e) is None] or pairs
    times = sorted({t for f, e in stable for t in f.snapshot_times(e)})
    return choose_times(times, wanted)


def cell_time(f, engine, column, previous):
    """Snapshot time to draw for one engine in a column at time `column`, or None.

    The engine's own snapshot at that time; else, for an engine that blew up before it, its
    last snapshot (the blown-up shape) in the first such column only.
    """
    own = f.snapshot_times(engine)
    for t in own:
        if abs(t - column) <= 1e-9 * max(1.0, abs(column)):
            return t
    blow = f.blowup(engine)
    if blow is not None and own and own[-1] <= column and (previous is None or previous < own[-1]):
        return own[-1]
    return None


def distance_mm(f, engine, t):
    """Per-particle distance (mm, nu by nv) from the folder's reference engine at snapshot time
    t, or None when the reference has no finite snapshot there."""
    ref = f.reference()
    if not ref or ref not in f.table("snapshots.csv").unique("engine"):
        return None
    if not any(abs(s - t) <= 1e-9 * max(1.0, abs(t)) for s in f.snapshot_times(ref)):
        return None
    a, b = f.snapshot(engine, t), f.snapshot(ref, t)
    d = 1000 * np.linalg.norm(a - b, axis=-1)
    return d if np.all(np.isfinite(d)) else None


def distance_norm(pairs, columns):
    """One colour scale (mm) for every panel: 0 to the 95th percentile of the distances of the
    stable engines' panels, so one engine's start-up transient does not take the whole scale
    (larger distances get the top colour; the colour bar's arrow says so)."""
    values = []
    for f, e in pairs:
        for c in columns:
            t = cell_time(f, e, c, None)
            d = distance_mm(f, e, t) if t is not None else None
            blown = f.blowup(e) is not None and t is not None and t >= (f.blowup(e) or 0) - 1e-12
            if d is not None and not blown and np.any(d > 0):
                values.append(d.ravel())
    hi = float(np.percentile(np.concatenate(values), 95)) if values else 0.0
    return plt.Normalize(0.0, hi if hi > 0 else 1.0)


def cell_axes(fig, shape, k, box):
    """The k-th (from 1) 3D axes of a rows by columns figure, seen as the player sees the
    scene, over the view box (lo, hi)."""
    lo, hi = box
    ax = fig.add_subplot(*shape, k, projection="3d", computed_zorder=False)
    ax.view_init(elev=ELEV, azim=AZIM)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[2], hi[2])
    ax.set_zlim(lo[1], hi[1])
    ax.set_box_aspect((hi[0] - lo[0], hi[2] - lo[2], hi[1] - lo[1]), zoom=0.9)
    ax.set_xlabel("x (m)", labelpad=-6)
    ax.set_ylabel("z (m)", labelpad=-6)
    ax.set_zlabel("y (m)", labelpad=-6)
    ax.tick_params(labelsize=style.FONT - 3, pad=-3)
    return ax


def _draw_mesh(ax, p, faces, engine, colour, d, state):
    """A mesh cloth's triangles: the engine's colour, or each face coloured by the mean distance
    (mm) of its corners from the reference when d (particles by 1) is given."""
    colors, norm, cmap = colour
    surf = ax.plot_trisurf(p[:, 0], p[:, 2], p[:, 1], triangles=faces,
                           color=colors[engine] if not state else "0.6", edgecolor="black",
                           linewidth=0.15, alpha=0.9 if d is None else 1.0, shade=d is None)
    if d is not None:
        surf.set_facecolor(cmap(norm(d.reshape(-1)[faces].mean(axis=1))))


def draw_cloth(ax, f, engine, t, box, colour):
    """Engine's cloth at snapshot time t (s) with the colliders; returns " — blown up" when it
    had blown up by then, else "".

    colour  (colors, norm, cmap): engine colours and the distance colour scale"""
    (lo, hi), blow, (colors, norm, cmap) = box, f.blowup(engine), colour
    for sc, sr in spheres(f, t):
        draw_sphere(ax, sc, sr, (lo, hi))
    colliders.draw_3d(ax, f, t, (lo, hi))
    g = f.snapshot(engine, t)
    ok = np.all(np.isfinite(g)) and np.all((g >= lo - 1e-9) & (g <= hi + 1e-9))
    state = ""
    if blow is not None and (np.isnan(blow) or t >= blow - 1e-12):
        state = " — blown up"
    faces = f.mesh_faces()
    if ok and faces is not None:
        _draw_mesh(ax, g.reshape(-1, 3), faces, engine, colour,
                   distance_mm(f, engine, t) if not state else None, state)
    elif ok and min(g.shape[:2]) < 2:
        # a 1 by N grid (a chain) has no surface: its particles joined by a line
        ax.plot(g[:, :, 0].ravel(), g[:, :, 2].ravel(), g[:, :, 1].ravel(),
                color=colors[engine], lw=2, marker="o", ms=3.5, mec="black",
                mew=0.4)
    elif ok:
        d = distance_mm(f, engine, t) if not state else None
        if d is None:
            ax.plot_surface(g[:, :, 0], g[:, :, 2], g[:, :, 1],
                            color=colors[engine] if not state else "0.6",
                            edgecolor="black", linewidth=0.25, alpha=0.9, shade=True)
        else:
            # unshaded, so the colour is the colour bar's
            ax.plot_surface(g[:, :, 0], g[:, :, 2], g[:, :, 1], facecolors=cmap(norm(d)),
                            edgecolor="black", linewidth=0.15, shade=False)
    else:
        ax.text2D(0.5, 0.5, "outside the view\n(non-finite or blown up)", ha="center",
                  va="center", transform=ax.transAxes, color="tab:red",
                  fontsize=style.FONT - 1)
    return state


def _draw_row(fig, r, pair, columns, layout, colour):
    """Row r of the figure: one engine's cloth at each column's time, or why it has none.

    layout  (number of folders, rows, columns, (lo, hi) view box); returns the row's axes"""
    f, engine = pair
    nfolders, nrows, ncols, box = layout
    blow = f.blowup(engine)
    previous = None
    axes = []
    for c, column in enumerate(columns):
        ax = cell_axes(fig, (nrows, ncols), r * ncols + c + 1, box)
        axes.append(ax)
        name = engine if nfolders == 1 else f"{engine} ({f.label})"
        t = cell_time(f, engine, column, previous)
        if t is None:
            ax.set_axis_off()
            why = "" if blow is None else f"\n(blew up at t = {style.fmt(blow)} s)"
            ax.text2D(0.5, 0.5, f"{name}\nno snapshot at t = {style.fmt(column)} s{why}",
                      ha="center", va="center", transform=ax.transAxes, color="0.35",
                      fontsize=style.FONT - 1)
            continue
        previous = t
        state = draw_cloth(ax, f, engine, t, box, colour)
        ax.set_title(f"{name}\nt = {style.fmt(t)} s{state}", fontsize=style.FONT - 1)
    return axes


def draw(folders, ctx):
    pairs = rows_of(folders)
    columns = column_times(pairs, ctx.snapshot_times)
    ncols = max(1, len(columns))
    nrows = len(pairs)
    times_of = {(f.label, e): [t for t in f.snapshot_times(e)] for f, e in pairs}
    lo, hi = view_box(folders, pairs, times_of)
    norm, cmap = distance_norm(pairs, columns), plt.get_cmap("viridis")
    axes_3d = []
    # a tall view box (a hanging chain) gets taller rows, so titles and axes labels do not meet
    tall = (hi[1] - lo[1]) / max(hi[0] - lo[0], hi[2] - lo[2])
    fig = plt.figure(figsize=(12, 1.3 + 2.8 * min(max(tall, 1.0), 1.6) * nrows),
                     layout="constrained")
    for r, pair in enumerate(pairs):
        axes_3d += _draw_row(fig, r, pair, columns, (len(folders), nrows, ncols, (lo, hi)),
                             (ctx.colors, norm, cmap))
    if axes_3d:
        bar = fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=cmap), ax=axes_3d,
                           shrink=min(0.6, 2.5 / max(1, nrows)), pad=0.02, aspect=30,
                           extend="max")
        bar.set_label("distance to the reference engine at the same time (mm)")
    style.title(fig, TITLE, folders, compare="rows")
    return style.save(fig, ctx.outdir, STEM, ctx.svg)
