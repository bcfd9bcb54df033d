"""Generate the synthetic output folders in analysis/tests/fixtures/.

The C++ runner writes these files for real; until a small real run is wired into the tests,
the fixtures come from a tiny numpy mass-spring cloth (7 x 7 particles dropped on a sphere) run
with four integrators, so that energies, strains, divergence and drape are physically coherent.
The "bullet-softbody" engine of the fixture is a stand-in (linearised implicit Euler), not Bullet.

    /usr/bin/python3 analysis/tests/make_fixtures.py      # rewrites analysis/tests/fixtures/

Folders written:
    fixtures/run/         frames, divergence, snapshots, summary, scenario.toml, run.json
    fixtures/run_after/   the same scene with less damping (the "after" side of --compare)
    fixtures/sweep/       stability, work_precision, convergence, recommendation (model data)
"""

import json
import math
import os
import sys

import numpy as np

FIXTURES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "fixtures")

# scene: the seed drape, scaled down to 7 x 7 particles
NU, NV = 7, 7
SIZE = 2.0              # m, square cloth
CENTER_Y = 1.0          # m, cloth height at t = 0
MASS = 1.0              # kg per particle
STIFFNESS = 20000.0     # N/m, structural, shear and bend
GRAVITY = -9.8          # m/s^2 along y
SPHERE_C = np.array([0.0, 0.4, 0.0])  # m
SPHERE_R = 0.5          # m
MARGIN = 0.01           # m
FRICTION = 0.3
DURATION = 2.0          # s
FRAME_DT = 0.02         # s
SNAP_DT = 0.5           # s
BLOWUP_STRAIN = 1.0

ENGINES = [  # name, kind, integrator, dt
    ("custom-rk4", "custom", "rk4", 2e-4),
    ("custom-symplectic", "custom", "symplectic-euler", 2e-4),
    ("custom-explicit", "custom", "explicit-euler", 4e-4),
    ("bullet-softbody", "bullet-softbody", "", 1e-3),
]

# the facts about engine kinds and integrators that clothbench writes into run.json
# (run_info_json in src/harness/run/runner.cpp), which the report reads: fixture data
FACTS = {
    "engine_kinds": {
        "custom": {"has_integrators": True, "energy_gated": True, "energy_note": ""},
        "bullet-deformable": {"has_integrators": False, "energy_gated": True, "energy_note": ""},
        "bullet-softbody": {"has_integrators": False, "energy_gated": False,
                            "energy_note": "0 by construction (bullet-softbody books its energy "
                                           "balance as dissipated)"}},
    "integrators": {name: {"order": order, "force_evals_per_step": evals} for name, order, evals in
                    [("explicit-euler", 1, 1), ("symplectic-euler", 1, 1),
                     ("picard-implicit", 1, 2), ("midpoint", 2, 2), ("rk4", 4, 4),
                     ("implicit-euler", 1, 1)]}}


