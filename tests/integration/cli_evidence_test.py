"""Trajectory evidence in `terramesh mesh --robot R` (issue 22, part 2): on by default, the sensor height estimated
and reported (stderr and summary.txt), driven vertices flagged in mesh.ply, the mesh a 2-manifold for the independent
checker; --no-trajectory-evidence gives the mesh of a run without the robot byte for byte; a given height that
disagrees with the data warns naming both values.

Run by ctest with: python3 -m unittest cli_evidence_test (TERRAMESH_BIN and TERRAMESH_SHARED_DIR set).
"""
import filecmp
import json
import os
import re
import shutil
import subprocess
import tempfile
import unittest

BIN = os.environ["TERRAMESH_BIN"]
SHARED = os.environ["TERRAMESH_SHARED_DIR"]
CHECKER = os.path.join(SHARED, "tools", "check_mesh.py")
ROBOTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "traversability", "robots")


def run(*args):
    return subprocess.run([BIN, *args], capture_output=True, text=True, timeout=900)


def ply_header(path):
    with open(path, "rb") as f:
        header = b""
        while not header.endswith(b"end_header\n"):
            header += f.readline()
    return header.decode()


class EvidenceTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="terramesh_evidence_")
        data = os.path.join(cls.dir, "data")
        result = run("generate", "street", "-o", data, "--quiet", "--length-m", "60")
        assert result.returncode == 0, result.stderr
        cls.stream = os.path.join(data, "stream.tmstream")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def mesh(self, name, *extra):
        out = os.path.join(self.dir, name)
        result = run("mesh", self.stream, "-o", out, "--quiet", "--no-geotiff", *extra)
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(os.path.join(out, "summary.txt")) as f:
            return out, f.read(), result.stderr

    def test_on_by_default_estimates_the_height_and_flags_driven_vertices(self):
        out, summary, _ = self.mesh("on", "--robot", os.path.join(ROBOTS, "small_wheeled.yaml"))
        match = re.search(r"trajectory evidence: on, sensor height estimated from the points beneath the path: "
                          r"([0-9.]+) m \(spread ([0-9.]+) m", summary)
        self.assertIsNotNone(match, summary)
        self.assertAlmostEqual(float(match.group(1)), 1.65, delta=0.05)  # the generator's camera height
        self.assertIn("property uchar driven", ply_header(os.path.join(out, "mesh.ply")))
        checked = subprocess.run(["python3", CHECKER, os.path.join(out, "mesh.ply"), "--json"], capture_output=True,
                                 text=True, timeout=300)
        self.assertEqual(checked.returncode, 0, checked.stdout)

    def test_no_trajectory_evidence_gives_the_mesh_without_robot_byte_for_byte(self):
        plain, _, _ = self.mesh("plain")
        off, summary, _ = self.mesh("off", "--robot", os.path.join(ROBOTS, "car.yaml"), "--no-trajectory-evidence")
        self.assertTrue(filecmp.cmp(os.path.join(plain, "mesh.ply"), os.path.join(off, "mesh.ply"), shallow=False))
        self.assertNotIn("driven", ply_header(os.path.join(off, "mesh.ply")))
        self.assertNotIn("trajectory evidence", summary)

    def test_a_height_that_disagrees_with_the_data_warns_naming_both(self):
        result = run("mesh", self.stream, "-o", os.path.join(self.dir, "warn"), "--no-geotiff",
                     "--robot", os.path.join(ROBOTS, "car.yaml"), "--sensor-height-m", "1.2")
        self.assertEqual(result.returncode, 0, result.stderr)
        warning = [line for line in result.stderr.splitlines() if "warning" in line and "sensor height" in line]
        self.assertEqual(len(warning), 1, result.stderr)
        self.assertIn("1.200 m", warning[0])
        self.assertRegex(warning[0], r"data \(1\.6[0-9]{2} m")
        with open(os.path.join(self.dir, "warn", "summary.txt")) as f:
            self.assertIn(warning[0].split("warning: ", 1)[1], f.read())

    def test_a_resume_with_other_evidence_settings_is_refused(self):
        robot = os.path.join(ROBOTS, "small_wheeled.yaml")
        out, _, _ = self.mesh("checkpointed", "--robot", robot, "--checkpoint-every", "3")
        saved = os.path.join(self.dir, "saved.tmckpt")
        shutil.copy(os.path.join(out, "checkpoint.tmckpt"), saved)
        other = os.path.join(self.dir, "resumed")
        result = run("mesh", self.stream, "-o", other, "--resume", saved, "--robot", robot, "--no-trajectory-evidence")
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("trajectory_evidence", result.stderr)
        self.assertFalse(os.path.exists(other), "nothing written for a refused resume")
        result = run("mesh", self.stream, "-o", other, "--resume", saved, "--robot", robot, "--quiet", "--no-geotiff")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertTrue(filecmp.cmp(os.path.join(out, "mesh.ply"), os.path.join(other, "mesh.ply"), shallow=False))

    def test_stations_between_keyframes_add_driven_ground_and_can_be_turned_off(self):
        robot = os.path.join(ROBOTS, "small_wheeled.yaml")
        with_stations, summary, _ = self.mesh("stations", "--robot", robot)
        without, summary_off, _ = self.mesh("no_stations", "--robot", robot, "--station-spacing-m", "0")
        self.assertIn("at stations at most 0.5 m apart between keyframes", summary)
        self.assertNotIn("at stations", summary_off)
        vertices = [int(re.search(r"element vertex (\d+)", ply_header(os.path.join(d, "mesh.ply"))).group(1))
                    for d in (with_stations, without)]
        # The generated street's keyframes are about 2 m apart: 3-4 stations of 3 samples each.
        self.assertGreater(vertices[0], vertices[1] + 100)
        result = run("mesh", self.stream, "-o", os.path.join(self.dir, "bad_spacing"), "--robot", robot,
                     "--station-spacing-m", "-1")
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("--station-spacing-m", result.stderr)

    def test_sensor_height_without_robot_is_a_usage_error(self):
        result = run("mesh", self.stream, "-o", os.path.join(self.dir, "bad"), "--sensor-height-m", "1.2")
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("--sensor-height-m needs --robot", result.stderr)


if __name__ == "__main__":
    unittest.main()
