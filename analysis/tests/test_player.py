"""Trajectories, the 3D player (in headless Chromium), the OBJ/VTK exports and the movie, on real
runs made by tests/analysis/player_from_real_runs.sh:

    CLOTHBENCH_PLAYER_RUN       the seed scene for 0.6 s: custom-rk4 (reference),
                                custom-symplectic-euler, bullet-softbody-matched; its report and
                                its obj and vtk exports
    CLOTHBENCH_PLAYER_UNSTABLE  the same scene with symplectic Euler at dt = 5e-4 s (blows up);
                                its report, with --movie when ffmpeg is installed
    CLOTHBENCH_PLAYER_COMPARE   report of the first compared with the second (--compare)

Without them (plain `unittest discover`) the tests that need them are skipped.
"""

import csv
import json
import os
import re
import shutil
import subprocess
import tempfile
import unittest
import xml.etree.ElementTree as ET

import numpy as np

from analysis.tests import reportcheck as rc

RUN = os.environ.get("CLOTHBENCH_PLAYER_RUN")
UNSTABLE = os.environ.get("CLOTHBENCH_PLAYER_UNSTABLE")
COMPARE = os.environ.get("CLOTHBENCH_PLAYER_COMPARE")
CHROMIUM = os.environ.get("CHROMIUM", "/usr/bin/chromium")
HAVE_CHROMIUM = os.access(CHROMIUM, os.X_OK)
WINDOW = (1400, 1100)


def chromium(url, *args, timeout=180):
    """Runs headless chromium on url; returns (stdout, stderr with the console messages)."""
    profile = tempfile.mkdtemp(prefix="clothbench-player-")
    try:
        r = subprocess.run(
            [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
             "--disable-background-networking", "--disable-component-update", "--disable-sync",
             "--disable-dev-shm-usage", "--hide-scrollbars", "--force-device-scale-factor=1",
             "--enable-logging=stderr", "--v=0", f"--user-data-dir={profile}",
             f"--window-size={WINDOW[0]},{WINDOW[1]}", "--virtual-time-budget=8000", *args, url],
            capture_output=True, text=True, timeout=timeout)
        return r.stdout, r.stderr
    finally:
        shutil.rmtree(profile, ignore_errors=True)


def player_status(page, fragment):
    """The player's status JSON (#player-status) and chromium's stderr, at page#fragment."""
    dom, err = chromium(f"file://{os.path.abspath(page)}#{fragment}", "--dump-dom")
    m = re.search(r'<pre id="player-status">(.*?)</pre>', dom, re.S)
    if not m:
        raise AssertionError(f"no player status in the page; chromium said:\n{err[-3000:]}")
    text = m.group(1).replace("&quot;", '"').replace("&lt;", "<").replace("&gt;", ">")
    return json.loads(text.replace("&amp;", "&")), err


def screenshot(page, fragment, png):
    chromium(f"file://{os.path.abspath(page)}#{fragment}", f"--screenshot={png}")
    import matplotlib.image as mpimg
    return (mpimg.imread(png)[..., :3] * 255).round().astype(int)


def crop(img, view, canvas):
    x0, y0 = int(canvas["x"] + view["x"]), int(canvas["y"] + view["y"])
    # leave out the label in the view's top left corner (up to two lines)
    return img[y0 + 40:y0 + int(view["h"]) - 2, x0 + 2:x0 + int(view["w"]) - 2]


def chromatic(pixels, floor=40):
    """Pixels whose colour is not a grey (max - min channel above floor), as (n, 3)."""
    p = pixels.reshape(-1, 3)
    return p[(p.max(axis=1) - p.min(axis=1)) > floor]


def console_errors(stderr):
    return [line for line in stderr.splitlines()
            if "CONSOLE" in line and ("Uncaught" in line or "Error" in line or "GL_INVALID" in line)]