class Cloth:
    """A square mass-spring grid; particle p = i * NV + j, positions are #P by 3."""

    def __init__(self, damping):
        i, j = np.meshgrid(np.arange(NU), np.arange(NV), indexing="ij")
        self.ij = np.stack([i.ravel(), j.ravel()], axis=1)
        h = SIZE / (NU - 1)
        self.x0 = np.stack([-SIZE / 2 + i.ravel() * h, np.full(NU * NV, CENTER_Y),
                            -SIZE / 2 + j.ravel() * h], axis=1)
        idx = lambda a, b: a * NV + b
        pairs = []
        for a in range(NU):
            for b in range(NV):
                for da, db in ((1, 0), (0, 1), (1, 1), (1, -1), (2, 0), (0, 2)):
                    if 0 <= a + da < NU and 0 <= b + db < NV:
                        pairs.append((idx(a, b), idx(a + da, b + db)))
        self.a = np.array([p[0] for p in pairs])
        self.b = np.array([p[1] for p in pairs])
        self.l0 = np.linalg.norm(self.x0[self.b] - self.x0[self.a], axis=1)
        self.damping = damping
        self.n = NU * NV
        self.m = MASS
        # two triangles per grid cell, for the shadow area
        tris = []
        for a in range(NU - 1):
            for b in range(NV - 1):
                tris.append((idx(a, b), idx(a + 1, b), idx(a + 1, b + 1)))
                tris.append((idx(a, b), idx(a + 1, b + 1), idx(a, b + 1)))
        self.tris = np.array(tris)

    def spring_terms(self, x, v):
        d = x[self.b] - x[self.a]
        length = np.linalg.norm(d, axis=1)
        u = d / length[:, None]
        rate = np.sum((v[self.b] - v[self.a]) * u, axis=1)
        return u, length, rate

    def forces(self, x, v):
        u, length, rate = self.spring_terms(x, v)
        f = (STIFFNESS * (length - self.l0) + self.damping * rate)[:, None] * u
        out = np.zeros_like(x)
        out[:, 1] += self.m * GRAVITY
        for c in range(3):
            out[:, c] += np.bincount(self.a, f[:, c], self.n) - np.bincount(self.b, f[:, c], self.n)
        return out

    def damping_power(self, x, v):
        _, _, rate = self.spring_terms(x, v)
        return float(np.sum(self.damping * rate ** 2))

    def jacobians(self, x):
        """Dense 3#P by 3#P stiffness and damping Jacobians (damping: direction frozen)."""
        d = x[self.b] - x[self.a]
        length = np.linalg.norm(d, axis=1)
        u = d / length[:, None]
        uu = u[:, :, None] * u[:, None, :]
        eye = np.eye(3)[None]
        ks = STIFFNESS * (uu + (1.0 - self.l0 / length)[:, None, None] * (eye - uu))
        cs = self.damping * uu
        k4 = np.zeros((self.n, self.n, 3, 3))
        c4 = np.zeros((self.n, self.n, 3, 3))
        for blocks, mat in ((k4, ks), (c4, cs)):
            np.add.at(blocks, (self.a, self.a), -mat)
            np.add.at(blocks, (self.b, self.b), -mat)
            np.add.at(blocks, (self.a, self.b), mat)
            np.add.at(blocks, (self.b, self.a), mat)
        k = k4.transpose(0, 2, 1, 3).reshape(3 * self.n, 3 * self.n)
        c = c4.transpose(0, 2, 1, 3).reshape(3 * self.n, 3 * self.n)
        return k, c

    def energies(self, x, v):
        _, length, _ = self.spring_terms(x, v)
        kinetic = 0.5 * self.m * float(np.sum(v * v))
        gravity = -self.m * GRAVITY * float(np.sum(x[:, 1]))
        elastic = 0.5 * STIFFNESS * float(np.sum((length - self.l0) ** 2))
        return kinetic, gravity, elastic

    def strain(self, x):
        length = np.linalg.norm(x[self.b] - x[self.a], axis=1)
        return np.abs(length / self.l0 - 1.0)

    def shadow_area(self, x, cells=160):
        """Area of the union of the triangles projected on the x-z plane (rasterised)."""
        p = x[:, [0, 2]]
        lo, hi = p.min(axis=0), p.max(axis=0)
        gx = np.linspace(lo[0], hi[0], cells)
        gz = np.linspace(lo[1], hi[1], cells)
        px, pz = np.meshgrid(gx, gz, indexing="ij")
        inside = np.zeros(px.shape, dtype=bool)
        for t in self.tris:
            (x1, z1), (x2, z2), (x3, z3) = p[t]
            det = (z2 - z3) * (x1 - x3) + (x3 - x2) * (z1 - z3)
            if abs(det) < 1e-14:
                continue
            l1 = ((z2 - z3) * (px - x3) + (x3 - x2) * (pz - z3)) / det
            l2 = ((z3 - z1) * (px - x3) + (x1 - x3) * (pz - z3)) / det
            inside |= (l1 >= 0) & (l2 >= 0) & (l1 + l2 <= 1)
        cell = (hi[0] - lo[0]) / (cells - 1) * (hi[1] - lo[1]) / (cells - 1)
        return float(inside.sum() * cell)


