"""`terramesh compare STREAM --gt GT.ply`: the views the truth is rendered from default to trajectory.txt beside GT and,
without one, to the stream's own keyframe poses (the run says so); --views naming a missing file exits 2; the figures
come from the scripts shipped beside the executable (share/terramesh/figures), never from a compiled-in source path.

Run by ctest with: python3 -m unittest cli_compare_test (TERRAMESH_BIN set).
"""
import csv
import os
import re
import shutil
import subprocess
import tempfile
import unittest

BIN = os.environ["TERRAMESH_BIN"]


def run(*args):
    return subprocess.run([BIN, *args], capture_output=True, text=True, timeout=900)


class CompareViewsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="terramesh_compare_")
        cls.data = os.path.join(cls.dir, "data")
        result = run("generate", "street", "-o", cls.data, "--quiet", "--length-m", "40", "--seed", "3")
        assert result.returncode == 0, result.stderr
        cls.stream = os.path.join(cls.data, "stream.tmstream")
        cls.alone = os.path.join(cls.dir, "truth_alone")
        os.makedirs(cls.alone)
        shutil.copy(os.path.join(cls.data, "ground_truth.ply"), cls.alone)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def compare(self, name, truth_dir, *extra):
        out = os.path.join(self.dir, name)
        result = run("compare", self.stream, "--gt", os.path.join(truth_dir, "ground_truth.ply"), "--methods",
                     "proposed", "--no-figures", "-o", out, *extra)
        return out, result

    @staticmethod
    def row(out):
        with open(os.path.join(out, "compare.csv"), newline="") as f:
            return next(csv.DictReader(f))

    def test_without_a_trajectory_beside_the_truth_the_stream_keyframes_are_the_views(self):
        beside, with_file = self.compare("beside", self.data)
        self.assertEqual(with_file.returncode, 0, with_file.stderr)
        alone, inferred = self.compare("alone", self.alone)
        self.assertEqual(inferred.returncode, 0, inferred.stderr)
        with open(os.path.join(self.data, "trajectory.txt")) as f:
            keyframes = sum(1 for line in f if line.strip())
        self.assertIn(f"views: the stream's {keyframes} keyframe poses", inferred.stderr)
        with open(os.path.join(alone, "report.md")) as f:
            self.assertRegex(f.read(), rf"rendered from the stream's {keyframes} keyframe poses \([1-9][0-9]* rays\)")
        with open(os.path.join(beside, "report.md")) as f:
            self.assertIn("trajectory.txt`", f.read())
        # The same keyframes seen from their SLAM estimates: the same scores, within the poses' noise.
        a, b = self.row(beside), self.row(alone)
        for column in ("depth_coverage", "accuracy_within_0.25m", "completeness_within_0.25m"):
            self.assertGreater(float(b[column]), 0.1, column)
            self.assertAlmostEqual(float(a[column]), float(b[column]), delta=0.02, msg=column)

    def test_figures_come_from_the_scripts_shipped_beside_the_executable(self):
        out = os.path.join(self.dir, "figures")
        result = run("compare", self.stream, "--gt", os.path.join(self.data, "ground_truth.ply"), "--methods",
                     "proposed", "--pairs", "0", "-o", out, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        for name in ("accuracy_vs_build_time.png", "top_views.png"):
            path = os.path.join(out, name)
            self.assertTrue(os.path.isfile(path), name)
            self.assertEqual(os.stat(path).st_mode & 0o777, 0o644, name)
        with open(os.path.join(out, "report.md")) as f:
            self.assertIn("![top views](top_views.png)", f.read())
        # A copy of the executable with nothing shipped beside it finds no script (no path into the
        # source tree is compiled in): the tables are written, the figures are not.
        alone = os.path.join(self.dir, "bin_alone", "bin")
        os.makedirs(alone)
        copy = shutil.copy(BIN, os.path.join(alone, "terramesh"))
        out = os.path.join(self.dir, "figures_alone")
        result = subprocess.run([copy, "compare", self.stream, "--gt", os.path.join(self.data, "ground_truth.ply"),
                                 "--methods", "proposed", "--pairs", "0", "-o", out], capture_output=True, text=True,
                                timeout=900)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("no figure script at", result.stdout + result.stderr)
        self.assertTrue(os.path.isfile(os.path.join(out, "compare.csv")))
        self.assertFalse(os.path.exists(os.path.join(out, "top_views.png")))

    def test_a_missing_views_file_exits_2_naming_it(self):
        missing = os.path.join(self.dir, "no_such_poses.txt")
        _, result = self.compare("missing", self.alone, "--views", missing)
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn(missing, result.stderr)


if __name__ == "__main__":
    unittest.main()
