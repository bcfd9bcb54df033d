"""One clothbench output folder: whichever CSV files it holds, its scenario and run info.

A run folder (`clothbench run`) holds frames, divergence, snapshots and summary; a sweep folder
(`clothbench stability` / `accuracy`) holds stability, work_precision, convergence and
recommendation, and resolution with `accuracy --resolutions`. A folder may hold any subset; the
report draws what is there.
"""

import json
import math
import os
import tomllib

import numpy as np

from .csvio import SCHEMAS, ReportError, read_table

CSV_FILES = list(SCHEMAS)


class Folder:
    """The parsed contents of one output folder.

    path      the folder
    label     short name used in legends and titles ("before", "after", or the folder name)
    tables    CSV file name -> Table, only for files present
    scenario  the resolved scenario (dict from scenario.toml) or {}
    scenario_text  scenario.toml as text, or ""
    run_info  run.json as a dict, or {}
    modes     (rest, {row: mode}) from stability_modes/ (a growth stability sweep), else None:
              rest 3 by #P rest positions (m), mode 3 by #P growing mode of stability.csv's
              row (0-based) at its growth_first_unstable_dt
    """

    def __init__(self, path, label=None):
        self.path = path
        self.label = label or os.path.basename(os.path.normpath(path)) or path
        if not os.path.exists(path):
            raise ReportError(f"{path}: no such folder")
        if not os.path.isdir(path):
            raise ReportError(f"{path}: not a folder (give the output folder of a clothbench run)")
        self.tables = {}
        for name in CSV_FILES:
            file = os.path.join(path, name)
            if os.path.exists(file):
                self.tables[name] = read_table(file)
        if not self.tables:
            raise ReportError(f"{path}: no clothbench CSV file found (expected one of: "
                              f"{', '.join(CSV_FILES)})")
        self.scenario, self.scenario_text = _read_toml(os.path.join(path, "scenario.toml"))
        self.run_info = _read_json(os.path.join(path, "run.json"))
        self._check_consistency()
        self.modes = self._read_modes()

    # --- what is there ---------------------------------------------------------------------

    def has(self, name):
        """True when the CSV file is present and has at least one data row."""
        return name in self.tables and len(self.tables[name]) > 0

    def table(self, name):
        return self.tables[name]

    @property
    def name(self):
        """Scenario name, or the folder name when there is no scenario.toml."""
        return str(self.scenario.get("name") or os.path.basename(os.path.normpath(self.path)))

    def engines(self):
        """Engine names of a run folder, in the order the files list them."""
        for name in ("summary.csv", "frames.csv", "snapshots.csv", "divergence.csv"):
            if self.has(name):
                return self.table(name).unique("engine")
        return []

    def reference(self):
        """Name of the reference engine: from divergence.csv, the scenario, or the first engine."""
        if self.has("divergence.csv"):
            refs = self.table("divergence.csv").unique("reference")
            if refs:
                return refs[0]
        ref = self.scenario.get("reference")
        if ref:
            return str(ref)
        engines = self.engines()
        return engines[0] if engines else ""

    def engine_info(self, engine):
        """Summary row of an engine as a dict, or {} without summary.csv."""
        if not self.has("summary.csv"):
            spec = next((e for e in self.scenario.get("engine", []) if e.get("name") == engine), {})
            return {"engine": engine, "kind": spec.get("kind", ""),
                    "integrator": spec.get("integrator", ""), "dt": spec.get("dt", math.nan)}
        rows = self.table("summary.csv").select(engine=engine)
        return next(rows.rows(), {})

    def energy_gated(self, engine):
        """(gated, note): whether the engine's energy error measures its time scheme, as the
        run.json that clothbench wrote says of its kind; (True, "") when it says nothing."""
        kind = self.engine_info(engine).get("kind", "")
        facts = self.run_info.get("engine_kinds", {}).get(kind, {})
        return bool(facts.get("energy_gated", True)), str(facts.get("energy_note", ""))

    def self_collision(self, engine):
        """"on", "off" or "not available": the engine's self-collision as run.json gives it;
        "" when run.json does not say (a run written before self-contact)."""
        return str(self.run_info.get("self_collision", {}).get(engine, ""))

    def expected_order(self, integrator):
        """Order of accuracy of a custom integrator as run.json gives it, or None."""
        order = self.run_info.get("integrators", {}).get(integrator, {}).get("order")
        return int(order) if isinstance(order, (int, float)) else None

    def blowup(self, engine):
        """Blow-up time (s) of an unstable engine, or None when it stayed stable (or unknown)."""
        info = self.engine_info(engine)
        if info and "stable" in info and not math.isnan(info["stable"]):
            if info["stable"] >= 0.5:
                return None
            t = info.get("blowup_t", math.nan)
            if not math.isnan(t):
                return float(t)
        if self.has("frames.csv"):
            rows = self.table("frames.csv").select(engine=engine)
            bad = rows["t"][rows["stable"] < 0.5]
            if len(bad):
                return float(bad.min())
        if info and "stable" in info and info["stable"] < 0.5:
            return math.nan
        return None

    def blowup_strain(self):
        return float(self.scenario.get("blowup_strain", 1.0))

    # --- snapshots ---------------------------------------------------------------------------

    def snapshot_times(self, engine):
        rows = self.table("snapshots.csv").select(engine=engine)
        return sorted(set(float(t) for t in rows["t"]))

    def snapshot(self, engine, t):
        """Cloth at a snapshot time as a nu by nv by 3 array (NaN where a point is missing)."""
        snaps = self.table("snapshots.csv")
        rows = snaps.where((snaps["engine"] == engine) & (snaps["t"] == t))
        nu, nv = self.grid_shape()
        grid = np.full((nu, nv, 3), np.nan)
        i = rows["i"].astype(int)
        j = rows["j"].astype(int)
        grid[i, j, 0] = rows["x"]
        grid[i, j, 1] = rows["y"]
        grid[i, j, 2] = rows["z"]
        return grid

    def mesh_faces(self):
        """A mesh cloth's triangles as an int array (faces, 3) of snapshot indices i (mesh.obj,
        which a run writes beside a mesh's CSVs), or None for a grid. Read once."""
        if not hasattr(self, "_faces"):
            self._faces = _read_obj_faces(os.path.join(self.path, "mesh.obj"))
        return self._faces

    def grid_shape(self):
        """(nu, nv) of the cloth: from the scenario, else from the largest indices."""
        snaps = self.table("snapshots.csv")
        nu = int(np.max(snaps["i"])) + 1
        nv = int(np.max(snaps["j"])) + 1
        particles = self.scenario.get("cloth", {}).get("particles")
        if isinstance(particles, list) and len(particles) == 2:
            nu, nv = max(nu, int(particles[0])), max(nv, int(particles[1]))
        return nu, nv

    # --- growing modes of a stability sweep --------------------------------------------------

    def _read_modes(self):
        """(rest, {row: mode}) of stability_modes/, None without it (an older folder). Every
        file is read and checked here, so a corrupt one stops the report before any plot."""
        folder = os.path.join(self.path, "stability_modes")
        if not os.path.isdir(folder) or "stability.csv" not in self.tables:
            return None
        names = sorted(n for n in os.listdir(folder) if n.endswith(".npy"))
        rows = sorted(int(n[:-4]) for n in names if n[:-4].isdigit())
        if not rows:
            return None
        rest = _read_npy(os.path.join(folder, "rest.npy"), None)
        table = self.tables["stability.csv"]
        modes = {}
        for row in rows:
            file = os.path.join(folder, f"{row}.npy")
            if row >= len(table):
                raise ReportError(f"{file}: stability.csv has no row {row} (it has "
                                  f"{len(table)} rows, counted from 0)")
            modes[row] = _read_npy(file, rest.shape[1])
        return rest, modes

    # --- checks ------------------------------------------------------------------------------

    def _check_consistency(self):
        if "snapshots.csv" in self.tables:
            snaps = self.tables["snapshots.csv"]
            for col in ("i", "j"):
                v = snaps[col]
                bad = ~np.isfinite(v) | (v < 0) | (v != np.round(v))
                if np.any(bad):
                    k = int(np.argmax(bad))
                    raise ReportError(f"{snaps.path}: column '{col}' must hold grid indices "
                                      f"(integers >= 0), found {v[k]!r}")
        for name in ("frames.csv", "divergence.csv", "snapshots.csv"):
            if name in self.tables:
                t = self.tables[name]["t"]
                if np.any(~np.isfinite(t)):
                    raise ReportError(f"{self.tables[name].path}: column 't' has a non-finite time")


