#!/usr/bin/python3
"""A run's trajectories as files other tools open.

usage: export.py DIR --format obj|vtk [--engine NAME]... [--out OUTDIR]

obj: OUTDIR/obj/<engine>/frame_NNNN.obj, one Wavefront OBJ per trajectory frame (vertices in m,
     two triangles per grid cell, the frame's time in a comment), for Blender's "import OBJ as
     sequence" or any mesh tool.
vtk: OUTDIR/vtk/<engine>/frame_NNNN.vtp (VTK XML polydata, ASCII) with the point data arrays
     strain (|l/l0 - 1| averaged over the vertex's springs) and distance_to_reference (m, to the
     run's reference engine at the same time; absent once the reference has no frame), and
     OUTDIR/vtk/<engine>.pvd, the time series ParaView opens.

OUTDIR defaults to DIR/export. Exit codes: 0 written; 2 bad input (one line on stderr).
"""

import argparse
import os
import sys

if __name__ == "__main__" and not __package__:
    _here = os.path.dirname(os.path.abspath(__file__))
    sys.path = [p for p in sys.path if os.path.abspath(p or ".") != _here]
    sys.path.insert(0, os.path.dirname(_here))

import numpy as np  # noqa: E402

from analysis import trajectory  # noqa: E402
from analysis.csvio import ReportError  # noqa: E402


def parse_args(argv):
    p = argparse.ArgumentParser(prog="export.py",
                                description="OBJ or VTK files from a run's trajectories.")
    p.add_argument("dir", metavar="DIR", help="output folder of clothbench run")
    p.add_argument("--format", required=True, choices=["obj", "vtk"])
    p.add_argument("--engine", action="append", metavar="NAME",
                   help="export only this engine (repeatable; default: every engine)")
    p.add_argument("--out", metavar="OUTDIR", help="where to write (default: DIR/export)")
    return p.parse_args(argv)


def write_atomic(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="ascii") as f:
        f.write(text)
    os.replace(tmp, path)


def obj_text(x, faces, t, engine):
    lines = [f"# clothbench {engine} t = {t:.6g} s", f"o {engine}"]
    lines += [f"v {p[0]:.7g} {p[1]:.7g} {p[2]:.7g}" for p in x]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    return "\n".join(lines) + "\n"


def _array(name, values, fmt, components=1, kind="Float32"):
    body = " ".join(fmt % v for v in np.asarray(values).reshape(-1))
    comps = f' NumberOfComponents="{components}"' if components > 1 else ""
    return f'<DataArray type="{kind}" Name="{name}"{comps} format="ascii">{body}</DataArray>'


def vtp_text(x, faces, strain, distance):
    point_data = [_array("strain", strain, "%.7g")]
    if distance is not None:
        point_data.append(_array("distance_to_reference", distance, "%.7g"))
    offsets = 3 * np.arange(1, len(faces) + 1)
    return "\n".join([
        '<?xml version="1.0"?>',
        '<VTKFile type="PolyData" version="0.1" byte_order="LittleEndian">',
        "<PolyData>",
        f'<Piece NumberOfPoints="{len(x)}" NumberOfVerts="0" NumberOfLines="0" '
        f'NumberOfStrips="0" NumberOfPolys="{len(faces)}">',
        '<PointData Scalars="strain">', *point_data, "</PointData>",
        "<Points>", _array("Points", x, "%.7g", 3), "</Points>",
        "<Polys>", _array("connectivity", faces, "%d", kind="Int32"),
        _array("offsets", offsets, "%d", kind="Int32"), "</Polys>",
        "</Piece>", "</PolyData>", "</VTKFile>", ""])


def pvd_text(entries):
    rows = [f'<DataSet timestep="{t:.9g}" group="" part="0" file="{f}"/>' for t, f in entries]
    return "\n".join(['<?xml version="1.0"?>',
                      '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
                      "<Collection>", *rows, "</Collection>", "</VTKFile>", ""])


def export(args):
    if not os.path.isdir(args.dir):
        raise ReportError(f"{args.dir}: no such folder")
    if not trajectory.available(args.dir):
        raise ReportError(f"{args.dir}: no trajectory/trajectory.json (a folder written by "
                          "clothbench run with animation_interval > 0)")
    tr = trajectory.Trajectory(args.dir)
    engines = args.engine or tr.engines
    for e in engines:
        if e not in tr.engines:
            raise ReportError(f"--engine {e}: no such engine in {args.dir} (engines: "
                              f"{', '.join(tr.engines)})")
    out = os.path.join(args.out or os.path.join(args.dir, "export"), args.format)
    faces = tr.triangles()
    ref = tr.positions[tr.index["reference"]]
    written = 0
    for e in engines:
        folder = os.path.join(out, e)
        os.makedirs(folder, exist_ok=True)
        entries = []
        for k, t in enumerate(tr.times(e)):
            x = tr.positions[e][k]
            name = f"frame_{k:04d}.{'obj' if args.format == 'obj' else 'vtp'}"
            if args.format == "obj":
                text = obj_text(x, faces, t, e)
            else:
                d = np.linalg.norm(x - ref[k], axis=-1) if k < len(ref) else None
                text = vtp_text(x, faces, tr.strain(x), d)
                entries.append((t, f"{e}/{name}"))
            write_atomic(os.path.join(folder, name), text)
            written += 1
        if args.format == "vtk":
            write_atomic(os.path.join(out, f"{e}.pvd"), pvd_text(entries))
    print(f"wrote {out} ({len(engines)} engines, {written} {args.format} frames"
          + (", one .pvd per engine" if args.format == "vtk" else "") + ")")
    return 0


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    try:
        return export(parse_args(argv))
    except ReportError as e:
        print(f"export: error: {e}", file=sys.stderr)
        return 2
    except OSError as e:
        print(f"export: error: {e.filename}: {e.strerror}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":
    sys.exit(main())
