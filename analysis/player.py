"""The report's interactive 3D player: a section of report.html with three.js inlined.

three.js comes from Debian's libjs-three (/usr/share/javascript/three/three.min.js, or the file
named by CLOTHBENCH_THREE_JS); without it, or without trajectories in the folder, the section
says why instead. The trajectories (trajectory/ of a run folder, see analysis/trajectory.py) go
into the page as base64 float32, so the page still opens offline by double-click.
"""

import base64
import html
import json
import math
import os

import numpy as np

from . import trajectory

THREE_JS = "/usr/share/javascript/three/three.min.js"
PLAYER_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "player")
# the player's scripts in analysis/player/, in the order they are joined: each file's top level
# declares what later files use, and main.js, last, starts the player
PLAYER_SCRIPTS = ["status.js", "decode.js", "data.js", "state.js", "measure.js", "scene.js",
                  "camera.js", "paint.js", "draw.js", "controls.js", "main.js"]

CSS = """
#player { margin: 10px 0 18px; }
#player-canvas-box { position: relative; border: 1px solid #dde; display: inline-block; }
#player-canvas-box canvas { display: block; cursor: grab; }
#player-labels { position: absolute; left: 0; top: 0; right: 0; bottom: 0; pointer-events: none; }
.player-label { position: absolute; font-size: 12px; background: rgba(255,255,255,0.8);
                padding: 1px 4px; }
.player-label.gone { color: #a02020; font-weight: bold; }
.player-label .sw { display: inline-block; width: 10px; height: 10px; margin-right: 4px; }
.player-controls { margin: 6px 0; display: flex; flex-wrap: wrap; gap: 8px; align-items: center;
                   font-size: 13px; }
#player-slider { width: 640px; }
#player-time { font-family: "DejaVu Sans Mono", monospace; min-width: 110px; }
#player-track { position: relative; display: inline-block; padding-bottom: 16px; }
#player-marks { position: absolute; left: 8px; right: 8px; top: 22px; height: 14px; }
.player-mark { position: absolute; top: 0; font-size: 11px; color: #d03030; white-space: nowrap;
               border-left: 2px solid #d03030; padding-left: 2px; }
#player-colorbar { display: flex; align-items: center; gap: 6px; font-size: 12px; }
#player-engines label { margin-right: 8px; }
#player-status { display: none; }
"""


def three_js_path():
    return os.environ.get("CLOTHBENCH_THREE_JS", THREE_JS)


def unavailable_reason(folders):
    """None when the player can be built, else the sentence the page shows in its place."""
    runs = [f for f in folders if f.has("summary.csv") or f.has("frames.csv")]
    if not runs:
        return "no run in this folder (the player shows what clothbench run wrote)"
    missing = [f.label for f in runs if not trajectory.available(f.path)]
    if missing:
        return (f"{', '.join(missing)} has no trajectory/ folder: runs write one unless the "
                f"scenario sets animation_interval = 0 (rerun with this clothbench)")
    path = three_js_path()
    if not os.path.isfile(path):
        return (f"three.js was not found at {path}: install Debian's libjs-three "
                f"(apt-get install libjs-three, or scripts/install-deps) and rebuild the report")
    return None


def _b64(a):
    return base64.b64encode(np.ascontiguousarray(a, dtype="<f4").tobytes()).decode("ascii")


def _quantized(x):
    """Positions as uint16 steps between the engine's smallest and largest coordinate per axis
    (half the bytes of float32; a step is 1/65535 of the extent, 0.06 mm on the 4 m seed
    cloth): {"lo": [3], "step": [3], "q": base64 of little-endian uint16}."""
    x = np.asarray(x, dtype=np.float64).reshape(-1, 3)
    if not len(x):
        return {"lo": [0, 0, 0], "step": [1, 1, 1], "q": ""}
    lo, hi = x.min(axis=0), x.max(axis=0)
    step = np.where(hi > lo, (hi - lo) / 65535.0, 1.0)
    q = np.round((x - lo) / step).astype("<u2")
    return {"lo": lo.tolist(), "step": step.tolist(),
            "q": base64.b64encode(q.tobytes()).decode("ascii")}


def _nice_up(x):
    """A round number >= x (1, 2 or 5 times a power of ten)."""
    if not (x > 0) or not math.isfinite(x):
        return 1.0
    p = 10 ** math.floor(math.log10(x))
    for m in (1, 2, 5, 10):
        if m * p >= x * (1 - 1e-12):
            return m * p
    return 10 * p