def collide(x, v):
    """Push particles out of the sphere (in place), removing inward and frictional velocity."""
    d = x - SPHERE_C
    dist = np.linalg.norm(d, axis=1)
    hit = dist < SPHERE_R + MARGIN
    if not np.any(hit):
        return
    n = d[hit] / dist[hit][:, None]
    x[hit] = SPHERE_C + n * (SPHERE_R + MARGIN)
    vh = v[hit]
    vn = np.sum(vh * n, axis=1)
    inward = np.minimum(vn, 0.0)
    vh = vh - inward[:, None] * n
    vt = vh - np.sum(vh * n, axis=1)[:, None] * n
    speed_t = np.linalg.norm(vt, axis=1)
    slow = FRICTION * np.abs(inward) / np.maximum(speed_t, 1e-300)
    keep = np.where(speed_t > 0, np.maximum(0.0, 1.0 - slow), 1.0)
    vh = vh - (1.0 - keep)[:, None] * vt
    v[hit] = vh


def step(cloth, integrator, x, v, dt):
    """One step; returns new x, v and the energy that spring damping removed (J)."""
    acc = lambda xs, vs: cloth.forces(xs, vs) / cloth.m
    lost = dt * cloth.damping_power(x, v)
    if integrator == "explicit-euler":
        a = acc(x, v)
        x, v = x + dt * v, v + dt * a
    elif integrator == "symplectic-euler":
        v = v + dt * acc(x, v)
        x = x + dt * v
        lost = dt * cloth.damping_power(x, v)
    elif integrator == "rk4":
        k1x, k1v = v, acc(x, v)
        k2x, k2v = v + 0.5 * dt * k1v, acc(x + 0.5 * dt * k1x, v + 0.5 * dt * k1v)
        k3x, k3v = v + 0.5 * dt * k2v, acc(x + 0.5 * dt * k2x, v + 0.5 * dt * k2v)
        k4x, k4v = v + dt * k3v, acc(x + dt * k3x, v + dt * k3v)
        p1 = cloth.damping_power(x, v)
        p2 = cloth.damping_power(x + 0.5 * dt * k1x, v + 0.5 * dt * k1v)
        p3 = cloth.damping_power(x + 0.5 * dt * k2x, v + 0.5 * dt * k2v)
        p4 = cloth.damping_power(x + dt * k3x, v + dt * k3v)
        lost = dt * (p1 + 2 * p2 + 2 * p3 + p4) / 6.0
        x = x + dt * (k1x + 2 * k2x + 2 * k3x + k4x) / 6.0
        v = v + dt * (k1v + 2 * k2v + 2 * k3v + k4v) / 6.0
    else:  # linearised implicit Euler (Baraff-Witkin), the fixture's stand-in for Bullet
        k, c = cloth.jacobians(x)
        n3 = 3 * cloth.n
        f = cloth.forces(x, v).ravel()
        lhs = cloth.m * np.eye(n3) - dt * c - dt * dt * k
        dv = np.linalg.solve(lhs, dt * (f + dt * (k @ v.ravel())))
        v = v + dv.reshape(-1, 3)
        x = x + dt * v
        lost = dt * cloth.damping_power(x, v)
    return x, v, lost


