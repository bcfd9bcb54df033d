"""movie.mp4: the player's grid view as a video (matplotlib 3D, encoded by Debian's ffmpeg).

One panel per engine (of each folder with --compare), the same view and the same scale in every
panel, the colliders drawn where they are, and an engine that blew up greyed from its blow-up
time; one video frame per trajectory frame, played at real time.
"""

import math
import os
import shutil

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import animation

from . import trajectory
from .csvio import ReportError
from .plots import colliders, style

ELEV, AZIM = 22.0, -58.0   # degrees, the drape plot's view
WIDTH_IN, DPI = 9.6, 100    # 960 px wide


def ffmpeg_missing():
    """None when ffmpeg is on the PATH, else the sentence saying how to get it."""
    if shutil.which("ffmpeg"):
        return None
    return "--movie needs ffmpeg: apt-get install ffmpeg (or scripts/install-deps)"


def _panels(folders):
    out = []
    for f in folders:
        tr = trajectory.Trajectory(f.path)
        for e in tr.index["engines"]:
            name = e["name"] if len(folders) == 1 else f"{e['name']} ({f.label})"
            out.append((name, e, tr, f))
    return out


def _box(panels):
    pts = []
    for _, e, tr, _ in panels:
        x = tr.positions[e["name"]]
        if len(x):
            pts.append(x[np.all(np.abs(x) < 1e3, axis=-1)])
    pts = np.concatenate(pts) if pts else np.zeros((1, 3))
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    side = max(max(hi - lo), 1e-3)
    grow = np.maximum(hi - lo, 0.35 * side) - (hi - lo)
    return lo - grow / 2 - 0.05 * side, hi + grow / 2 + 0.05 * side


def _figure(panels, lo, hi):
    """The movie's figure and one 3D axes per panel, up to four in a row."""
    cols = min(4, len(panels))
    rows = math.ceil(len(panels) / cols)
    fig = plt.figure(figsize=(WIDTH_IN, 0.5 + 2.6 * rows), dpi=DPI)
    axes = []
    for k in range(len(panels)):
        ax = fig.add_subplot(rows, cols, k + 1, projection="3d", computed_zorder=False)
        ax.view_init(elev=ELEV, azim=AZIM)
        ax.set_axis_off()
        ax.set_box_aspect((hi[0] - lo[0], hi[2] - lo[2], hi[1] - lo[1]), zoom=1.1)
        axes.append(ax)
    return fig, axes


# a unit sphere's parameter grid, for the spheres' wireframes
_SPHERE_U, _SPHERE_V = np.meshgrid(np.linspace(0, 2 * math.pi, 24), np.linspace(0, math.pi, 13))


def _draw_panel(ax, panel, t, box, colors):
    """One engine's cloth and the colliders at time t (s) in ax, emptied first."""
    (name, e, tr, folder), (lo, hi), u, v = panel, box, _SPHERE_U, _SPHERE_V
    ax.clear()
    ax.set_axis_off()
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[2], hi[2])
    ax.set_zlim(lo[1], hi[1])
    kc = min(int(round(t / tr.interval)), tr.index["frames"] - 1)
    for s, shape in enumerate(tr.index["shapes"]):
        if shape.get("type") == "sphere":
            c, r = tr.colliders[kc, s], shape["radius"]
            ax.plot_wireframe(c[0] + r * np.cos(u) * np.sin(v), c[2] + r * np.sin(u) * np.sin(v),
                              np.clip(c[1] + r * np.cos(v), lo[1], None), color="0.6", lw=0.3,
                              zorder=1)
    colliders.draw_3d(ax, folder, t, (lo, hi))  # planes, boxes, capsules, cylinders
    x = tr.positions[e["name"]]
    ke = int(round(t / tr.interval))
    gone = ke > len(x) - 1
    nu, nv = tr.grid
    state = ""
    if len(x):
        g = x[min(ke, len(x) - 1)].reshape(nv, nu, 3)
        color = "0.6" if gone else colors[e["name"]]
        if tr.index.get("edges"):
            # a mesh: its triangles
            p = g.reshape(-1, 3)
            ax.plot_trisurf(p[:, 0], p[:, 2], p[:, 1], triangles=tr.triangles(), color=color,
                            edgecolor="k", linewidth=0.1, shade=True, zorder=2)
        elif min(nu, nv) > 1:
            ax.plot_surface(g[..., 0], g[..., 2], g[..., 1], color=color, edgecolor="k",
                            linewidth=0.1, shade=True, zorder=2)
        else:
            ax.plot(g[..., 0].ravel(), g[..., 2].ravel(), g[..., 1].ravel(), color=color)
    if gone:
        state = f"\nblew up at {e['blowup_t'] or (len(x) - 1) * tr.interval:.3f} s"
    ax.set_title(name + state, fontsize=8, color="tab:red" if gone else "black")


def check(folders):
    """Raises ReportError when no movie can be made of folders (no ffmpeg, no trajectories);
    returns the folders that have trajectories."""
    why = ffmpeg_missing()
    if why:
        raise ReportError(why)
    runs = [f for f in folders if trajectory.available(f.path)]
    if not runs:
        raise ReportError(f"--movie: {folders[0].path} has no trajectory/ (a run folder written "
                          "with animation_interval > 0)")
    return runs


def write(folders, outdir, colors):
    """Writes outdir/movie.mp4 and returns its path."""
    runs = check(folders)
    panels = _panels(runs)
    box = _box(panels)
    fig, axes = _figure(panels, *box)
    interval = min(tr.interval for _, _, tr, _ in panels)
    frames = max(tr.index["frames"] for _, _, tr, _ in panels)
    title = fig.suptitle("")
    fig.subplots_adjust(0, 0, 1, 0.93, 0.02, 0.08)

    path = os.path.join(outdir, "movie.mp4")
    tmp = os.path.join(outdir, ".movie.tmp.mp4")
    writer = animation.FFMpegWriter(fps=1.0 / interval, codec="libx264", bitrate=900,
                                    extra_args=["-pix_fmt", "yuv420p"])
    with writer.saving(fig, tmp, DPI):
        for k in range(frames):
            t = k * interval
            title.set_text(f"{runs[0].name}: t = {t:.2f} s")
            for ax, panel in zip(axes, panels):
                _draw_panel(ax, panel, t, box, colors)
            writer.grab_frame()
    plt.close(fig)
    os.replace(tmp, path)
    return path
