"""What every plot shares: backend, colours per engine, line style per folder, titles, saving."""

import math
import os
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ..quantities import num as fmt  # noqa: E402,F401  (3 significant digits, short exponents)

DPI = 110                 # PNG resolution: a 12 in wide figure is 1320 px, the page's width
FONT = 10                 # pt, base font size
RUN_STYLES = ["-", "--"]  # line style of the first and the second folder (--compare)
RUN_MARKERS = ["o", "s"]

plt.rcParams.update({
    "font.size": FONT,
    "axes.titlesize": FONT + 1,
    "axes.labelsize": FONT,
    "legend.fontsize": FONT - 1,
    "figure.titlesize": FONT + 2,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "svg.fonttype": "none",
})

# tab10 without its red, which marks blow-ups and tolerances, then the light shades of the same
# hues (tab20's odd entries, light red left out too): 18 distinct colours before one repeats
_PALETTE = ([c for k, c in enumerate(plt.get_cmap("tab10").colors) if k != 3] +
            [c for k, c in enumerate(plt.get_cmap("tab20").colors) if k % 2 == 1 and k != 7])


class Colors:
    """A fixed colour per key (engine, or engine/integrator) shared by every plot of a report."""

    def __init__(self, keys=()):
        self._map = {}
        for key in keys:
            self[key]

    def __getitem__(self, key):
        if key not in self._map:
            self._map[key] = _PALETTE[len(self._map) % len(_PALETTE)]
        return self._map[key]


def engine_label(folder, engine):
    """engine (integrator, dt 2e-4 s) from the summary or the scenario."""
    info = folder.engine_info(engine)
    parts = []
    integ = info.get("integrator", "") if info else ""
    if integ:
        parts.append(str(integ))
    dt = info.get("dt", math.nan) if info else math.nan
    if isinstance(dt, (int, float)) and not math.isnan(dt):
        parts.append(f"dt {fmt(float(dt))} s")
    return f"{engine} ({', '.join(parts)})" if parts else engine


def scenario_params(folder):
    """Key parameters of the scenario, ordered (name, text with unit)."""
    sc = folder.scenario
    cloth = sc.get("cloth", {})
    out = []
    p = cloth.get("particles")
    if isinstance(p, list) and len(p) == 2:
        out.append(("grid", f"{p[0]}×{p[1]} particles"))
    size = cloth.get("size")
    if isinstance(size, list) and len(size) == 2:
        out.append(("size", f"{fmt(size[0])}×{fmt(size[1])} m"))
    if "particle_mass" in cloth:
        out.append(("mass", f"{fmt(cloth['particle_mass'])} kg/particle"))
    elif "total_mass" in cloth:
        out.append(("mass", f"{fmt(cloth['total_mass'])} kg total"))
    k = cloth.get("stiffness")
    if isinstance(k, dict) and k:
        values = sorted({float(v) for v in k.values() if isinstance(v, (int, float))})
        if len(values) == 1:
            out.append(("k", f"k {fmt(values[0])} N/m ({'/'.join(k)})"))
        else:
            out.append(("k", "k " + ", ".join(f"{n} {fmt(v)}" for n, v in k.items()) + " N/m"))
    if "damping" in cloth:
        out.append(("damping", f"damping {fmt(cloth['damping'])} N·s/m"))
    if cloth.get("air_drag"):
        out.append(("air_drag", f"air drag {fmt(cloth['air_drag'])}"))
    spheres = sc.get("sphere", [])
    spheres = [spheres] if isinstance(spheres, dict) else spheres
    for n, s in enumerate(spheres if isinstance(spheres, list) else []):
        if isinstance(s, dict) and "radius" in s:
            out.append((f"sphere{n}", f"sphere r {fmt(s['radius'])} m"))
    cons = sc.get("constraint", [])
    if isinstance(cons, list) and cons:
        out.append(("constraints", "held: " + ", ".join(
            str(c.get("select", "?")) if isinstance(c, dict) else "?" for c in cons)))
    if "duration" in sc:
        out.append(("duration", f"{fmt(sc['duration'])} s simulated"))
    return out


