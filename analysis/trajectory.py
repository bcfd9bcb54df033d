"""The trajectories a run writes for the player and the exports (trajectory/ in a run folder).

Layout (written by src/harness/run/trajectory_files.cpp):
    trajectory/trajectory.json   the index: interval (s), frames, grid [nu, nv], spacing [du, dv]
                                 (m, rest spacing), springs (grid offsets [di, dj] of the spring
                                 kinds the cloth has), reference, engines (name, file, frames,
                                 stable, blowup_t, cause), colliders_file, shapes (type and size),
                                 held (indices of particles with a held axis)
    trajectory/<engine>.npy      float32, frames x particles x 3 (m); particle p = j * nu + i;
                                 frame k at t = k * interval; only the frames before a blow-up
    trajectory/colliders.npy     float32, frames x shapes x 3: each shape's position (m)
"""

import json
import os

import numpy as np

from .csvio import ReportError

FOLDER = "trajectory"
INDEX = "trajectory.json"


class Trajectory:
    """One run folder's trajectories.

    index      the parsed trajectory.json
    positions  engine name -> float32 array (frames, particles, 3)
    colliders  float32 array (frames, shapes, 3)
    """

    def __init__(self, folder_path):
        base = os.path.join(folder_path, FOLDER)
        path = os.path.join(base, INDEX)
        try:
            with open(path, encoding="utf-8") as f:
                self.index = json.load(f)
        except (OSError, ValueError) as e:
            raise ReportError(f"{path}: cannot read the trajectory index: {e}") from None
        try:
            self._load_arrays(base)
        except (KeyError, TypeError, ValueError) as e:
            # an index that parses but lacks a field or has one of the wrong kind
            what = f"no {e}" if isinstance(e, KeyError) else str(e)
            raise ReportError(f"{path}: a damaged trajectory index ({what}); rerun clothbench "
                              "run to write it again") from None

    def _load_arrays(self, base):
        """The engines' and colliders' arrays the index names, checked against its shapes."""
        nu, nv = self.index["grid"]
        particles = int(self.index.get("particles", int(nu) * int(nv)))
        self.positions = {}
        for e in self.index["engines"]:
            self.positions[e["name"]] = _load(os.path.join(base, e["file"]),
                                              (int(e["frames"]), particles, 3))
        self.colliders = _load(os.path.join(base, self.index["colliders_file"]),
                               (int(self.index["frames"]), len(self.index["shapes"]), 3))

    @property
    def grid(self):
        return tuple(self.index["grid"])

    @property
    def interval(self):
        return float(self.index["interval"])

    @property
    def engines(self):
        return [e["name"] for e in self.index["engines"]]

    def crossings(self, engine):
        """{frame: [triangle, ...]} of the engine's trajectory frames where the cloth crosses
        itself (the triangles pierced and those holding a piercing edge); empty for runs
        written before self-intersection was measured."""
        for e in self.index["engines"]:
            if e["name"] == engine:
                return {int(k): [int(t) for t in tris] for k, tris in e.get("crossings", [])}
        return {}

    def times(self, engine):
        """Times (s) of an engine's frames."""
        return np.arange(len(self.positions[engine])) * self.interval

    def triangles(self):
        """Faces of the cloth as an array (faces, 3) of particle indices: the index's list
        (written since self-intersection was measured), else the grid's two per cell."""
        if self.index.get("triangles") is not None:
            return np.array(self.index["triangles"], dtype=np.int64).reshape(-1, 3)
        nu, nv = self.grid
        faces = []
        for j in range(nv - 1):
            for i in range(nu - 1):
                a, b, c, d = j * nu + i, j * nu + i + 1, (j + 1) * nu + i, (j + 1) * nu + i + 1
                faces += [(a, b, d), (a, d, c)]
        return np.array(faces, dtype=np.int64).reshape(-1, 3)

    def segments(self):
        """Segments between neighbouring particles as an array (segments, 2): a chain's shape,
        which has no faces (also every grid edge of a wider grid)."""
        nu, nv = self.grid
        segs = [(j * nu + i, j * nu + i + 1) for j in range(nv) for i in range(nu - 1)]
        segs += [(j * nu + i, (j + 1) * nu + i) for j in range(nv - 1) for i in range(nu)]
        return np.array(segs, dtype=np.int64).reshape(-1, 2)

    def strain(self, x):
        """Per-vertex strain |l/l0 - 1| averaged over the vertex's springs, x (particles, 3)."""
        if self.index.get("edges"):
            return self._edge_strain(x)
        nu, nv = self.grid
        du, dv = self.index["spacing"]
        g = np.asarray(x, dtype=np.float64).reshape(nv, nu, 3)
        total = np.zeros((nv, nu))
        count = np.zeros((nv, nu))
        for di, dj in self.index["springs"]:
            rest = float(np.hypot(di * du, dj * dv))
            if rest <= 0:
                continue
            # springs from (i, j) to (i + di, j + dj) inside the grid
            j0, j1 = max(0, -dj), nv - max(0, dj)
            i0, i1 = max(0, -di), nu - max(0, di)
            if j1 <= j0 or i1 <= i0:
                continue
            a = g[j0:j1, i0:i1]
            b = g[j0 + dj:j1 + dj, i0 + di:i1 + di]
            s = np.abs(np.linalg.norm(b - a, axis=-1) / rest - 1.0)
            total[j0:j1, i0:i1] += s
            count[j0:j1, i0:i1] += 1
            total[j0 + dj:j1 + dj, i0 + di:i1 + di] += s
            count[j0 + dj:j1 + dj, i0 + di:i1 + di] += 1
        return (total / np.maximum(count, 1)).reshape(-1)

    def _edge_strain(self, x):
        """strain() of a mesh, from its edges [a, b, rest length] in the index."""
        x = np.asarray(x, dtype=np.float64).reshape(-1, 3)
        edges = np.asarray(self.index["edges"], dtype=np.float64).reshape(-1, 3)
        a, b, rest = edges[:, 0].astype(np.int64), edges[:, 1].astype(np.int64), edges[:, 2]
        s = np.abs(np.linalg.norm(x[b] - x[a], axis=-1) / rest - 1.0)
        total = np.bincount(a, s, len(x)) + np.bincount(b, s, len(x))
        count = np.bincount(a, minlength=len(x)) + np.bincount(b, minlength=len(x))
        return total / np.maximum(count, 1)


def _load(path, shape):
    try:
        a = np.load(path)
    except (OSError, ValueError) as e:
        raise ReportError(f"{path}: cannot read: {e}") from None
    if a.dtype != np.float32 or a.shape != tuple(shape):
        raise ReportError(f"{path}: expected float32 of shape {tuple(shape)}, found {a.dtype} "
                          f"{a.shape}")
    return a


def available(folder_path):
    """True when the folder has a trajectory index."""
    return os.path.exists(os.path.join(folder_path, FOLDER, INDEX))
