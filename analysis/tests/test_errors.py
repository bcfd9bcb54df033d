"""Bad input gives one clear line on stderr naming the file, exit code 2, no traceback; an
internal error gives one line and exit code 1, its traceback only on request."""

import contextlib
import io
import os
import shutil
import subprocess
import sys
import tempfile
import unittest
from unittest import mock

from analysis.tests import reportcheck as rc


def rewrite(path, edit):
    """Replace a file's text by edit(text)."""
    with open(path, encoding="utf-8") as f:
        text = f.read()
    with open(path, "w", encoding="utf-8") as f:
        f.write(edit(text))


def drop_column(text, name):
    lines = text.splitlines()
    k = lines[0].split(",").index(name)
    return "\n".join(",".join(c for n, c in enumerate(line.split(",")) if n != k)
                     for line in lines) + "\n"


def replace_line(text, number, new):
    lines = text.splitlines()
    lines[number - 1] = new(lines[number - 1])
    return "\n".join(lines) + "\n"


class BadInput(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="clothbench-bad-")
        self.run = os.path.join(self.tmp, "run")
        self.sweep = os.path.join(self.tmp, "sweep")
        shutil.copytree(os.path.join(rc.FIXTURES, "run"), self.run)
        shutil.copytree(os.path.join(rc.FIXTURES, "sweep"), self.sweep)
        self.out = os.path.join(self.tmp, "out")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def assert_fails(self, folder, *fragments, args=()):
        result = rc.run_report(folder, "--out", self.out, *args)
        self.assertEqual(result.returncode, 2, f"stdout: {result.stdout}\nstderr: {result.stderr}")
        self.assertNotIn("Traceback", result.stderr)
        self.assertEqual(len(result.stderr.strip().splitlines()), 1, result.stderr)
        self.assertTrue(result.stderr.startswith("clothbench: report: "), result.stderr)
        for fragment in fragments:
            self.assertIn(fragment, result.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.out, "report.html")))
        return result.stderr

    def test_option_errors_are_one_line_in_clothbench_form(self):
        # argparse's own errors too: named as the command the user typed, with no usage block
        result = rc.run_report(self.run, "--no-such-option")
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertEqual(result.stderr.strip().splitlines(),
                         ["clothbench: report: unrecognized arguments: --no-such-option "
                          "(see clothbench report --help)"])
        export = os.path.join(rc.ROOT, "analysis", "export.py")
        result = subprocess.run([sys.executable, export, self.run], capture_output=True,
                                text=True, timeout=60, cwd=rc.ROOT)
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertEqual(result.stderr.strip().splitlines(),
                         ["clothbench: export: the following arguments are required: --format "
                          "(see clothbench export --help)"])

    def test_tolerance_must_be_a_finite_positive_number(self):
        for bad in ("nan", "inf", "-1", "0", "fast"):
            with self.subTest(tolerance=bad):
                self.assert_fails(self.sweep, f'--tolerance: expected a finite number > 0, got "{bad}"',
                                  args=("--tolerance", bad))

    def test_movie_of_a_folder_without_trajectories_writes_nothing(self):
        # refused before any plot or page is written (ffmpeg or its absence alike)
        self.assert_fails(self.sweep, "ffmpeg" if shutil.which("ffmpeg") is None
                          else "has no trajectory/", args=("--movie",))
        self.assertFalse(os.path.exists(self.out) and os.listdir(self.out), os.listdir(self.out)
                         if os.path.exists(self.out) else "")

    def test_compare_of_different_scenarios(self):
        chain = os.path.join(self.tmp, "chain")
        shutil.copytree(os.path.join(rc.FIXTURES, "chain"), chain)
        self.assert_fails(self.run, "--compare:", "'seed_sphere_drape_7x7'", "'hanging_chain'",
                          "--force", args=("--compare", chain))
        forced = rc.run_report(self.run, "--out", self.out, "--compare", chain, "--force")
        self.assertEqual(forced.returncode, 0, forced.stderr)
        self.assertIn("report: warning: --compare:", forced.stderr)

    def test_missing_folder(self):
        self.assert_fails(os.path.join(self.tmp, "nowhere"), "nowhere", "no such folder")

    def test_folder_without_csv(self):
        empty = os.path.join(self.tmp, "empty")
        os.mkdir(empty)
        self.assert_fails(empty, "empty", "no clothbench CSV file found", "frames.csv")

    def test_missing_column(self):
        rewrite(os.path.join(self.run, "frames.csv"), lambda t: drop_column(t, "energy_error"))
        self.assert_fails(self.run, "frames.csv", "missing required column 'energy_error'")

    def test_missing_sweep_column(self):
        rewrite(os.path.join(self.sweep, "work_precision.csv"),
                lambda t: drop_column(t, "wall_s_per_sim_s"))
        self.assert_fails(self.sweep, "work_precision.csv", "'wall_s_per_sim_s'")

    def test_value_not_a_number(self):
        rewrite(os.path.join(self.run, "summary.csv"),
                lambda t: replace_line(t, 3, lambda line: line.replace(",0.0002,", ",fast,", 1)))
        self.assert_fails(self.run, "summary.csv line 3, column 'dt'", "expected a number",
                          "'fast'")

    def test_truncated_row(self):
        rewrite(os.path.join(self.run, "divergence.csv"),
                lambda t: replace_line(t, 5, lambda line: line.rsplit(",", 2)[0]))
        self.assert_fails(self.run, "divergence.csv line 5", "6 fields, but the header has 8")

    def test_empty_file(self):
        open(os.path.join(self.run, "snapshots.csv"), "w").close()
        self.assert_fails(self.run, "snapshots.csv", "empty file")

    def test_bad_flag(self):
        rewrite(os.path.join(self.run, "frames.csv"),
                lambda t: replace_line(t, 2, lambda line: line[:-1] + "maybe"))
        self.assert_fails(self.run, "frames.csv line 2, column 'stable'", "expected 0 or 1")

    def test_empty_key(self):
        rewrite(os.path.join(self.run, "snapshots.csv"),
                lambda t: replace_line(t, 4, lambda line: "," + line.split(",", 1)[1]))
        self.assert_fails(self.run, "snapshots.csv line 4, column 'engine'", "empty value")

    def test_fractional_grid_index(self):
        rewrite(os.path.join(self.run, "snapshots.csv"),
                lambda t: replace_line(t, 2, lambda line: ",".join(
                    "0.5" if n == 2 else c for n, c in enumerate(line.split(",")))))
        self.assert_fails(self.run, "snapshots.csv", "column 'i'", "grid indices")

    def test_malformed_scenario(self):
        rewrite(os.path.join(self.run, "scenario.toml"), lambda t: t + "\n[cloth\n")
        self.assert_fails(self.run, "scenario.toml", "not valid TOML")

    def test_malformed_run_json(self):
        rewrite(os.path.join(self.run, "run.json"), lambda t: t[:-5])
        self.assert_fails(self.run, "run.json", "not valid JSON")

    def test_bad_compare_folder(self):
        rewrite(os.path.join(self.sweep, "stability.csv"), lambda t: drop_column(t, "cause"))
        self.assert_fails(self.run, "stability.csv", "'cause'", args=("--compare", self.sweep))

    def test_bad_labels(self):
        self.assert_fails(self.run, "--labels", args=("--labels", "a,b"))

    def test_header_only_file_is_not_an_error(self):
        rewrite(os.path.join(self.run, "divergence.csv"), lambda t: t.splitlines()[0] + "\n")
        result = rc.run_report(self.run, "--out", self.out)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.out, "divergence.png")))
        with open(os.path.join(self.out, "report.html"), encoding="utf-8") as f:
            self.assertIn("divergence.csv has a header but no rows.", f.read())