def simulate(cloth, integrator, dt):
    """Run one engine; returns frames (list of dicts) and snapshots {t: positions}."""
    x, v = cloth.x0.copy(), np.zeros_like(cloth.x0)
    steps_per_frame = int(round(FRAME_DT / dt))
    frames_per_snap = int(round(SNAP_DT / FRAME_DT))
    n_frames = int(round(DURATION / FRAME_DT))
    e0 = sum(cloth.energies(x, v))
    dissipated = 0.0
    contact_work = 0.0
    frames, snaps = [], {}
    t = 0.0

    def record(stable):
        kin, grav, ela = cloth.energies(x, v)
        total = kin + grav + ela
        strain = cloth.strain(x)
        finite = np.all(np.isfinite(x))
        dist = np.linalg.norm(x - SPHERE_C, axis=1)
        frames.append(dict(
            t=t, kinetic=kin, gravity_potential=grav, elastic_potential=ela,
            dissipated=dissipated, contact_work=contact_work, unbooked=0.0, total_energy=total,
            energy_error=total + dissipated - contact_work - e0,
            max_strain=float(strain.max()), mean_strain=float(strain.mean()),
            com_x=float(x[:, 0].mean()), com_y=float(x[:, 1].mean()), com_z=float(x[:, 2].mean()),
            min_y=float(x[:, 1].min()), max_penetration=float(max(0.0, np.max(SPHERE_R - dist))),
            shadow_area=cloth.shadow_area(x) if finite else float("nan"), stable=int(stable),
            x=x.copy(), v=v.copy()))

    record(True)
    snaps[0.0] = x.copy()
    with np.errstate(all="ignore"):
        for frame in range(1, n_frames + 1):
            for s in range(steps_per_frame):
                x, v, lost = step(cloth, integrator, x, v, dt)
                # the contact response's whole energy change is its work, booked apart from
                # the dampers, as the custom engine books it
                before = sum(cloth.energies(x, v))
                collide(x, v)
                dissipated += lost
                contact_work += sum(cloth.energies(x, v)) - before
                t = (frame - 1) * FRAME_DT + (s + 1) * dt
                strain = cloth.strain(x)
                finite = np.all(np.isfinite(x)) and not np.isnan(strain).any()
                if not finite or np.nanmax(strain) > BLOWUP_STRAIN:
                    record(False)
                    snaps[t] = x.copy()
                    return frames, snaps, t
            t = frame * FRAME_DT
            record(True)
            if frame % frames_per_snap == 0 or frame == n_frames:
                snaps[t] = x.copy()
    return frames, snaps, None


def num(value):
    """CSV text of a number: 7 significant digits, nan/inf spelled as C++ streams do."""
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "nan"
    if math.isinf(value):
        return "inf" if value > 0 else "-inf"
    return f"{value:.7g}"


def write_csv(path, header, rows):
    """RFC 4180 CSV: text with a comma or a quote is quoted."""
    def cell_text(cell):
        if not isinstance(cell, str):
            return num(cell)
        if any(ch in cell for ch in ',"\n'):
            return '"' + cell.replace('"', '""') + '"'
        return cell

    with open(path, "w", encoding="utf-8") as f:
        f.write(",".join(header) + "\n")
        for row in rows:
            f.write(",".join(cell_text(cell) for cell in row) + "\n")


FRAME_COLS = ["engine", "t", "kinetic", "gravity_potential", "elastic_potential", "dissipated",
              "contact_work", "unbooked", "total_energy", "energy_error", "max_strain", "mean_strain", "com_x", "com_y",
              "com_z", "min_y", "max_penetration", "shadow_area", "stable"]