def _merged_params(folders):
    """Parameters of one folder, or 'a → b' where two folders differ."""
    if len(folders) == 1:
        return [text for _, text in scenario_params(folders[0])]
    a, b = (dict(scenario_params(f)) for f in folders[:2])
    out = []
    for key in list(a) + [k for k in b if k not in a]:
        ta, tb = a.get(key), b.get(key)
        # a folder without scenario.toml (a sweep, say) has nothing to say about the scene
        if ta is None or tb is None or ta == tb or not a or not b:
            out.append(ta or tb)
        else:
            out.append(f"{ta} → {tb}")
    return out


# how the two folders of --compare are told apart, by kind of plot
COMPARE_LINES = {
    "lines": "{a} (solid) vs {b} (dashed)",
    "panels": "{a} (left) vs {b} (right)",
    "markers": "{a} (filled markers) vs {b} (hollow markers)",
    "rows": "{a} and {b}: one row each per engine",
    "labelled": "{a} and {b}: each panel's title names its folder",
}


def title(fig, what, folders, engines_line=None, width_in=None, compare="lines"):
    """Suptitle: what and scenario, engines, key parameters; wrapped to the figure's width.

    folders       one Folder, or two for --compare
    engines_line  text for the second line (default: engines with integrator and dt)
    compare       how the two folders are drawn: a key of COMPARE_LINES
    """
    width_in = width_in or fig.get_figwidth()
    chars = max(60, int(width_in * 72 / (FONT * 0.56)))
    names = []
    for f in folders:
        if f.name not in names:
            names.append(f.name)
    head = f"{what} — {' / '.join(names)}"
    lines = [head]
    if len(folders) == 2:
        lines.append(COMPARE_LINES[compare].format(a=folders[0].label, b=folders[1].label))
    if engines_line is None:
        engines = []
        for f in folders:
            for e in f.engines():
                label = engine_label(f, e)
                if e == f.reference() and f.has("divergence.csv"):
                    label += " [reference]"
                if label not in engines:
                    engines.append(label)
        engines_line = "engines: " + ", ".join(engines) if engines else ""
    if engines_line:
        lines.append(engines_line)
    params = _merged_params(folders)
    if params:
        lines.append(" · ".join(params))
    wrapped = []
    for n, line in enumerate(lines):
        wrapped.extend(textwrap.wrap(line, chars) or [""])
    fig.suptitle("\n".join(wrapped), fontsize=FONT + 1, linespacing=1.35)


def save(fig, outdir, stem, svg):
    """Write stem.png (and stem.svg); returns the PNG path."""
    png = os.path.join(outdir, stem + ".png")
    fig.savefig(png, dpi=DPI)
    if svg:
        fig.savefig(os.path.join(outdir, stem + ".svg"))
    plt.close(fig)
    return png


def finite(a):
    a = np.asarray(a, dtype=float)
    return a[np.isfinite(a)]


def use_log(values, span=100.0):
    """True when the positive finite values span more than `span` (a log axis reads better)."""
    v = finite(values)
    v = v[v > 0]
    return len(v) > 1 and v.max() / v.min() > span and len(v) >= 0.8 * len(finite(values))


def note(ax, text):
    """A message in the middle of an empty panel."""
    ax.text(0.5, 0.5, text, ha="center", va="center", transform=ax.transAxes, fontsize=FONT,
            color="0.35", wrap=True)


def config_key(engine, integrator):
    """Legend name of one sweep configuration: 'engine / integrator', or the engine alone."""
    return f"{engine} / {integrator}" if integrator else str(engine)


def configs(table):
    """(engine, integrator) pairs of a sweep table in order of first appearance."""
    seen = {}
    for e, i in zip(table["engine"], table["integrator"]):
        seen.setdefault((e, i), None)
    return list(seen)


def sweep_line(folders, names=("work_precision.csv", "stability.csv", "convergence.csv")):
    """Second title line of a sweep plot: the configurations swept."""
    keys = []
    for f in folders:
        for name in names:
            if f.has(name):
                for e, i in configs(f.table(name)):
                    if config_key(e, i) not in keys:
                        keys.append(config_key(e, i))
    return "configurations: " + ", ".join(keys) if keys else ""


def legend(ax, **kwargs):
    """ax.legend(**kwargs) when the axes have labelled artists (no warning on empty plots)."""
    if ax.get_legend_handles_labels()[0]:
        ax.legend(**kwargs)