def _read_npy(path, particles):
    """A 3 by #P float array from a .npy file (#P = particles unless None), finite throughout;
    ReportError naming the file for anything else."""
    if not os.path.exists(path):
        raise ReportError(f"{path}: file not found (stability_modes/ holds growing modes, so "
                          "it needs the rest positions too)")
    try:
        a = np.load(path, allow_pickle=False)
    except (OSError, ValueError, EOFError) as e:
        raise ReportError(f"{path}: not a readable .npy array: {' '.join(str(e).split())}") \
            from None
    if not isinstance(a, np.ndarray) or a.ndim != 2 or a.shape[0] != 3 or a.shape[1] == 0 \
            or a.dtype.kind not in "fiu":
        raise ReportError(f"{path}: expected a 3 by #P array of numbers, found shape "
                          f"{getattr(a, 'shape', '?')} of {getattr(a, 'dtype', '?')}")
    if particles is not None and a.shape[1] != particles:
        raise ReportError(f"{path}: {a.shape[1]} particles, but rest.npy has {particles}")
    if not np.all(np.isfinite(a)):
        raise ReportError(f"{path}: holds a non-finite value")
    return a.astype(float)


def _read_obj_faces(path):
    """The f lines of an OBJ file as 0-based (faces, 3) indices, None when there is no file."""
    if not os.path.exists(path):
        return None
    faces = []
    try:
        with open(path, encoding="utf-8") as f:
            for n, line in enumerate(f, 1):
                if line.startswith("f "):
                    faces.append([int(w.split("/")[0]) - 1 for w in line.split()[1:4]])
    except (OSError, UnicodeDecodeError, ValueError) as e:
        raise ReportError(f"{path}: cannot read the mesh's triangles: {e}") from None
    return np.array(faces, dtype=np.int64).reshape(-1, 3)


def _read_toml(path):
    """(dict, text) of a TOML file, or ({}, "") when it does not exist."""
    if not os.path.exists(path):
        return {}, ""
    try:
        with open(path, "rb") as f:
            text = f.read().decode("utf-8")
        return tomllib.loads(text), text
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as e:
        raise ReportError(f"{path}: not valid TOML: {e}") from None
    except OSError as e:
        raise ReportError(f"{path}: cannot read: {e}") from None


def _read_json(path):
    if not os.path.exists(path):
        return {}
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise ReportError(f"{path}: not valid JSON: {e}") from None
    except OSError as e:
        raise ReportError(f"{path}: cannot read: {e}") from None
    if not isinstance(data, dict):
        raise ReportError(f"{path}: expected a JSON object")
    return data
