"""The report on self-intersection: the verdict names every engine whose cloth crossed itself,
the plot is drawn from frames.csv's columns, and runs written before the columns existed get
neither (no claim about what was not measured)."""

import csv
import json
import os
import shutil
import tempfile
import unittest
from unittest import mock

from analysis import verdicts
from analysis.folder import Folder
from analysis.plots import Context, self_contact, style
from analysis.tests import reportcheck as rc

RUN = os.path.join(rc.FIXTURES, "run")


def with_crossings(src, dst, crossings):
    """Copies run folder src to dst with frames.csv's self-intersection columns added:
    crossings(engine, t) gives the count (None: an empty field, as for a non-finite state)."""
    shutil.copytree(src, dst)
    path = os.path.join(dst, "frames.csv")
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    header = rows[0] + ["max_stretch", "max_compression", "self_intersections",
                        "min_self_distance"]
    e, t = header.index("engine"), header.index("t")
    out = [header]
    for row in rows[1:]:
        n = crossings(row[e], float(row[t]))
        gap = "" if n is None else ("0" if n > 0 else "0.01")
        out.append(row + ["0", "0", "" if n is None else str(n), gap])
    with open(path, "w", newline="", encoding="utf-8") as f:
        csv.writer(f, lineterminator="\n").writerows(out)


def layer_lines(folder):
    for heading, lines in verdicts.run_verdicts(folder):
        if heading.startswith("Layers"):
            return lines
    return None


class SelfContactReport(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp()

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def test_the_verdict_names_each_engine_that_crossed_and_when(self):
        dst = os.path.join(self.tmp, "run")
        # bullet-softbody crosses from t = 0.1 s on, 7 crossings at most; the others never
        with_crossings(RUN, dst, lambda e, t: (7 if t < 0.3 else 3) if e == "bullet-softbody"
                       and t >= 0.1 - 1e-9 else 0)
        lines = layer_lines(Folder(dst))
        self.assertIsNotNone(lines)
        self.assertEqual(lines[0], ("bad", "Engines that let the cloth pass through itself: "
                                    "bullet-softbody."))
        bad = [text for kind, text in lines[1:] if kind == "bad"]
        self.assertEqual(len(bad), 1)
        self.assertIn("bullet-softbody: LAYERS CROSSED from t = 0.1 s", bad[0])
        self.assertIn("up to 7 edge-triangle crossings", bad[0])
        ok = [text for kind, text in lines if kind == "ok"]
        self.assertTrue(ok and all("no crossing in any frame" in text for text in ok))
        self.assertTrue(any(text.startswith("custom-rk4:") for text in ok))

    def test_no_engine_crossing_is_said_engine_by_engine(self):
        dst = os.path.join(self.tmp, "run")
        with_crossings(RUN, dst, lambda e, t: 0)
        lines = layer_lines(Folder(dst))
        self.assertTrue(lines and all(kind == "ok" for kind, _ in lines))
        self.assertTrue(all("closest approach" in text for _, text in lines))

    def test_an_unmeasured_frame_is_not_a_crossing(self):
        dst = os.path.join(self.tmp, "run")
        with_crossings(RUN, dst, lambda e, t: None if t > 0.2 else 0)
        lines = layer_lines(Folder(dst))
        self.assertTrue(all(kind == "ok" for kind, _ in lines))

    def test_each_engine_says_whether_its_self_contact_was_on(self):
        dst = os.path.join(self.tmp, "run")
        # gaps of 0.01 m in every frame but a few at 0.001 m; thickness 0.004 m
        with_crossings(RUN, dst, lambda e, t: 0)
        path = os.path.join(dst, "frames.csv")
        with open(path, newline="", encoding="utf-8") as f:
            rows = list(csv.reader(f))
        g, t = rows[0].index("min_self_distance"), rows[0].index("t")
        for row in rows[1:]:
            if float(row[t]) < 0.1 - 1e-9:
                row[g] = "0.001"
        with open(path, "w", newline="", encoding="utf-8") as f:
            csv.writer(f, lineterminator="\n").writerows(rows)
        with open(os.path.join(dst, "scenario.toml"), encoding="utf-8") as f:
            scenario = f.read()
        scenario = scenario.replace("[cloth]\n", "[cloth]\nthickness = 0.004\n", 1)
        with open(os.path.join(dst, "scenario.toml"), "w", encoding="utf-8") as f:
            f.write(scenario)
        info_path = os.path.join(dst, "run.json")
        with open(info_path, encoding="utf-8") as f:
            info = json.load(f)
        info["self_collision"] = {"custom-rk4": "on", "bullet-softbody": "not available"}
        with open(info_path, "w", encoding="utf-8") as f:
            json.dump(info, f)
        folder = Folder(dst)
        ok = {text.split(":")[0]: text for _, text in layer_lines(folder)}
        self.assertIn("custom-rk4 (self-contact on)", ok)
        self.assertIn("bullet-softbody (self-contact not available in this engine)", ok)
        # the share of frames at or above half the thickness, from the column itself
        times = sorted({float(r[t]) for r in rows[1:] if r[0] == "custom-rk4"})
        share = sum(1 for x in times if x >= 0.1 - 1e-9) / len(times)
        self.assertIn(f"{100 * share:.0f} % of frames at or above half the thickness",
                      ok["custom-rk4 (self-contact on)"])

    def test_older_runs_get_no_layer_verdict_and_no_plot(self):
        f = Folder(RUN)
        self.assertIsNone(layer_lines(f))
        self.assertFalse(self_contact.available(f))

    def test_the_plot_is_drawn_from_the_columns(self):
        dst = os.path.join(self.tmp, "run")
        with_crossings(RUN, dst, lambda e, t: 2 if e == "bullet-softbody" else 0)
        f = Folder(dst)
        self.assertTrue(self_contact.available(f))
        ctx = Context(self.tmp, False, style.Colors(f.engines()))
        png = self_contact.draw([f], ctx)
        self.assertTrue(os.path.getsize(png) > 1000)

    def test_a_run_without_crossings_counts_in_whole_numbers_from_zero(self):
        dst = os.path.join(self.tmp, "run")
        with_crossings(RUN, dst, lambda e, t: 0)
        f = Folder(dst)
        ctx = Context(self.tmp, False, style.Colors(f.engines()))
        drawn = []
        real_save = style.save
        with mock.patch.object(style, "save",
                               side_effect=lambda fig, *a: drawn.append(fig) or real_save(fig, *a)):
            self_contact.draw([f], ctx)
        counts = drawn[0].axes[0]
        low, high = counts.get_ylim()
        ticks = [y for y in counts.get_yticks() if low <= y <= high]
        self.assertGreaterEqual(high, 1.0)
        self.assertTrue(ticks and all(y == int(y) and y >= 0 for y in ticks), ticks)


if __name__ == "__main__":
    unittest.main()
