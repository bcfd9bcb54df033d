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

import os
import shutil
import signal
import sys

if __name__ == "__main__" and not __package__:
    _here = os.path.dirname(os.path.abspath(__file__))
    sys.path = [p for p in sys.path if os.path.abspath(p or ".") != _here]
    sys.path.insert(0, os.path.dirname(_here))

import numpy as np  # noqa: E402

from analysis import trajectory  # noqa: E402
from analysis.csvio import ArgumentParser, ReportError, message  # noqa: E402


def parse_args(argv):
    p = ArgumentParser("export", description="OBJ or VTK files from a run's trajectories.")
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


def obj_text(x, faces, t, engine, segments=()):
    """One frame as OBJ: vertices, triangles, and for a chain (no triangles) its segments as
    lines, so that Blender and ParaView show it."""
    lines = [f"# clothbench {engine} t = {t:.6g} s", f"o {engine}"]
    lines += [f"v {p[0]:.7g} {p[1]:.7g} {p[2]:.7g}" for p in x]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    lines += [f"l {a + 1} {b + 1}" for a, b in segments]
    return "\n".join(lines) + "\n"


def _array(name, values, fmt, components=1, kind="Float32"):
    body = " ".join(fmt % v for v in np.asarray(values).reshape(-1))
    comps = f' NumberOfComponents="{components}"' if components > 1 else ""
    return f'<DataArray type="{kind}" Name="{name}"{comps} format="ascii">{body}</DataArray>'


def _cells(tag, cells, per_cell):
    """A VTK cell block (Polys or Lines): connectivity and offsets; nothing when empty."""
    if len(cells) == 0:
        return []
    offsets = per_cell * np.arange(1, len(cells) + 1)
    return [f"<{tag}>", _array("connectivity", cells, "%d", kind="Int32"),
            _array("offsets", offsets, "%d", kind="Int32"), f"</{tag}>"]


def vtp_text(x, faces, strain, distance, segments=()):
    """One frame as VTK polydata: triangles, or a chain's segments as lines."""
    point_data = [_array("strain", strain, "%.7g")]
    if distance is not None:
        point_data.append(_array("distance_to_reference", distance, "%.7g"))
    return "\n".join([
        '<?xml version="1.0"?>',
        '<VTKFile type="PolyData" version="0.1" byte_order="LittleEndian">',
        "<PolyData>",
        f'<Piece NumberOfPoints="{len(x)}" NumberOfVerts="0" NumberOfLines="{len(segments)}" '
        f'NumberOfStrips="0" NumberOfPolys="{len(faces)}">',
        '<PointData Scalars="strain">', *point_data, "</PointData>",
        "<Points>", _array("Points", x, "%.7g", 3), "</Points>",
        *_cells("Lines", segments, 2), *_cells("Polys", faces, 3),
        "</Piece>", "</PolyData>", "</VTKFile>", ""])


def pvd_text(entries):
    rows = [f'<DataSet timestep="{t:.9g}" group="" part="0" file="{f}"/>' for t, f in entries]
    return "\n".join(['<?xml version="1.0"?>',
                      '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
                      "<Collection>", *rows, "</Collection>", "</VTKFile>", ""])


def _replace_folder(staged, folder):
    """Puts the staged folder in folder's place: every frame of an earlier export goes, so a
    sequence never mixes two runs (an earlier, longer export's last frames included)."""
    old = folder + ".old"
    shutil.rmtree(old, ignore_errors=True)
    if os.path.exists(folder):
        os.replace(folder, old)
    os.replace(staged, folder)
    shutil.rmtree(old, ignore_errors=True)


def _export_engine(tr, e, out, fmt):
    """Writes engine e's frames into out/e (replacing it whole); returns the frame count."""
    faces = tr.triangles()
    segments = tr.segments() if len(faces) == 0 else ()
    ref = tr.positions[tr.index["reference"]]
    folder = os.path.join(out, e)
    staged = folder + ".new"
    shutil.rmtree(staged, ignore_errors=True)
    os.makedirs(staged)
    entries = []
    try:
        for k, t in enumerate(tr.times(e)):
            x = tr.positions[e][k]
            name = f"frame_{k:04d}.{'obj' if fmt == 'obj' else 'vtp'}"
            if fmt == "obj":
                text = obj_text(x, faces, t, e, segments)
            else:
                d = np.linalg.norm(x - ref[k], axis=-1) if k < len(ref) else None
                text = vtp_text(x, faces, tr.strain(x), d, segments)
                entries.append((t, f"{e}/{name}"))
            write_atomic(os.path.join(staged, name), text)
        _replace_folder(staged, folder)
    finally:
        shutil.rmtree(staged, ignore_errors=True)  # interrupted: no half export left
    if fmt == "vtk":
        write_atomic(os.path.join(out, f"{e}.pvd"), pvd_text(entries))
    return len(tr.times(e))


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
    written = 0
    for e in engines:
        written += _export_engine(tr, e, out, args.format)
    print(f"wrote {out} ({len(engines)} engines, {written} {args.format} frames"
          + (", one .pvd per engine" if args.format == "vtk" else "") + ")")
    return 0


def _interrupt(signum, frame):
    """SIGTERM as Ctrl-C: the same clean-up, then exit 143 (130 for Ctrl-C)."""
    raise KeyboardInterrupt(signum)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    signal.signal(signal.SIGTERM, _interrupt)
    try:
        return export(parse_args(argv))
    except ReportError as e:
        print(message("export", e), file=sys.stderr)
        return 2
    except OSError as e:
        print(message("export", f"{e.filename}: {e.strerror}"), file=sys.stderr)
        return 2
    except KeyboardInterrupt as e:
        return 143 if e.args == (signal.SIGTERM,) else 130


if __name__ == "__main__":
    sys.exit(main())
