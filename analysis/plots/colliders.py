"""The scenario's planes, boxes, capsules and cylinders, drawn where they are at a time.

Read from the run's resolved scenario.toml (`[[plane]]`, `[[box]]`, `[[capsule]]`,
`[[cylinder]]`, each moved by its `velocity` or piecewise-linear `path`); the drape plot draws
them in 3D, the shadow plot their outlines seen from above. Spheres stay with drape.py.
"""

import math

import matplotlib.pyplot as plt
import numpy as np

KINDS = ("plane", "box", "capsule", "cylinder")
COLOR = "0.45"


def entries(folder, kind):
    """The scenario's [[kind]] tables (dicts), skipping anything malformed."""
    found = folder.scenario.get(kind, [])
    return [e for e in (found if isinstance(found, list) else []) if isinstance(e, dict)]


def displacement(entry, t):
    """Displacement (3,) of a collider at time t: its path (held after the last point), else
    its constant velocity."""
    path = entry.get("path")
    if isinstance(path, list) and path:
        pts = np.array(path, dtype=float)
        return np.array([np.interp(t, pts[:, 0], pts[:, k]) for k in (1, 2, 3)])
    return np.array(entry.get("velocity", [0.0, 0.0, 0.0]), dtype=float) * t


def _vec(entry, key, default):
    return np.array(entry.get(key, default), dtype=float)


def _line(ax, pts):
    """A polyline of (n, 3) simulation points; matplotlib's 3D axes are (x, z-depth, y-up)."""
    ax.plot(pts[:, 0], pts[:, 2], pts[:, 1], color=COLOR, lw=0.8, alpha=0.8)


def box_edges(center, half):
    """The 12 edges of an axis-aligned box as (2, 3) segments."""
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    pts = center + corners * half
    return [np.array([pts[a], pts[b]]) for a in range(8) for b in range(a + 1, 8)
            if np.sum(corners[a] != corners[b]) == 1]


def circle(center, radius, y, n=48):
    """(n, 3) points of a horizontal circle at height y."""
    u = np.linspace(0.0, 2.0 * math.pi, n)
    return np.stack([center[0] + radius * np.cos(u), np.full(n, y),
                     center[2] + radius * np.sin(u)], axis=1)


def plane_patch(point, normal, box):
    """Corners (5, 3) of the plane's square patch across the view box, closed; None when the
    plane does not meet the box."""
    n = normal / np.linalg.norm(normal)
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 0.0, 1.0])
    e1 = helper - helper.dot(n) * n
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(n, e1)
    lo, hi = np.asarray(box[0], dtype=float), np.asarray(box[1], dtype=float)
    mid = 0.5 * (lo + hi)
    foot = mid - (mid - point).dot(n) * n  # the plane's point nearest the view's centre
    if np.any(foot < lo - 1e-9) or np.any(foot > hi + 1e-9):
        return None
    s = 0.5 * float(np.max(hi - lo))
    quad = [foot + a * s * e1 + b * s * e2 for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1), (-1, -1))]
    return np.clip(np.array(quad), lo, hi)


def draw_3d(ax, folder, t, box):
    """Draws every plane, box, capsule and cylinder at time t (s) on a 3D axes; box is the
    view's ((x, y, z) low, (x, y, z) high) limits."""
    for e in entries(folder, "plane"):
        try:
            quad = plane_patch(_vec(e, "point", [0, 0, 0]) + displacement(e, t),
                               _vec(e, "normal", [0, 1, 0]), box)
        except (TypeError, ValueError, ZeroDivisionError):
            continue
        if quad is not None:
            _line(ax, quad)
    for e in entries(folder, "box"):
        try:
            c = _vec(e, "center", [0, 0, 0]) + displacement(e, t)
            for seg in box_edges(c, _vec(e, "half_extents", [0.5, 0.5, 0.5])):
                _line(ax, np.clip(seg, box[0], box[1]))
        except (TypeError, ValueError):
            continue
    for e in entries(folder, "capsule"):
        try:
            d = displacement(e, t)
            _line(ax, np.array([_vec(e, "a", [-1, 0, 0]) + d, _vec(e, "b", [1, 0, 0]) + d]))
        except (TypeError, ValueError):
            continue
    for e in entries(folder, "cylinder"):
        try:
            c = _vec(e, "center", [0, 0, 0]) + displacement(e, t)
            r, h = float(e.get("radius", 0.1)), float(e.get("height", 0.02))
            for y in (c[1] - 0.5 * h, c[1] + 0.5 * h):
                _line(ax, circle(c, r, y))
        except (TypeError, ValueError):
            continue


def draw_top(ax, folder, ab):
    """Outlines at t = 0 of the boxes, capsules and cylinders on a top view whose axes are the
    world axes ab; returns (legend handle, label) pairs."""
    handles = []
    style = dict(fill=False, color="black", ls="-.", lw=1.2)
    for e in entries(folder, "box"):
        try:
            c, h = _vec(e, "center", [0, 0, 0]), _vec(e, "half_extents", [0.5, 0.5, 0.5])
        except (TypeError, ValueError):
            continue
        ax.add_patch(plt.Rectangle((c[ab[0]] - h[ab[0]], c[ab[1]] - h[ab[1]]),
                                   2 * h[ab[0]], 2 * h[ab[1]], **style))
        handles.append((plt.Line2D([], [], color="black", ls="-."), "box"))
    for e in entries(folder, "cylinder"):
        try:
            c, r = _vec(e, "center", [0, 0, 0]), float(e.get("radius", 0.1))
        except (TypeError, ValueError):
            continue
        ax.add_patch(plt.Circle((c[ab[0]], c[ab[1]]), r, **style))
        handles.append((plt.Line2D([], [], color="black", ls="-."), f"support: disk r = {r:g} m"))
    for e in entries(folder, "capsule"):
        try:
            a, b = _vec(e, "a", [-1, 0, 0]), _vec(e, "b", [1, 0, 0])
        except (TypeError, ValueError):
            continue
        ax.plot([a[ab[0]], b[ab[0]]], [a[ab[1]], b[ab[1]]], color="black", ls="-.", lw=1.2)
        handles.append((plt.Line2D([], [], color="black", ls="-."), "capsule axis"))
    return handles