class InternalError(unittest.TestCase):
    """A bug in a plot (here a stand-in that raises) ends in one line, not a traceback."""

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="clothbench-internal-")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def run_main(self, *args, env=None):
        """(exit code or the exception raised, stderr) of report.main in this process."""
        from analysis import report
        from analysis.plots import energy
        err = io.StringIO()
        broken = mock.Mock(side_effect=ZeroDivisionError("float division by zero"))
        with mock.patch.object(energy, "draw", broken), \
                mock.patch.dict(os.environ, env or {}), contextlib.redirect_stderr(err):
            try:
                code = report.main([os.path.join(rc.FIXTURES, "run"),
                                    "--out", os.path.join(self.tmp, "out"), *args])
            except ZeroDivisionError as e:
                code = e
        return code, err.getvalue()

    def test_one_line_and_a_hint(self):
        code, err = self.run_main(env={"CLOTHBENCH_REPORT_DEBUG": ""})
        self.assertEqual(code, 1)
        self.assertEqual(len(err.strip().splitlines()), 1, err)
        self.assertTrue(err.startswith("clothbench: report: internal error: ZeroDivisionError: float "
                                       "division by zero"), err)
        self.assertIn("--debug", err)
        self.assertNotIn("Traceback", err)

    def test_debug_flag_raises(self):
        code, _ = self.run_main("--debug", env={"CLOTHBENCH_REPORT_DEBUG": ""})
        self.assertIsInstance(code, ZeroDivisionError)

    def test_debug_variable_raises(self):
        code, _ = self.run_main(env={"CLOTHBENCH_REPORT_DEBUG": "1"})
        self.assertIsInstance(code, ZeroDivisionError)


if __name__ == "__main__":
    unittest.main()


class DamagedTrajectory(unittest.TestCase):
    """A trajectory index that parses but lacks a field, or has one of the wrong kind: one line
    naming the file, exit 2, never a traceback (export and report alike)."""

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="clothbench-traj-")
        os.makedirs(os.path.join(self.tmp, "trajectory"))

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def export(self, index):
        with open(os.path.join(self.tmp, "trajectory", "trajectory.json"), "w") as f:
            f.write(index)
        return subprocess.run([sys.executable, os.path.join(rc.ROOT, "analysis", "export.py"),
                               self.tmp, "--format", "obj"], capture_output=True, text=True)

    def test_damaged_indexes(self):
        for index, fragment in (('{"engines": []}', "(no 'grid')"),
                                ('{"grid": 3, "engines": []}', "damaged trajectory index"),
                                ('{"grid": [2, 2], "engines": [{"name": "a"}]}', "(no 'file')")):
            with self.subTest(index=index):
                result = self.export(index)
                self.assertEqual(result.returncode, 2, result.stderr)
                self.assertNotIn("Traceback", result.stderr)
                self.assertEqual(len(result.stderr.strip().splitlines()), 1, result.stderr)
                self.assertIn("trajectory.json: a damaged trajectory index", result.stderr)
                self.assertIn(fragment, result.stderr)
