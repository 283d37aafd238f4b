"""scripts/check_paths_lidar.py on tiny hand-made clouds: a flat ground with a box and
a hole, paths whose verdicts are known by construction (on the ground, floating, sunk, through the
box, over the hole), the length over unknown faces, and KITTI-style scans where an object seen by
one scan only (moving) does not invalidate a path but one seen by every scan does."""
import csv
import os
import struct
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.path.dirname(__file__), "..", "..", "scripts", "check_paths_lidar.py")


def python_with_numpy():
    """The script needs numpy: this interpreter if it has it, else the system's (the script's shebang)."""
    probe = subprocess.run([sys.executable, "-c", "import numpy"], capture_output=True)
    return sys.executable if probe.returncode == 0 else "/usr/bin/python3"


def write_map(d):
    """A 10 x 4 m rectangle at z = 0 in two triangles: face 0 (y < 0.4 x) known, face 1 unknown."""
    os.makedirs(d)
    with open(os.path.join(d, "traversability.ply"), "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
                "element face 2\nproperty list uchar uint vertex_indices\nproperty uchar unknown\nend_header\n"
                "0 0 0\n10 0 0\n10 4 0\n0 4 0\n3 0 1 2 0\n3 0 2 3 1\n")
    with open(os.path.join(d, "map_frame.yaml"), "w") as f:
        f.write("up: [0, 0, 1]\nmetres_per_unit: 1\n")
    with open(os.path.join(d, "robot.yaml"), "w") as f:
        f.write("name: test\nfootprint:\n  radius_m: 0.34\nmax_step_m: 0.18\nmin_clearance_m: 0.5\n")


def ground(x0=0.0, x1=10.0, hole=(8.0, 9.5)):
    points = []
    for i in range(int(round((x1 - x0) / 0.1)) + 1):
        x = x0 + 0.1 * i
        if hole[0] <= x <= hole[1]:
            continue
        points += [(x, 0.1 * j, 0.0) for j in range(41)]
    return points


def box(x, y, half=0.2):
    """A vertical 0.4 x 0.4 m box from 0.1 to 1.0 m."""
    return [(x + dx, y + dy, 0.1 * k) for dx in (-half, 0, half) for dy in (-half, 0, half) for k in range(1, 11)]


def write_cloud(path, points):
    with open(path, "w") as f:
        f.write(f"ply\nformat ascii 1.0\nelement vertex {len(points)}\nproperty float x\nproperty float y\n"
                "property float z\nend_header\n")
        f.writelines(f"{x:.3f} {y:.3f} {z:.3f}\n" for x, y, z in points)


def write_path(path, states):
    with open(path, "w") as f:
        f.write("x,y,z,yaw,face,cost\n")
        f.writelines(f"{x},{y},{z},0,{face},0\n" for x, y, z, face in states)


class CheckPathsLidarTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.d = cls.tmp.name
        write_map(os.path.join(cls.d, "map"))
        cls.python = python_with_numpy()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def check(self, paths, *cloud_args):
        names = []
        for name, states in paths.items():
            write_path(os.path.join(self.d, name + ".csv"), states)
            names.append(os.path.join(self.d, name + ".csv"))
        out = os.path.join(self.d, "verdicts.csv")
        result = subprocess.run([self.python, SCRIPT, os.path.join(self.d, "map"), *names, *cloud_args, "--csv", out],
                                capture_output=True, text=True, timeout=300)
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(out) as f:
            return {os.path.basename(r["path"])[:-4]: r for r in csv.DictReader(f)}

    def test_verdicts_on_a_merged_cloud(self):
        cloud = os.path.join(self.d, "cloud.ply")
        write_cloud(cloud, ground() + box(6.2, 3.0))
        rows = self.check({
            "on_ground": [(0.5, 1, 0.05, 1), (2.5, 1, 0.05, 1), (4.5, 1, 0.05, 0)],
            "floating": [(0.5, 1, 0.6, 1), (2.5, 1, 0.6, 1), (4.5, 1, 0.6, 0)],
            "sunk": [(5.0, 1, -0.5, 0), (7.0, 1, -0.5, 0)],
            "through_box": [(5.0, 3, 0.0, 1), (7.5, 3, 0.0, 1)],
            "over_hole": [(5.0, 1, 0.0, 0), (9.9, 1, 0.0, 0)],
        }, "--lidar", cloud)
        self.assertEqual(rows["on_ground"]["verdict"], "valid")
        self.assertAlmostEqual(float(rows["on_ground"]["length_m"]), 4.0, places=3)
        # x 0.5 to 2.5 lies on the unknown face (y = 1 > 0.4 x), 2.5 to 4.5 on the known one.
        self.assertAlmostEqual(float(rows["on_ground"]["unknown_m"]), 2.0, places=3)
        self.assertAlmostEqual(float(rows["on_ground"]["median_offset_m"]), 0.05, places=3)
        self.assertEqual(rows["floating"]["verdict"], "invalid")
        self.assertIn("above the LiDAR ground", rows["floating"]["reason"])
        self.assertAlmostEqual(float(rows["floating"]["fail_unknown_m"]), 2.0, places=3)
        self.assertEqual(rows["sunk"]["verdict"], "invalid")
        self.assertIn("below the LiDAR ground", rows["sunk"]["reason"])
        self.assertEqual(float(rows["sunk"]["unknown_m"]), 0.0)
        self.assertEqual(rows["through_box"]["verdict"], "invalid")
        self.assertIn("LiDAR obstacle in the footprint", rows["through_box"]["reason"])
        # The footprint (0.34 m) meets the box (x 6.0 to 6.4) from x 5.66 to 6.74: ~1.1 m fail.
        self.assertGreater(float(rows["through_box"]["fail_m"]), 0.9)
        self.assertLess(float(rows["through_box"]["fail_m"]), 1.3)
        self.assertEqual(rows["over_hole"]["verdict"], "unchecked")
        # The last returns before and after the hole are at x 7.9 and 9.6: the 0.4 m column finds
        # none from x 8.3 to 9.2 (0.9 m).
        self.assertGreater(float(rows["over_hole"]["no_lidar_m"]), 0.8)
        self.assertLess(float(rows["over_hole"]["no_lidar_m"]), 1.0)

    def test_kitti_scans_moving_object(self):
        scans = os.path.join(self.d, "scans")
        os.makedirs(os.path.join(scans, "velodyne"))
        with open(os.path.join(scans, "calib.txt"), "w") as f:
            f.write("Tr: 1 0 0 0 0 1 0 0 0 0 1 0\n")
        poses = os.path.join(self.d, "poses.txt")
        with open(poses, "w") as f:
            f.write("1 0 0 0 0 1 0 0 0 0 1 0\n" * 3)
        for frame in range(3):
            points = ground(hole=(99, 99)) + box(3.0, 3.0) + (box(7.0, 3.0) if frame == 0 else [])
            with open(os.path.join(scans, "velodyne", f"{frame:06d}.bin"), "wb") as f:
                f.write(b"".join(struct.pack("<4f", x, y, z, 0.0) for x, y, z in points))
        args = ("--kitti-scans", scans, "--poses", poses, "--frames", "0:2", "--ego-radius-m", "0")
        rows = self.check({
            "through_static": [(1.5, 3, 0.0, 1), (4.5, 3, 0.0, 1)],
            "through_moving": [(5.5, 3, 0.0, 1), (8.5, 3, 0.0, 1)],
        }, *args)
        self.assertEqual(rows["through_static"]["verdict"], "invalid")
        self.assertIn("LiDAR obstacle in the footprint", rows["through_static"]["reason"])
        self.assertEqual(rows["through_moving"]["verdict"], "valid")


if __name__ == "__main__":
    unittest.main()
