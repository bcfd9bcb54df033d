"""Top view: the cloths' shadows on the plane normal to gravity, with drape coefficients."""

import math

import matplotlib.pyplot as plt
import numpy as np

from . import colliders, style
from .drape import spheres

STEM = "shadow"
TITLE = "Drape seen from above"
CAPTION = ("Top view of the final cloth of every engine: its shadow on the plane normal to gravity "
           "(filled), overlaid, with the support outlined and the drape coefficient "
           "(shadow area − support area) / (cloth area − support area) where the run reports "
           "one.")

RASTER = 800     # cells along the longer side of the shadow raster
EDGE_ON = 1e-6   # a shadow below this fraction of the cloth's own area counts as none
MIN_SIDE = 0.2   # each side of the window spans at least this fraction of the longer one


def axes_of(folder):
    """Indices (a, b) of the two world axes spanning the plane normal to gravity."""
    g = np.array(folder.scenario.get("gravity", [0.0, -9.8, 0.0]), dtype=float)
    down = int(np.argmax(np.abs(g))) if np.any(g) else 1
    return [k for k in range(3) if k != down]


def corners(grid, faces=None):
    """(triangles, 3, 3) corner positions: a mesh's faces (grid is its n by 1 by 3 snapshot),
    else the nu by nv by 3 grid's two triangles per cell, split along the (i, j)-(i+1, j+1)
    diagonal. Empty for a 1 by N grid (a chain)."""
    if faces is not None:
        return grid.reshape(-1, 3)[faces]
    a, b, c, d = grid[:-1, :-1], grid[1:, :-1], grid[1:, 1:], grid[:-1, 1:]
    return np.concatenate([np.stack(t, axis=-2).reshape(-1, 3, 3) for t in ((a, b, c), (a, c, d))])


def shadow_mask(grid, ab, gx, gy, faces=None):
    """Boolean raster (len(gx) by len(gy)): inside the union of the projected triangles (a
    mesh's faces, or the grid's cells split in two)."""
    px, py = np.meshgrid(gx, gy, indexing="ij")
    inside = np.zeros(px.shape, dtype=bool)
    for tri in corners(grid, faces)[:, :, ab]:
        (x1, y1), (x2, y2), (x3, y3) = tri
        det = (y2 - y3) * (x1 - x3) + (x3 - x2) * (y1 - y3)
        if abs(det) < 1e-15:
            continue
        # only test the raster cells inside the triangle's bounding box
        i0, i1 = np.searchsorted(gx, [min(x1, x2, x3), max(x1, x2, x3)])
        j0, j1 = np.searchsorted(gy, [min(y1, y2, y3), max(y1, y2, y3)])
        sx, sy = px[i0:i1 + 1, j0:j1 + 1], py[i0:i1 + 1, j0:j1 + 1]
        l1 = ((y2 - y3) * (sx - x3) + (x3 - x2) * (sy - y3)) / det
        l2 = ((y3 - y1) * (sx - x3) + (x1 - x3) * (sy - y3)) / det
        eps = 1e-9
        inside[i0:i1 + 1, j0:j1 + 1] |= (l1 >= -eps) & (l2 >= -eps) & (l1 + l2 <= 1 + eps)
    return inside


def triangle_areas(grid, ab=None, faces=None):
    """Areas (m²) of the cloth's triangles (see corners): in space, or projected on the plane
    of the world axes ab. Empty for a 1 by N grid (a chain)."""
    t = corners(grid, faces)
    u, v = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
    if ab is None:
        return 0.5 * np.linalg.norm(np.cross(u, v), axis=-1)
    u, v = u[:, ab], v[:, ab]
    return 0.5 * np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])


def boundary_edges(faces):
    """The (a, b) edges of exactly one triangle of faces (faces, 3)."""
    e = np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    unique, count = np.unique(e, axis=0, return_counts=True)
    return unique[count == 1]


def casts_shadow(grid, ab, faces=None):
    """True when the cloth's shadow on the plane of axes ab has area (it is not edge-on)."""
    full = triangle_areas(grid, faces=faces).sum()
    return full > 0 and triangle_areas(grid, ab, faces).sum() > EDGE_ON * full