@unittest.skipUnless(RUN, "CLOTHBENCH_PLAYER_RUN not set (ctest sets it)")
class TrajectoryLayout(unittest.TestCase):
    def setUp(self):
        with open(os.path.join(RUN, "trajectory", "trajectory.json"), encoding="utf-8") as f:
            self.index = json.load(f)

    def test_numpy_reads_the_snapshot_positions_exactly(self):
        nu, nv = self.index["grid"]
        interval = self.index["interval"]
        self.assertAlmostEqual(interval, 0.03)  # 1/30 s rounded to three 0.01 s frames
        snaps = {}
        with open(os.path.join(RUN, "snapshots.csv"), encoding="utf-8") as f:
            for row in csv.DictReader(f):
                key = (row["engine"], float(row["t"]))
                p = int(row["j"]) * nu + int(row["i"])
                snaps.setdefault(key, np.zeros((nu * nv, 3)))[p] = [
                    float(row["x"]), float(row["y"]), float(row["z"])]
        compared = 0
        for e in self.index["engines"]:
            x = np.load(os.path.join(RUN, "trajectory", e["file"]))  # one call per engine
            self.assertEqual(x.dtype, np.float32)
            self.assertEqual(x.shape, (e["frames"], nu * nv, 3))
            for (name, t), shape in snaps.items():
                k = round(t / interval)
                if name != e["name"] or abs(k * interval - t) > 1e-9 or k >= len(x):
                    continue
                np.testing.assert_array_equal(x[k], shape.astype(np.float32))
                compared += 1
            # the cloth moved: a trajectory that repeats its first frame would pass the above
            self.assertGreater(np.abs(x[-1] - x[0]).max(), 0.05)
        # snapshots at 0, 0.3 and 0.6 s for three engines, all on the 0.03 s grid
        self.assertEqual(compared, 9)

    def test_colliders_and_held_particles(self):
        c = np.load(os.path.join(RUN, "trajectory", "colliders.npy"))
        self.assertEqual(c.shape, (self.index["frames"], len(self.index["shapes"]), 3))
        self.assertEqual([s["type"] for s in self.index["shapes"]], ["sphere"])
        np.testing.assert_array_equal(c[:, 0], 0.0)  # the seed's sphere sits at the origin
        nu, nv = self.index["grid"]
        self.assertEqual(sorted(self.index["held"]), [0, nu - 1, nu * (nv - 1), nu * nv - 1])

    def test_size_on_disk(self):
        # 21 frames of 625 particles in float32, plus a header of at most 128 bytes
        for e in self.index["engines"]:
            size = os.path.getsize(os.path.join(RUN, "trajectory", e["file"]))
            self.assertEqual(e["frames"], 21)
            self.assertLessEqual(size - 21 * 625 * 3 * 4, 128)


@unittest.skipUnless(RUN, "CLOTHBENCH_PLAYER_RUN not set (ctest sets it)")
class Exports(unittest.TestCase):
    def test_obj(self):
        folder = os.path.join(RUN, "export", "obj", "custom-rk4")
        files = sorted(os.listdir(folder))
        self.assertEqual(len(files), 21)
        with open(os.path.join(folder, files[0]), encoding="ascii") as f:
            lines = f.read().splitlines()
        v = [line for line in lines if line.startswith("v ")]
        faces = [line for line in lines if line.startswith("f ")]
        self.assertEqual(len(v), 625)
        self.assertEqual(len(faces), 2 * 24 * 24)
        # particle (0, 0) of the seed cloth starts at its corner (-2, 1, -2), held there
        self.assertEqual([float(s) for s in v[0].split()[1:]], [-2.0, 1.0, -2.0])
        self.assertEqual(faces[0], "f 1 2 27")

    def test_vtk(self):
        base = os.path.join(RUN, "export", "vtk")
        pvd = ET.parse(os.path.join(base, "custom-symplectic-euler.pvd")).getroot()
        sets = pvd.findall("./Collection/DataSet")
        self.assertEqual(len(sets), 21)
        self.assertAlmostEqual(float(sets[-1].get("timestep")), 0.6)
        for engine, same_as_reference in (("custom-rk4", True), ("custom-symplectic-euler", False)):
            last = os.path.join(base, engine, "frame_0020.vtp")
            piece = ET.parse(last).getroot().find("./PolyData/Piece")
            self.assertEqual(piece.get("NumberOfPoints"), "625")
            self.assertEqual(piece.get("NumberOfPolys"), str(2 * 24 * 24))
            arrays = {a.get("Name"): np.array(a.text.split(), dtype=float)
                      for a in piece.iter("DataArray")}
            self.assertEqual(len(arrays["Points"]), 3 * 625)
            self.assertEqual(list(arrays["Points"][:3]), [-2.0, 1.0, -2.0])
            self.assertEqual(len(arrays["strain"]), 625)
            self.assertGreater(arrays["strain"].max(), 0.0)  # the draped cloth is stretched
            d = arrays["distance_to_reference"]
            if same_as_reference:
                self.assertTrue(np.all(d == 0))
            else:
                self.assertGreater(d.max(), 1e-4)
            self.assertEqual(list(arrays["offsets"][:2]), [3, 6])

    def test_unknown_engine_is_refused(self):
        r = subprocess.run(["/usr/bin/python3", os.path.join(rc.ROOT, "analysis", "export.py"),
                            RUN, "--format", "obj", "--engine", "nope", "--out",
                            tempfile.mkdtemp()], capture_output=True, text=True)
        self.assertEqual(r.returncode, 2)
        self.assertIn("--engine nope: no such engine", r.stderr)


