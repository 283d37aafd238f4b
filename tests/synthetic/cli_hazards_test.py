"""End-to-end tests of `terramesh generate hazards` and `terramesh pairs`: the scene writes its
outputs and hazards.csv, seeds are reproducible and differ, the stream meshes, and the pairs the
truth decides for small_wheeled say the ramp joins and the slabs and the pit do not.

Run by ctest with: python3 -m unittest cli_hazards_test (TERRAMESH_BIN and TERRAMESH_SOURCE_DIR set).
"""
import csv
import filecmp
import os
import shutil
import subprocess
import tempfile
import unittest

BIN = os.environ["TERRAMESH_BIN"]
ROBOTS = os.path.join(os.environ["TERRAMESH_SOURCE_DIR"], "traversability", "robots")
OUTPUTS = ["stream.tmstream", "stream.json", "ground_truth.ply", "trajectory.txt", "frames.txt", "generation.txt",
           "hazards.csv"]


def run(*args):
    return subprocess.run([BIN, *args], capture_output=True, text=True, timeout=600)


class HazardsTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="terramesh_hazards_")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def generate(self, name, *args):
        out = os.path.join(self.dir, name)
        result = run("generate", "hazards", "-o", out, "--quiet", *args)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(sorted(os.listdir(out)), sorted(OUTPUTS))
        return out

    def test_seeds_are_reproducible_and_differ(self):
        a = self.generate("a", "--seed", "3")
        b = self.generate("b", "--seed", "3")
        c = self.generate("c", "--seed", "4")
        for name in OUTPUTS:
            self.assertTrue(filecmp.cmp(os.path.join(a, name), os.path.join(b, name), shallow=False), name)
        self.assertFalse(filecmp.cmp(os.path.join(a, "hazards.csv"), os.path.join(c, "hazards.csv"), shallow=False))

    def test_density_is_measured_and_sparse(self):
        out = self.generate("d", "--measure-density")
        with open(os.path.join(out, "generation.txt")) as f:
            values = dict(line.rstrip("\n").split(" ", 1) for line in f if line.strip())
        self.assertEqual(values["scene"], "hazards")
        self.assertEqual(float(values["noise_std_m"]), 0.03)
        self.assertGreaterEqual(float(values["ground_points_per_m2_seen"]), 1.0)
        self.assertLessEqual(float(values["ground_points_per_m2_seen"]), 3.0)

    def test_pairs_follow_the_truth_for_small_wheeled(self):
        out = self.generate("p")
        pairs = os.path.join(self.dir, "pairs.csv")
        result = run("pairs", os.path.join(out, "ground_truth.ply"), "--robot",
                     os.path.join(ROBOTS, "small_wheeled.yaml"), "-o", pairs, "--pairs", "5", "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(pairs) as f:
            rows = list(csv.DictReader(f))
        by_source = {}
        for row in rows:
            by_source.setdefault(row["source"], []).append(row)
        self.assertEqual(len(by_source["random"]), 5)
        self.assertTrue(all(row["reachable"] == "1" for row in by_source["random"]))
        expected = {"slab": "0", "pit": "0", "plateau": "1", "thin_wall": "1", "rock": "1"}
        for kind, reachable in expected.items():
            for row in by_source[kind]:
                self.assertEqual(row["reachable"], reachable, row)
        # Straight at the plateau (up its ramp) drives; straight at a wall or onto a slab does not.
        self.assertEqual(by_source["plateau"][0]["straight_valid"], "1", by_source["plateau"][0])
        for kind in ("slab", "pit", "thin_wall"):
            self.assertTrue(all(row["straight_valid"] == "0" for row in by_source[kind]), kind)

    def test_bad_arguments_exit_2(self):
        result = run("generate", "hazards", "-o", os.path.join(self.dir, "x"), "--length-m", "50")
        self.assertEqual(result.returncode, 2)
        self.assertFalse(os.path.exists(os.path.join(self.dir, "x")))
        out = self.generate("q")
        os.remove(os.path.join(out, "hazards.csv"))
        result = run("pairs", os.path.join(out, "ground_truth.ply"), "--robot",
                     os.path.join(ROBOTS, "small_wheeled.yaml"), "-o", os.path.join(self.dir, "p.csv"), "--pairs", "0")
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.dir, "p.csv")))


if __name__ == "__main__":
    unittest.main()
