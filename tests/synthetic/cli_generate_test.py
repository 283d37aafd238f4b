"""End-to-end tests of `terramesh generate`: each scene writes its five outputs, the stream runs
through `terramesh mesh` to a mesh the shared checker accepts, and bad input exits with code 2
and one line, writing nothing.

Run by ctest with: python3 -m unittest cli_generate_test (TERRAMESH_BIN and TERRAMESH_SHARED_DIR set).
"""
import json
import os
import shutil
import subprocess
import tempfile
import unittest

BIN = os.environ["TERRAMESH_BIN"]
SHARED = os.environ["TERRAMESH_SHARED_DIR"]
CHECKER = os.path.join(SHARED, "tools", "check_mesh.py")
KITTI_POSES = os.path.join(SHARED, "data", "kitti_poses", "00.txt")
OUTPUTS = ["stream.tmstream", "stream.json", "ground_truth.ply", "trajectory.txt", "frames.txt", "generation.txt"]


def run(*args):
    return subprocess.run([BIN, *args], capture_output=True, text=True, timeout=600)


def read_generation(path):
    with open(os.path.join(path, "generation.txt")) as f:
        return dict(line.rstrip("\n").split(" ", 1) for line in f if line.strip())


class TempDirCase(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="terramesh_generate_")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def out(self, name="out"):
        return os.path.join(self.dir, name)