def scenario_toml(name, damping):
    lines = [
        f'name = "{name}"',
        'description = "A 7 x 7 cloth dropped on a sphere: the seed drape scaled down '
        '(synthetic fixture)."',
        f"duration = {DURATION}",
        f"frame_interval = {FRAME_DT}",
        f"snapshot_interval = {SNAP_DT}",
        f"blowup_strain = {BLOWUP_STRAIN}",
        'reference = "custom-rk4"',
        f"gravity = [0.0, {GRAVITY}, 0.0]",
        "",
        "[cloth]",
        f"particles = [{NU}, {NV}]",
        f"size = [{SIZE}, {SIZE}]",
        f"center = [0.0, {CENTER_Y}, 0.0]",
        'plane = "xz"',
        f"particle_mass = {MASS}",
        f"stiffness = {{ structural = {STIFFNESS}, shear = {STIFFNESS}, bend = {STIFFNESS} }}",
        f"damping = {damping}",
        "air_drag = 0.0",
        "",
        "[[sphere]]",
        f"center = [{SPHERE_C[0]}, {SPHERE_C[1]}, {SPHERE_C[2]}]",
        f"radius = {SPHERE_R}",
        "restitution = 0.0",
        f"friction = {FRICTION}",
        "velocity = [0.0, 0.0, 0.0]",
        f"margin = {MARGIN}",
    ]
    for name_, kind, integrator, dt in ENGINES:
        lines += ["", "[[engine]]", f'name = "{name_}"', f'kind = "{kind}"']
        if integrator:
            lines.append(f'integrator = "{integrator}"')
        lines.append(f"dt = {dt}")
    return "\n".join(lines) + "\n"


def _write_frames(folder, results):
    rows = []
    for name, *_ in ENGINES:
        for fr in results[name][0]:
            rows.append([name] + [fr[c] for c in FRAME_COLS[1:]])
    write_csv(os.path.join(folder, "frames.csv"), FRAME_COLS, rows)


def _write_divergence(folder, results, ref):
    """divergence.csv: matched by frame index (the blow-up row against the next reference
    frame)."""
    ref_frames = results[ref][0]
    rows = []
    for name, *_ in ENGINES[1:]:
        for k, fr in enumerate(results[name][0]):
            rf = ref_frames[min(k, len(ref_frames) - 1)]
            with np.errstate(all="ignore"):
                dist = np.linalg.norm(fr["x"] - rf["x"], axis=1)
                com = np.linalg.norm(fr["x"].mean(axis=0) - rf["x"].mean(axis=0))
            rows.append([name, ref, fr["t"], float(np.sqrt(np.mean(dist ** 2))),
                         float(np.max(dist)),
                         float(com), fr["total_energy"] - rf["total_energy"],
                         fr["shadow_area"] - rf["shadow_area"]])
    write_csv(os.path.join(folder, "divergence.csv"),
              ["engine", "reference", "t", "rms_distance", "max_distance", "com_distance",
               "energy_difference", "shadow_area_difference"], rows)


def _write_snapshots(folder, results, cloth):
    rows = []
    for name, *_ in ENGINES:
        for t, x in results[name][1].items():
            for p in range(cloth.n):
                i, j = int(cloth.ij[p, 0]), int(cloth.ij[p, 1])
                rows.append([name, t, i, j, x[p, 0], x[p, 1], x[p, 2]])
    write_csv(os.path.join(folder, "snapshots.csv"), ["engine", "t", "i", "j", "x", "y", "z"], rows)


def _write_summary(folder, results, ref):
    """summary.csv: wall time is modelled (fixture), force evaluations are exact; the
    distances come from the divergence.csv already written."""
    evals = {"rk4": 4, "symplectic-euler": 1, "explicit-euler": 1, "": 1}
    cloth_area = SIZE * SIZE
    support = math.pi * SPHERE_R ** 2
    rows = []
    for name, kind, integrator, dt in ENGINES:
        frames, _, blowup = results[name]
        steps = int(round((blowup if blowup is not None else DURATION) / dt))
        us = {"rk4": 9.5, "symplectic-euler": 2.6, "explicit-euler": 2.5, "": 31.0}[integrator]
        energy_err = max(abs(f["energy_error"]) for f in frames if f["stable"])
        if name == ref:
            final_rms = max_rms = 0.0
        else:
            div = [r for r in _rows_for(folder, name)]
            final_rms, max_rms = div[-1], max(div)
        stable = blowup is None
        drape = (frames[-1]["shadow_area"] - support) / (cloth_area - support) if stable else ""
        rows.append([name, kind, integrator, dt, steps, steps * us * 1e-6, us,
                     steps * evals[integrator], int(stable), "" if stable else blowup,
                     energy_err, final_rms, max_rms, drape, frames[-1]["kinetic"], "", 0, 0, 0, 0])
    write_csv(os.path.join(folder, "summary.csv"),
              ["engine", "kind", "integrator", "dt", "steps", "wall_s", "us_per_step",
               "force_evals",
               "stable", "blowup_t", "max_energy_error", "final_rms_vs_reference",
               "max_rms_vs_reference", "drape_coefficient", "final_kinetic", "static_residual",
               "newton_iterations", "cg_iterations", "cg_unconverged", "newton_unconverged"],
              rows)