def payload(folders, colors):
    """The JSON the player reads: one set per folder, one entry per engine."""
    trajs = [trajectory.Trajectory(f.path) for f in folders]
    sets, engines = [], []
    same_grid = all(t.grid == trajs[0].grid for t in trajs)
    ref0 = None
    strain_hi, dist_hi = [], []
    for n, (f, tr) in enumerate(zip(folders, trajs)):
        idx = tr.index
        sets.append({"grid": list(tr.grid), "spacing": idx["spacing"], "springs": idx["springs"],
                     "shapes": idx["shapes"], "held": idx["held"], "interval": tr.interval,
                     "frames": idx["frames"], "colliders": _b64(tr.colliders),
                     "particles": int(idx.get("particles", tr.grid[0] * tr.grid[1])),
                     "triangles": [int(i) for i in tr.triangles().ravel()],
                     "edges": idx.get("edges")})
        first = len(engines)
        for e in idx["engines"]:
            label = e["name"] if len(folders) == 1 else f"{f.label}: {e['name']}"
            rgb = [float(c) for c in colors[e["name"]][:3]]
            engines.append({"name": e["name"] if len(folders) == 1 else label, "label": label,
                            "rgb": rgb, "set_index": n, "interval": tr.interval,
                            "frames": e["frames"], "stable": bool(e["stable"]),
                            "blowup_t": e["blowup_t"], "cause": e["cause"],
                            "crossings": tr.crossings(e["name"]),
                            "data": _quantized(tr.positions[e["name"]])})
        ref = first + [e["name"] for e in idx["engines"]].index(idx["reference"])
        # before/after: distances to the first folder's reference when the grids match
        if ref0 is None:
            ref0 = ref
        for e in engines[first:]:
            e["ref"] = ref0 if same_grid else ref
        # strain colour scale: the 99th percentile over the frames, rounded up
        for e in idx["engines"]:
            x = tr.positions[e["name"]]
            if len(x):
                step = max(1, len(x) // 30)
                strain_hi.append(np.percentile([tr.strain(x[k]) for k in range(0, len(x), step)], 99))
    for e in engines:
        r = engines[e["ref"]]
        a, b = _decode(e), _decode(r)
        m = min(len(a), len(b))
        if m and e is not r and a.shape[1:] == b.shape[1:] and e["interval"] == r["interval"]:
            # the median over frames of the largest distance: a start-up transient or a
            # blow-up would otherwise take the whole scale
            dist_hi.append(1000 * np.median(np.linalg.norm(a[:m] - b[:m], axis=-1).max(axis=1)))
    duration = max(tr.interval * (tr.index["frames"] - 1) for tr in trajs)
    return {"sets": sets, "engines": engines, "duration": duration,
            "start_t": _most_different_time(engines),
            "step": min(tr.interval for tr in trajs),
            "strain_scale": _nice_up(max(strain_hi, default=0.01)),
            "distance_scale_mm": _nice_up(max(dist_hi, default=1.0)),
            "colormap": _viridis()}


def _most_different_time(engines):
    """The time (s) of the frame where an engine is farthest (RMS) from its reference, where the
    player opens: the engines differ most there, while t = 0 shows every cloth alike."""
    best, best_t = 0.0, 0.0
    for e in engines:
        r = engines[e["ref"]]
        a, b = _decode(e), _decode(r)
        m = min(len(a), len(b))
        if not m or e is r or a.shape[1:] != b.shape[1:] or e["interval"] != r["interval"]:
            continue
        rms = np.sqrt(np.mean(np.sum((a[:m] - b[:m]) ** 2, axis=-1), axis=-1))
        rms[~np.isfinite(rms)] = 0
        k = int(np.argmax(rms))
        if rms[k] > best:
            best, best_t = float(rms[k]), k * e["interval"]
    return best_t


def _decode(e):
    """An engine's positions as the page sees them (frames, particles, 3)."""
    d = e["data"]
    q = np.frombuffer(base64.b64decode(d["q"]), dtype="<u2").reshape(-1, 3)
    a = np.asarray(d["lo"]) + q * np.asarray(d["step"])
    return a.reshape(e["frames"], -1, 3) if e["frames"] else a.reshape(0, 1, 3)


def _viridis():
    import matplotlib
    cmap = matplotlib.colormaps["viridis"]
    return [[round(float(c), 4) for c in cmap(k / 15)[:3]] for k in range(16)]


def player_script():
    """The player's JavaScript for the page's one inline script: the files of analysis/player/
    joined in PLAYER_SCRIPTS order, inside one function that runs at once.

    A report opened from file:// cannot load ES modules (the browser refuses module scripts
    from file://, and the page must open by double-click), so the files are plain scripts, not
    modules: no import or export lines, each declares its variables and functions at its top
    level, and the one function around all of them gives them a single shared scope, strict
    mode, and keeps them out of the page's global names. A file of analysis/player/ that is not
    in PLAYER_SCRIPTS is an error, so none can be left out silently."""
    present = sorted(f for f in os.listdir(PLAYER_DIR) if f.endswith(".js"))
    if present != sorted(PLAYER_SCRIPTS):
        raise RuntimeError(f"{PLAYER_DIR} holds {', '.join(present)}; player.py joins "
                           f"{', '.join(PLAYER_SCRIPTS)}")
    parts = []
    for name in PLAYER_SCRIPTS:
        with open(os.path.join(PLAYER_DIR, name), encoding="utf-8") as fh:
            parts.append(f"// --- player/{name}\n{fh.read()}")
    return '(function () {\n"use strict";\n' + "\n".join(parts) + "})();\n"


def section(folders, colors):
    """The player's HTML (heading included), or a paragraph saying why it is left out."""
    E = html.escape
    head = "<h2 id=\"player-heading\">See the cloths move</h2>"
    if not any(f.has("summary.csv") or f.has("frames.csv") for f in folders):
        return ""  # a sweep folder: nothing moves
    reason = unavailable_reason(folders)
    if reason:
        return head + f'<p class="skipped" id="player-missing">3D player left out: {E(reason)}.</p>'
    runs = [f for f in folders if f.has("summary.csv") or f.has("frames.csv")]
    data = json.dumps(payload(runs, colors), separators=(",", ":"))
    with open(three_js_path(), encoding="utf-8") as fh:
        three = fh.read()
    player = player_script()
    controls = (
        '<div class="player-controls">'
        '<button id="player-play">▶ play</button>'
        '<button id="player-back" title="one frame back">◀ step</button>'
        '<button id="player-fwd" title="one frame on">step ▶</button>'
        '<label>speed <select id="player-speed"><option value="0.1">0.1×</option>'
        '<option value="0.25">0.25×</option><option value="0.5">0.5×</option>'
        '<option value="1" selected>1×</option><option value="2">2×</option></select></label>'
        '<span id="player-track"><input type="range" id="player-slider" min="0" value="0">'
        '<span id="player-marks"></span></span>'
        '<span id="player-time">t = 0 s</span></div>'
        '<div class="player-controls">'
        '<label>layout <select id="player-layout"><option value="grid">grid (one view per '
        'engine, one camera)</option><option value="overlay">overlay</option></select></label>'
        '<label>colour <select id="player-color"><option value="engine">by engine</option>'
        '<option value="strain">by strain</option>'
        '<option value="distance">by distance to the reference</option></select></label>'
        '<span id="player-colorbar" style="visibility:hidden"><span class="cb-lo">0</span>'
        '<canvas width="200" height="12"></canvas><span class="cb-hi"></span>'
        '<span class="cb-text"></span></span></div>'
        '<div class="player-controls" id="player-engines">engines shown:</div>')
    note = ("Drag to orbit, shift-drag (or right-drag) to pan, wheel to zoom: every view shares "
            "one camera. Grey shapes are the colliders (spheres, planes, boxes, capsules, cylinders), black dots the held particles. An engine "
            "that blew up keeps its last stable shape, greyed, from its blow-up time (✕ on the "
            "timeline). The address bar keeps the view: report.html#t=1.5&amp;color=distance&amp;"
            "layout=grid&amp;engines=a,b opens it again.")
    return (head + '<div id="player">' + controls +
            '<div id="player-canvas-box"><div id="player-labels"></div></div>'
            f'<p class="notes">{note}</p><pre id="player-status"></pre></div>'
            f"<script>{three}</script>"
            f"<script>window.CLOTHBENCH_PLAYER = {data};</script>"
            f"<script>{player}</script>")