class GenerateTest(TempDirCase):
    def generate(self, *args):
        out = self.out(args[0])
        result = run("generate", *args, "-o", out, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(result.stdout, "")
        self.assertEqual(sorted(os.listdir(out)), sorted(OUTPUTS), "outputs only, no temporary files")
        return out, read_generation(out)

    def assert_meshes(self, out):
        mesh_out = os.path.join(out, "mesh")
        result = run("mesh", os.path.join(out, "stream.tmstream"), "-o", mesh_out, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        checked = subprocess.run(["python3", CHECKER, os.path.join(mesh_out, "mesh.ply"), "--json"],
                                 capture_output=True, text=True, timeout=300)
        self.assertEqual(checked.returncode, 0, checked.stdout + checked.stderr)
        self.assertGreater(json.loads(checked.stdout)["faces"], 1000)

    def test_every_scene_generates_and_meshes(self):
        for scene, length in [("street", "120"), ("offroad", "60"), ("garage", "40")]:
            with self.subTest(scene=scene):
                out, generation = self.generate(scene, "--length-m", length)
                self.assertEqual(generation["scene"], scene)
                self.assertEqual(generation["metres_per_unit"], "1")
                keyframes = int(generation["keyframes"])
                self.assertGreater(keyframes, 15)
                with open(os.path.join(out, "trajectory.txt")) as f:
                    lines = f.read().splitlines()
                self.assertEqual(len(lines), keyframes, "one true pose per keyframe")
                self.assertTrue(all(len(line.split()) == 12 for line in lines))
                with open(os.path.join(out, "ground_truth.ply"), "rb") as f:
                    header = f.read(600).split(b"end_header")[0].decode()
                self.assertIn("property uchar label", header)
                self.assertIn("property float slope_deg", header)
                self.assertIn("element face " + generation["ground_truth_faces"], header)
                with open(os.path.join(out, "stream.json")) as f:
                    self.assertEqual(len(json.load(f)["views"]), keyframes)
                self.assert_meshes(out)

    def test_street_along_kitti_poses_with_loop_closure(self):
        out, generation = self.generate("street", "--kitti-poses", KITTI_POSES, "--frames", "0:400",
                                        "--keyframe-every", "4", "--loop-closure-drift-m", "1.5")
        self.assertEqual(generation["frames"], "400")
        self.assertEqual(generation["keyframes"], "100")
        self.assertEqual(generation["up_W"], "0 -1 0")
        self.assertGreater(int(generation["keyframe_events"]), 100, "the drift window is re-sent")
        self.assertIn("00.txt frames 0:400", generation["trajectory"])

    def test_same_seed_same_files(self):
        first, _ = self.generate("garage", "--length-m", "40", "--seed", "3")
        again = self.out("again")
        self.assertEqual(run("generate", "garage", "--length-m", "40", "--seed", "3", "-o", again,
                             "--quiet").returncode, 0)
        for name in OUTPUTS:
            with open(os.path.join(first, name), "rb") as a, open(os.path.join(again, name), "rb") as b:
                self.assertEqual(a.read(), b.read(), name)


class LidarTest(TempDirCase):
    """`generate --lidar`: a KITTI odometry sequence beside the camera stream, which it leaves
    unchanged, and which `terramesh mesh` reads as it is."""

    def test_lidar_sequence_beside_an_unchanged_camera_stream_meshes(self):
        plain, lidar = self.out("plain"), self.out("lidar")
        for out, extra in [(plain, []), (lidar, ["--lidar", "--lidar-scans", "3"])]:
            result = run("generate", "street", "--length-m", "60", "--seed", "2", "-o", out, "--quiet", *extra)
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assertEqual(result.stdout, "")
        self.assertEqual(sorted(os.listdir(lidar)), sorted(OUTPUTS + ["lidar"]))
        for name in OUTPUTS[:-1]:
            with open(os.path.join(plain, name), "rb") as a, open(os.path.join(lidar, name), "rb") as b:
                self.assertEqual(a.read(), b.read(), name + " is the same with --lidar")
        generation = read_generation(lidar)
        self.assertEqual(generation["lidar_scans"], "3")
        self.assertEqual(generation["lidar_beams"], "64")
        self.assertNotIn("lidar_scans", read_generation(plain))

        sequence = os.path.join(lidar, "lidar")
        self.assertEqual(sorted(os.listdir(sequence)), ["calib.txt", "poses.txt", "times.txt", "velodyne"])
        scans = sorted(os.listdir(os.path.join(sequence, "velodyne")))
        self.assertEqual(scans, ["000000.bin", "000001.bin", "000002.bin"])
        sizes = [os.path.getsize(os.path.join(sequence, "velodyne", scan)) for scan in scans]
        self.assertTrue(all(size % 16 == 0 for size in sizes))
        self.assertEqual(sum(sizes) // 16, int(generation["lidar_returns"]))
        with open(os.path.join(sequence, "poses.txt")) as f:
            poses = [line.split() for line in f]
        self.assertEqual([len(pose) for pose in poses], [12, 12, 12])
        # Scans 8 m/s / 10 Hz apart along a nearly straight road: cam0 moves 0.8 m a scan.
        step = sum((float(poses[1][k]) - float(poses[0][k])) ** 2 for k in (3, 7, 11)) ** 0.5
        self.assertAlmostEqual(step, 0.8, delta=0.01)
        with open(os.path.join(sequence, "times.txt")) as f:
            self.assertEqual([float(t) for t in f.read().split()], [0.0, 0.1, 0.2])
        with open(os.path.join(sequence, "calib.txt")) as f:
            self.assertEqual(len(f.readline().split()), 13, "Tr: and 12 numbers")

        mesh_out = self.out("mesh")
        result = run("mesh", sequence, "--max-returns-per-scan", "5000", "-o", mesh_out)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("inferred: Steiner lattice: 2 m, as the input advises", result.stderr)
        checked = subprocess.run(["python3", CHECKER, os.path.join(mesh_out, "mesh.ply"), "--json"],
                                 capture_output=True, text=True, timeout=300)
        self.assertEqual(checked.returncode, 0, checked.stdout + checked.stderr)
        self.assertGreater(json.loads(checked.stdout)["faces"], 1000)

        # Against the scans themselves: the advised lattice keeps the faces that close what no ray
        # reached near the returns (and marks them interpolated), where the mesher's default
        # 10 m lattice leaves long measured faces between them.
        coarse_out = self.out("mesh_10m")
        result = run("mesh", sequence, "--max-returns-per-scan", "5000", "--steiner-step-m", "10", "-o", coarse_out)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("inferred: Steiner lattice: 10 m, from --steiner-step-m", result.stderr)
        scores = {}
        for name, out in (("advised", mesh_out), ("10 m", coarse_out)):
            report = self.out(name.replace(" ", "_") + ".txt")
            result = run("eval", os.path.join(out, "mesh.ply"), "--gt-lidar", sequence, "--poses",
                         os.path.join(sequence, "poses.txt"), "--frames", "0:2", "--report", report, "--quiet")
            self.assertEqual(result.returncode, 0, result.stderr)
            with open(report) as f:
                scores[name] = dict(line.split()[:2] for line in f if len(line.split()) == 2)
        accuracy = {name: float(v["accuracy_within_0.20m"]) for name, v in scores.items()}
        self.assertGreater(accuracy["advised"], accuracy["10 m"] + 0.2, accuracy)
        for name, v in scores.items():
            self.assertGreater(float(v["completeness_within_0.25m"]), 0.85, name)


class BadInputTest(TempDirCase):
    def assert_bad(self, *args, mention=None):
        out = self.out()
        result = run("generate", *args, "-o", out)
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertEqual(len(result.stderr.strip().splitlines()), 1, result.stderr)
        if mention:
            self.assertIn(mention, result.stderr)
        self.assertFalse(os.path.exists(out), "nothing written on bad input")

    def test_bad_arguments(self):
        self.assert_bad("moon", mention="street, offroad, garage or hazards")
        self.assert_bad("street", "--noise-std-m", "-1", mention="noise_std_m")
        self.assert_bad("street", "--noise-std-m", "abc", mention="--noise-std-m")
        self.assert_bad("street", "--keyframe-spacing-m", "2", "--keyframe-every", "3")
        self.assert_bad("street", "--preset", "kitti-like", mention="--kitti-poses")
        self.assert_bad("garage", "--kitti-poses", KITTI_POSES)
        self.assert_bad("street", "--kitti-poses", KITTI_POSES, "--frames", "9:3")
        self.assert_bad("street", "--kitti-poses", KITTI_POSES, "--frames", "5000:6000", mention="empty")
        self.assert_bad("garage", "--length-m", "10", mention="length_m")
        self.assert_bad("street", "--unknown-option", "1")

    def test_bad_lidar_options(self):
        self.assert_bad("street", "--lidar", "--lidar-scans", "0", mention="--lidar-scans")
        self.assert_bad("street", "--lidar", "--lidar-scans", "2.5", mention="whole number")
        self.assert_bad("street", "--lidar", "--lidar-speed-m-per-s", "-1", mention="--lidar-speed-m-per-s")
        self.assert_bad("street", "--lidar", "--lidar-speed-m-per-s", "1e-9", mention="--lidar-scans N")
        self.assert_bad("street", "--lidar", "--lidar-range-noise-m", "x", mention="--lidar-range-noise-m")
        self.assert_bad("street", "--lidar-scans", "3", mention="needs --lidar")

    def test_bad_pose_files_name_file_and_line(self):
        self.assert_bad("street", "--kitti-poses", self.out("missing.txt"), mention="missing.txt")
        bad = self.out("bad.txt")
        with open(bad, "w") as f:
            f.write("1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 x\n")
        self.assert_bad("street", "--kitti-poses", bad, mention="line 2")

    def test_missing_output_is_a_usage_error(self):
        result = run("generate", "street")
        self.assertEqual(result.returncode, 2)
        self.assertIn("--output", result.stderr)


if __name__ == "__main__":
    unittest.main()