def _write_run_json(folder, **more):
    with open(os.path.join(folder, "run.json"), "w", encoding="utf-8") as f:
        json.dump({"tool": "clothbench", "version": "0.1.0", "git_commit": "0000000 (fixture)",
                   "compiler": "synthetic (analysis/tests/make_fixtures.py)",
                   "date": "2025-01-01T00:00:00Z", **more, **FACTS}, f, indent=2)
        f.write("\n")


def make_run(folder, damping):
    os.makedirs(folder, exist_ok=True)
    cloth = Cloth(damping)
    results = {}
    for name, kind, integrator, dt in ENGINES:
        frames, snaps, blowup = simulate(cloth, integrator or "implicit-euler", dt)
        results[name] = (frames, snaps, blowup)
        print(f"  {name}: {len(frames)} frames, blow-up at {blowup}", file=sys.stderr)
    ref = ENGINES[0][0]
    _write_frames(folder, results)
    _write_divergence(folder, results, ref)
    _write_snapshots(folder, results, cloth)
    _write_summary(folder, results, ref)
    with open(os.path.join(folder, "scenario.toml"), "w", encoding="utf-8") as f:
        f.write(scenario_toml("seed_sphere_drape_7x7", damping))
    _write_run_json(folder)


def _rows_for(folder, engine):
    """RMS distances of one engine from the divergence.csv just written."""
    out = []
    with open(os.path.join(folder, "divergence.csv"), encoding="utf-8") as f:
        next(f)
        for line in f:
            cells = line.rstrip("\n").split(",")
            if cells[0] == engine:
                out.append(float(cells[3]))
    return out


# engine, integrator, order, error constant, evals/step, us per eval, stability radius
SWEEP_METHODS = [
    ("custom", "explicit-euler", 1, 2.0, 1, 2.4, 2.0),
    ("custom", "symplectic-euler", 1, 1.2, 1, 2.5, 2.0),
    ("custom", "picard-implicit", 1, 1.0, 2, 2.4, 1.0),
    ("custom", "midpoint", 2, 60.0, 2, 2.4, 2.0),
    ("custom", "rk4", 4, 4e6, 4, 2.4, 2.785),
    ("custom", "implicit-euler", 1, 3.0, 1, 30.0, None),
    ("bullet-softbody", "", 1, 6.0, 1, 5.0, None),
]
SWEEP_DTS = [1.6e-3, 8e-4, 4e-4, 2e-4, 1e-4, 5e-5, 2.5e-5]
SWEEP_LAMBDA = 6000.0  # 1/s, the fastest (damping-dominated) mode of the fixture's cloth