def skip_reason(folders):
    """Why the plot would show nothing, or None: a chain (1 by N grid) has no area, and a cloth
    hanging in a plane that holds gravity is edge-on from above."""
    panels = [f for f in folders if f.has("snapshots.csv")]
    shapes = [final_shapes(f) for f in panels]
    grids = [f.grid_shape() for f in panels]
    if all(min(g) < 2 and f.mesh_faces() is None for f, g in zip(panels, grids)):
        nu, nv = grids[0]
        return (f"the cloth is a {nu} × {nv} grid, a chain of particles: it has no area, so it "
                f"casts no shadow from above.")
    finals = [(f, g) for f, sh in zip(panels, shapes) for _, g in sh.values()]
    if finals and not any(casts_shadow(g, axes_of(f), f.mesh_faces()) for f, g in finals):
        return ("every final cloth is edge-on from above (it hangs in a plane that holds "
                "gravity), so its shadow on the plane normal to gravity has no area.")
    return None


def final_shapes(folder):
    """engine -> (time, grid) of the last snapshot, for engines whose final cloth is finite."""
    out = {}
    for e in folder.table("snapshots.csv").unique("engine"):
        times = folder.snapshot_times(e)
        g = folder.snapshot(e, times[-1])
        if folder.blowup(e) is None and np.all(np.isfinite(g)):
            out[e] = (times[-1], g)
    return out


def disks(folder):
    """((a, b), radius) of the scenario's `select = "disk"` constraints (the table's support),
    in the cloth plane's two world axes, which are those of the top view for a horizontal cloth."""
    out = []
    cons = folder.scenario.get("constraint", [])
    for c in cons if isinstance(cons, list) else []:
        if isinstance(c, dict) and c.get("select") in ("disk", "within"):
            try:
                center = [float(v) for v in c.get("center", [0.0, 0.0])]
                # a ball (within) seen from above: its centre on the x-z axes
                center = center[:2] if c["select"] == "disk" else [center[0], center[2]]
                out.append((tuple(center), float(c["radius"])))
            except (KeyError, TypeError, ValueError, IndexError):
                continue
    return out


def available(folder):
    return folder.has("snapshots.csv")


def _window(panels, shapes, ab):
    """(lo, hi, cell, gx, gy): one window for every panel, holding the flat cloth and every
    finite final cloth, and the shadow raster's cell size (m) and cell centres along a and b."""
    pts = []
    for f, sh in zip(panels, shapes):
        for e in f.table("snapshots.csv").unique("engine"):
            g0 = f.snapshot(e, f.snapshot_times(e)[0])
            pts.append(g0.reshape(-1, 3))
        pts.extend(g.reshape(-1, 3) for _, g in sh.values())
    pts = np.concatenate(pts)[:, ab]
    pts = pts[np.all(np.isfinite(pts), axis=1)]
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    # an edge-on cloth is a line from above: widen the short side so that the cells have size
    longest = max(hi - lo) if max(hi - lo) > 0 else 1.0
    grow = np.maximum(hi - lo, MIN_SIDE * longest) - (hi - lo)
    pad = 0.06 * longest
    lo, hi = lo - grow / 2 - pad, hi + grow / 2 + pad
    cell = max(hi - lo) / RASTER
    gx = np.arange(lo[0], hi[0] + cell, cell)
    gy = np.arange(lo[1], hi[1] + cell, cell)
    return lo, hi, cell, gx, gy


def _figure(panels, lo, hi):
    """The figure: a row of panels sharing their axes, a row of blank axes for the legends."""
    # room for the title, the square-ish panels and a legend line per engine below them
    entries = max(len(f.table("snapshots.csv").unique("engine")) for f in panels) + 2
    aspect = (hi[1] - lo[1]) / (hi[0] - lo[0])
    width = 12 if len(panels) > 1 else 9.5
    panel_w = (width - 1.2) / len(panels) if len(panels) > 1 else 6.0
    legend_h = 0.24 * entries + 0.2
    height = 1.6 + panel_w * aspect + legend_h
    # the legends get their own row of blank axes, so that the layout always makes room
    fig, axes = plt.subplots(2, len(panels), figsize=(width, height), squeeze=False,
                             layout="constrained",
                             gridspec_kw={"height_ratios": [panel_w * aspect, legend_h]})
    for ax in axes[0][1:]:
        ax.sharex(axes[0][0])
        ax.sharey(axes[0][0])
    return fig, axes