@unittest.skipUnless(RUN and HAVE_CHROMIUM, "needs CLOTHBENCH_PLAYER_RUN and chromium")
class Player(unittest.TestCase):
    page = os.path.join(RUN or "", "report.html")

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="clothbench-player-")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def test_loads_without_errors_and_draws(self):
        status, err = player_status(self.page, "t=0")
        self.assertTrue(status["ready"], status)
        self.assertEqual(status["errors"], [])
        self.assertEqual(console_errors(err), [])
        self.assertEqual(status["layout"], "grid")
        self.assertEqual(status["shown"], ["custom-rk4", "custom-symplectic-euler",
                                           "bullet-softbody-matched"])
        img = screenshot(self.page, "t=0", os.path.join(self.tmp, "start.png"))
        for view in status["views"]:
            cell = crop(img, view, status["canvas"])
            # not blank: the cloth (engine colour) covers part of every view
            self.assertGreater(len(chromatic(cell)), 0.02 * cell.shape[0] * cell.shape[1], view)

    def test_opens_where_the_engines_differ_most(self):
        # no #t= in the address: the frame of the largest distance from the reference
        status, _ = player_status(self.page, "")
        with open(os.path.join(RUN, "divergence.csv"), newline="") as f:
            rows = [r for r in csv.DictReader(f) if r["engine"] != r["reference"]]
        worst = max(float(r["rms_distance"]) for r in rows)
        near = [float(r["rms_distance"]) for r in rows if abs(float(r["t"]) - status["t"]) < 0.016]
        self.assertGreater(status["t"], 0)
        self.assertTrue(near and max(near) >= 0.9 * worst, (status["t"], near, worst))

    def test_every_cloth_stays_in_its_view(self):
        # the camera frames every engine over the whole run: no cloth is cut off at a view's
        # edge at any of these times (its colour never reaches the border of the view)
        for t in ("0", "0.3", "0.6"):
            status, _ = player_status(self.page, f"t={t}")
            img = screenshot(self.page, f"t={t}", os.path.join(self.tmp, f"frame{t}.png"))
            for view in status["views"]:
                # the view's own edges, one pixel in (the label sits inside, clear of them)
                x0 = int(status["canvas"]["x"] + view["x"]) + 1
                y0 = int(status["canvas"]["y"] + view["y"]) + 1
                cell = img[y0:y0 + int(view["h"]) - 2, x0:x0 + int(view["w"]) - 2].astype(int)
                coloured = (cell.max(axis=-1) - cell.min(axis=-1)) > 40
                border = np.concatenate([coloured[0], coloured[-1], coloured[:, 0], coloured[:, -1]])
                self.assertEqual(int(border.sum()), 0, (t, view["engine"]))

    def test_start_and_end_differ(self):
        status, _ = player_status(self.page, "t=0")
        start = screenshot(self.page, "t=0", os.path.join(self.tmp, "start.png"))
        end = screenshot(self.page, "t=0.6", os.path.join(self.tmp, "end.png"))
        for view in status["views"]:
            a, b = crop(start, view, status["canvas"]), crop(end, view, status["canvas"])
            changed = np.abs(a - b).max(axis=-1) > 30
            self.assertGreater(changed.mean(), 0.02, view)  # the cloth fell onto the sphere

    def test_distance_colour_reference_is_uniform(self):
        status, err = player_status(self.page, "t=0.6&color=distance&layout=grid")
        self.assertEqual(status["color"], "distance")
        self.assertEqual(console_errors(err), [])
        img = screenshot(self.page, "t=0.6&color=distance&layout=grid",
                         os.path.join(self.tmp, "distance.png"))
        spread = {}
        for view in status["views"]:
            px = chromatic(crop(img, view, status["canvas"])).astype(float)
            self.assertGreater(len(px), 500, view)
            # lighting scales a colour's brightness, not its chromaticity
            chroma = px / px.sum(axis=1, keepdims=True)
            spread[view["engine"]] = float(np.percentile(np.abs(chroma - np.median(chroma, axis=0)).sum(axis=1), 90))
        self.assertLess(spread["custom-rk4"], 0.03, spread)
        self.assertGreater(spread["bullet-softbody-matched"], 2 * spread["custom-rk4"], spread)

    def test_deep_link_overlay_and_engines(self):
        status, _ = player_status(self.page, "t=0.3&layout=overlay&engines=custom-rk4,bullet-softbody-matched&color=strain")
        self.assertEqual(status["layout"], "overlay")
        self.assertEqual(status["color"], "strain")
        self.assertAlmostEqual(status["t"], 0.3)
        self.assertEqual(status["shown"], ["custom-rk4", "bullet-softbody-matched"])

    @unittest.skipUnless(UNSTABLE, "CLOTHBENCH_PLAYER_UNSTABLE not set")
    def test_unstable_engine_is_marked_and_greyed(self):
        page = os.path.join(UNSTABLE, "report.html")
        status, err = player_status(page, "t=0.6")
        self.assertEqual(console_errors(err), [])
        marked = {m["engine"]: m["t"] for m in status["marked"]}
        self.assertEqual(list(marked), ["custom-symplectic-euler"])
        with open(os.path.join(UNSTABLE, "summary.csv"), encoding="utf-8") as f:
            row = next(r for r in csv.DictReader(f) if r["engine"] == "custom-symplectic-euler")
        self.assertEqual(row["stable"], "0")
        self.assertAlmostEqual(marked["custom-symplectic-euler"], float(row["blowup_t"]))
        views = {v["engine"]: v for v in status["views"]}
        self.assertTrue(views["custom-symplectic-euler"]["greyed"])
        self.assertFalse(views["custom-rk4"]["greyed"])
        img = screenshot(page, "t=0.6", os.path.join(self.tmp, "unstable.png"))
        grey = crop(img, views["custom-symplectic-euler"], status["canvas"])
        ok = crop(img, views["custom-rk4"], status["canvas"])
        self.assertLess(len(chromatic(grey)), 0.002 * grey.shape[0] * grey.shape[1])
        self.assertGreater(len(chromatic(ok)), 0.02 * ok.shape[0] * ok.shape[1])

    @unittest.skipUnless(COMPARE, "CLOTHBENCH_PLAYER_COMPARE not set")
    def test_compare_shows_both_folders(self):
        status, err = player_status(os.path.join(COMPARE, "report.html"), "t=0.6")
        self.assertEqual(console_errors(err), [])
        self.assertEqual(status["shown"], ["run: custom-rk4", "run: custom-symplectic-euler",
                                           "run: bullet-softbody-matched", "unstable: custom-rk4",
                                           "unstable: custom-symplectic-euler"])
        self.assertEqual([m["engine"] for m in status["marked"]],
                         ["unstable: custom-symplectic-euler"])

    @unittest.skipUnless(UNSTABLE and shutil.which("ffmpeg"), "needs the unstable run and ffmpeg")
    def test_movie(self):
        path = os.path.join(UNSTABLE, "movie.mp4")
        self.assertTrue(os.path.exists(path))
        self.assertLess(os.path.getsize(path), 5e6)
        with open(path, "rb") as f:
            self.assertEqual(f.read(12)[4:8], b"ftyp")

    def test_movie_without_ffmpeg_says_how_to_get_it(self):
        env = dict(os.environ, PATH=self.tmp, MPLBACKEND="Agg")
        r = subprocess.run(["/usr/bin/python3", rc.REPORT, RUN, "--movie", "--out",
                            os.path.join(self.tmp, "out")], env=env, capture_output=True,
                           text=True, timeout=600)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("--movie needs ffmpeg: apt-get install ffmpeg", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.tmp, "out", "report.html")))

    def test_without_three_js_the_report_says_why(self):
        env = dict(os.environ, CLOTHBENCH_THREE_JS=os.path.join(self.tmp, "none.js"), MPLBACKEND="Agg")
        out = os.path.join(self.tmp, "out")
        r = subprocess.run(["/usr/bin/python3", rc.REPORT, RUN, "--out", out], env=env,
                           capture_output=True, text=True, timeout=600)
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(out, "report.html"), encoding="utf-8") as f:
            text = f.read()
        self.assertIn("3D player left out: three.js was not found", text)
        self.assertIn("libjs-three", text)
        self.assertNotIn("<script", text)


if __name__ == "__main__":
    unittest.main()