def _sweep_method(method, rng, wp, conv, stab):
    """One engine and integrator's work-precision rows, fitted order and stability limit,
    appended to wp, conv and stab."""
    engine, integ, order, const, evals, us, radius = method
    limit = radius / SWEEP_LAMBDA if radius else (1.2e-3 if engine.startswith("bullet") else None)
    measured = limit * (0.93 + 0.05 * rng.random()) if limit else None
    pts = []
    for dt in SWEEP_DTS:
        stable = measured is None or dt <= measured
        wall_per_sim = evals * us * 1e-6 / dt * (1.0 + 0.05 * rng.random())
        if stable:
            err = const * dt ** order * (1.0 + 0.08 * rng.standard_normal())
            pts.append((dt, err))
            row_err = (err, err * (1.4 + 0.2 * rng.random()))
        else:
            row_err = ("", "")
        cg = int(12 + 4 * math.log2(dt / 2.5e-5)) if integ == "implicit-euler" else 0
        steps = int(round(1.0 / dt))
        wp.append([engine, integ, dt, int(stable), *row_err, wall_per_sim * 1.0, wall_per_sim,
                   steps * evals, cg * steps])
    if len(pts) >= 2:
        lx = np.log([p[0] for p in pts])
        ly = np.log([p[1] for p in pts])
        conv.append([engine, integ, float(np.polyfit(lx, ly, 1)[0]), len(pts)])
    if engine == "custom" and integ == "implicit-euler":
        stab.append([engine, integ, 1.6e-3, "", "", "", ""])
    else:
        first = measured * 1.02
        predicted = limit if engine == "custom" else ""
        ratio = measured / predicted if predicted != "" else ""
        cause = "strain" if integ in ("explicit-euler", "midpoint") else "non-finite"
        if predicted != "":
            cause += " (mode 1/s 6000, damping)"
        stab.append([engine, integ, measured, first, predicted, ratio, cause])


def _write_recommendation(folder, wp):
    """recommendation.csv: the cheapest stable row meeting the tolerance, per engine and
    overall (judged on the largest error over the run, as clothbench accuracy does)."""
    tol = 1e-4
    ok = [r for r in wp if r[3] == 1 and r[5] != "" and r[5] <= tol]
    rec = []
    for engine in sorted({r[0] for r in ok}) + ["overall"]:
        cands = [r for r in ok if engine in ("overall", r[0])]
        best = min(cands, key=lambda r: r[7])
        scope = "overall" if engine == "overall" else "engine"
        rec.append([scope, best[0], best[1], best[2], best[5], best[7], tol])
    write_csv(os.path.join(folder, "recommendation.csv"),
              ["scope", "engine", "integrator", "dt", "error_max", "wall_s_per_sim_s",
               "tolerance"], rec)


def make_sweep(folder):
    """Sweep CSVs from a model of the seed scene: error C dt^p, cost evals / dt, known limits."""
    os.makedirs(folder, exist_ok=True)
    rng = np.random.default_rng(5)
    wp, conv, stab = [], [], []
    for method in SWEEP_METHODS:
        _sweep_method(method, rng, wp, conv, stab)
    write_csv(os.path.join(folder, "work_precision.csv"),
              ["engine", "integrator", "dt", "stable", "error_final", "error_max", "wall_s",
               "wall_s_per_sim_s", "force_evals", "cg_iterations"], wp)
    write_csv(os.path.join(folder, "convergence.csv"),
              ["engine", "integrator", "order", "points"], conv)
    write_csv(os.path.join(folder, "stability.csv"),
              ["engine", "integrator", "stable_dt", "first_unstable_dt", "predicted_dt",
               "ratio_measured_to_predicted", "cause"], stab)
    _write_recommendation(folder, wp)
    _write_run_json(folder, command="accuracy + stability (modelled)")


def main():
    print("run/ (damping 750 N s/m)", file=sys.stderr)
    make_run(os.path.join(FIXTURES, "run"), 750.0)
    print("run_after/ (damping 500 N s/m)", file=sys.stderr)
    make_run(os.path.join(FIXTURES, "run_after"), 500.0)
    print("sweep/", file=sys.stderr)
    make_sweep(os.path.join(FIXTURES, "sweep"))


if __name__ == "__main__":
    main()