def _draw_supports(ax, f, engines, ab):
    """The flat cloth's outline, the supporting spheres and held disks, and the other colliders;
    returns their legend entries [(handle, text)]."""
    handles = []
    # the flat cloth at the first snapshot of the first engine, for scale
    g0 = f.snapshot(engines[0], f.snapshot_times(engines[0])[0])
    if np.all(np.isfinite(g0)) and f.mesh_faces() is not None:
        # a mesh's outline: its boundary edges (those of one triangle)
        p = g0.reshape(-1, 3)[:, ab]
        for a, b in boundary_edges(f.mesh_faces()):
            ax.plot(p[[a, b], 0], p[[a, b], 1], color="0.45", ls=":", lw=1.2)
        handles.append((plt.Line2D([], [], color="0.45", ls=":"),
                        f"cloth at t = {style.fmt(f.snapshot_times(engines[0])[0])} s"))
    elif np.all(np.isfinite(g0)):
        outline = np.concatenate([g0[:, 0], g0[-1, :], g0[::-1, -1], g0[0, ::-1]])[:, ab]
        ax.plot(outline[:, 0], outline[:, 1], color="0.45", ls=":", lw=1.2)
        handles.append((plt.Line2D([], [], color="0.45", ls=":"),
                        f"cloth at t = {style.fmt(f.snapshot_times(engines[0])[0])} s"))
    for c, r in spheres(f, 0.0):
        circle = plt.Circle((c[ab[0]], c[ab[1]]), r, fill=False, color="black", ls="--", lw=1.2)
        ax.add_patch(circle)
        handles.append((plt.Line2D([], [], color="black", ls="--"),
                        f"support: sphere r = {style.fmt(r)} m"))
    for (x, y), r in disks(f):
        ax.add_patch(plt.Circle((x, y), r, fill=False, color="black", ls="-.", lw=1.2))
        handles.append((plt.Line2D([], [], color="black", ls="-."),
                        f"support: held disk r = {style.fmt(r)} m"))
    return handles + colliders.draw_top(ax, f, ab)


def _draw_shadow(ax, f, e, sh, color, ab, raster):
    """Engine e's final shadow (filled and outlined, or the cloth as dots when it has no area);
    returns its legend entry (handle, text)."""
    gx, gy, cell = raster
    info = f.engine_info(e)
    dc = info.get("drape_coefficient", math.nan) if info else math.nan
    dc_text = f"drape coefficient {dc:.3f}" if isinstance(dc, float) and np.isfinite(dc) \
        else "no drape coefficient"
    if e not in sh:
        blow = f.blowup(e)
        why = f"blew up at t = {style.fmt(blow)} s" if blow is not None else "non-finite"
        return (plt.Line2D([], [], color=color, lw=0), f"{e}: not drawn ({why})")
    t, g = sh[e]
    mask = shadow_mask(g, ab, gx, gy, f.mesh_faces()).astype(float)
    if np.any(mask):
        ax.contourf(gx, gy, mask.T, levels=[0.5, 1.5], colors=[color], alpha=0.22)
        ax.contour(gx, gy, mask.T, levels=[0.5], colors=[color], linewidths=1.8)
        area = f"{mask.sum() * cell * cell:.3g} m²"
    else:
        # edge-on or a chain: the projected cloth itself, as a line
        ax.plot(g[:, :, ab[0]].ravel(), g[:, :, ab[1]].ravel(), color=color, lw=0,
                marker=".", ms=3)
        chain = min(g.shape[:2]) < 2 and f.mesh_faces() is None
        area = "0 m² (" + ("a chain: no area" if chain else "edge-on from above") + ")"
    return (plt.Line2D([], [], color=color, lw=6, alpha=0.5),
            f"{e} (t = {style.fmt(t)} s): shadow {area}, {dc_text}")


def draw(folders, ctx):
    panels = [f for f in folders if f.has("snapshots.csv")]
    shapes = [final_shapes(f) for f in panels]
    ab = axes_of(panels[0])
    names = "xyz"
    lo, hi, cell, gx, gy = _window(panels, shapes, ab)
    fig, axes = _figure(panels, lo, hi)
    for ax, leg_ax, f, sh in zip(axes[0], axes[1], panels, shapes):
        engines = f.table("snapshots.csv").unique("engine")
        handles = _draw_supports(ax, f, engines, ab)
        handles += [_draw_shadow(ax, f, e, sh, ctx.colors[e], ab, (gx, gy, cell))
                    for e in engines]
        ax.set_aspect("equal")
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_xlabel(f"{names[ab[0]]} (m)")
        ax.set_ylabel(f"{names[ab[1]]} (m)")
        ax.set_title(f"{f.label}: final shapes seen from above" if len(panels) > 1
                     else "final shapes seen from above")
        leg_ax.set_axis_off()
        leg_ax.legend([h for h, _ in handles], [t for _, t in handles], loc="upper center",
                      fontsize=style.FONT - 1, ncol=1, frameon=False)
    style.title(fig, TITLE, folders, compare="panels")
    return style.save(fig, ctx.outdir, STEM, ctx.svg)
