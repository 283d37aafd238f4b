"""End-to-end tests of `terramesh mesh`: real KITTI 00 data through the independent mesh checker,
every mode, every output option, and bad input (exit code 2, one line naming the file, no output).

Run by ctest with: python3 -m unittest cli_mesh_test (TERRAMESH_BIN and TERRAMESH_SHARED_DIR set).
"""
import csv
import json
import os
import shutil
import subprocess
import tempfile
import unittest

BIN = os.environ["TERRAMESH_BIN"]
SHARED = os.environ["TERRAMESH_SHARED_DIR"]
CHECKER = os.path.join(SHARED, "tools", "check_mesh.py")
KITTI = os.path.join(SHARED, "data", "kitti00_orbslam", "slam_data_version0.1_KITTI00_50frames.json")
KITTI_V02 = os.path.join(SHARED, "data", "kitti00_orbslam",
                         "non_incremental_slam_data_version0.2_KITTI00_200frames.json")
KITTI_SCALE = "16.589"  # metres per ORB-SLAM unit (piazza_sim3_to_gt_icp.txt)


def run(*args):
    return subprocess.run([BIN, *args], capture_output=True, text=True, timeout=600)


def check_mesh(path, *flags):
    result = subprocess.run(["python3", CHECKER, path, "--json", *flags], capture_output=True,
                            text=True, timeout=300)
    return result.returncode, json.loads(result.stdout) if result.stdout.strip() else None


class TempDirCase(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="terramesh_cli_")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def out(self, name="out"):
        return os.path.join(self.dir, name)


class KittiMeshTest(TempDirCase):
    def assert_kitti_run(self, *extra):
        out = self.out()
        result = run("mesh", KITTI, "-o", out, "--metres-per-unit", KITTI_SCALE,
                     "--check-invariants", *extra)
        self.assertEqual(result.returncode, 0, result.stderr)
        code, report = check_mesh(os.path.join(out, "mesh.ply"))
        self.assertEqual(code, 0, report)
        self.assertGreater(report["faces"], 1000)
        self.assertEqual(report["boundary_edges"], 0)
        with open(os.path.join(out, "keyframes.csv")) as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), 17)  # one row per view of the file
        total_new = sum(int(r["new_points"]) for r in rows)
        self.assertGreater(total_new, 800)
        for r in rows:
            self.assertGreaterEqual(float(r["time_total_s"]),
                                    float(r["time_ray_tracing_s"]) + float(r["time_grow_s"]) - 1e-9)
        return out, rows

    def test_proposed_mode_gives_a_manifold_and_the_table(self):
        out, rows = self.assert_kitti_run()
        self.assertTrue(any(int(r["moved_points"]) > 0 for r in rows), "points move in this file")
        with open(os.path.join(out, "summary.txt")) as f:
            self.assertIn("closed 2-manifold", f.read())

    def test_baseline_modes_give_manifolds(self):
        for mode in ("litvinov13", "romanoni15"):
            with self.subTest(mode=mode):
                self.assert_kitti_run("--mode", mode)
                shutil.rmtree(self.out())

    def test_without_a_scale_the_map_units_are_taken_as_metres(self):
        out = self.out()
        result = run("mesh", KITTI, "-o", out, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(result.stdout, "")
        self.assertEqual(check_mesh(os.path.join(out, "mesh.ply"))[0], 0)

    def test_obj_output_snapshots_and_open_surface(self):
        out = self.out()
        result = run("mesh", KITTI, "-o", out, "--metres-per-unit", KITTI_SCALE, "--format", "obj",
                     "--snapshot-every", "5", "--drop-steiner")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(check_mesh(os.path.join(out, "mesh.obj"))[0], 0)
        snapshots = sorted(os.listdir(os.path.join(out, "snapshots")))
        self.assertEqual(snapshots, ["mesh_000005.obj", "mesh_000010.obj", "mesh_000015.obj"])
        for name in snapshots:
            self.assertEqual(check_mesh(os.path.join(out, "snapshots", name))[0], 0, name)
        code, report = check_mesh(os.path.join(out, "mesh_open.obj"), "--allow-boundary")
        self.assertGreater(report["boundary_edges"], 0)
        self.assertIn("open surface", result.stdout)
        self.assertIn("non-manifold vertices", result.stdout)

    def test_version_02_file(self):
        out = self.out()
        result = run("mesh", KITTI_V02, "-o", out, "--metres-per-unit", KITTI_SCALE,
                     "--check-invariants")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(check_mesh(os.path.join(out, "mesh.ply"))[0], 0)


class SyntheticStreamTest(TempDirCase):
    """Every synthetic scene, generated small, meshed with invariants checked after each update."""

    def generate(self, scene, *args):
        data = self.out("data_" + scene)
        result = run("generate", scene, "-o", data, "--quiet", *args)
        self.assertEqual(result.returncode, 0, result.stderr)
        return os.path.join(data, "stream.tmstream")

    def assert_meshes(self, stream, *args):
        out = self.out("mesh")
        result = run("mesh", stream, "-o", out, "--check-invariants", "--quiet", *args)
        self.assertEqual(result.returncode, 0, result.stderr)
        code, report = check_mesh(os.path.join(out, "mesh.ply"))
        self.assertEqual(code, 0, report)
        with open(os.path.join(out, "keyframes.csv")) as f:
            rows = list(csv.DictReader(f))
        shutil.rmtree(out)
        return report, rows

    def test_street_offroad_and_garage(self):
        for scene, extra in (("street", ["--length-m", "80"]), ("offroad", ["--length-m", "60"]),
                             ("garage", ["--length-m", "40"])):
            with self.subTest(scene=scene):
                report, rows = self.assert_meshes(self.generate(scene, *extra))
                self.assertGreater(report["faces"], 500)
                self.assertGreater(sum(int(r["moved_points"]) for r in rows), 0)

    def test_loop_closure_corrections_keep_the_mesh_manifold(self):
        stream = self.generate("street", "--length-m", "90", "--loop-closure-drift-m", "2")
        report, rows = self.assert_meshes(stream)
        # Re-sent keyframes (corrected poses) withdraw and re-walk their rays.
        self.assertGreater(sum(int(r["rays_untraced"]) for r in rows), 0)

    def test_json_and_stream_formats_give_the_same_mesh_file(self):
        # Two processes (different memory layouts) and two formats: byte-identical meshes.
        stream = self.generate("street", "--length-m", "60")
        meshes = []
        for path in (stream, stream.replace(".tmstream", ".json")):
            out = self.out("m_" + os.path.basename(path))
            self.assertEqual(run("mesh", path, "-o", out, "--quiet").returncode, 0)
            with open(os.path.join(out, "mesh.ply"), "rb") as f:
                meshes.append(f.read())
        self.assertEqual(meshes[0], meshes[1])

    def test_every_mode_on_a_synthetic_street(self):
        stream = self.generate("street", "--length-m", "60")
        for mode in ("litvinov13", "romanoni15"):
            with self.subTest(mode=mode):
                self.assert_meshes(stream, "--mode", mode)


class BadInputTest(TempDirCase):
    def write(self, name, text):
        path = os.path.join(self.dir, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def assert_rejected(self, args, *expected_fragments):
        out = self.out()
        result = run("mesh", *args, "-o", out)
        self.assertEqual(result.returncode, 2, result.stderr)
        lines = result.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, result.stderr)
        for fragment in expected_fragments:
            self.assertIn(fragment, lines[0])
        self.assertFalse(os.path.exists(out), "no output may be written for bad input")

    def test_missing_file(self):
        path = os.path.join(self.dir, "absent.json")
        self.assert_rejected([path], path, "cannot open")

    def test_malformed_json_names_line_and_column(self):
        path = self.write("bad.json", '{"slam_data_version": "0.1",\n "views": [ {,} ]}')
        self.assert_rejected([path], path, "line 2", "malformed JSON")

    def test_wrong_type_names_the_field(self):
        view = {"key": 0, "extrinsic": {"rotation": [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
                                        "center": [0, "x", 0]}, "observations": []}
        path = self.write("type.json", json.dumps({"slam_data_version": "0.1", "views": [view]}))
        self.assert_rejected([path], "views[0].extrinsic.center[1]", "expected a number")

    def test_unknown_version(self):
        path = self.write("v.json", json.dumps({"slam_data_version": "9.9", "views": []}))
        self.assert_rejected([path], "slam_data_version", "9.9")

    def test_unknown_extension(self):
        path = self.write("stream.txt", "hello")
        self.assert_rejected([path], "unknown stream format")

    def test_bad_option_value(self):
        self.assert_rejected([KITTI, "--mode", "fastest"], "--mode")
        self.assert_rejected([KITTI, "--steiner-step-m", "-3"], "steiner_step_m")

    def test_truncated_stream_file(self):
        path = self.write("cut.tmstream", "terramesh_stream 1\nkeyframe 0 0 0 0 1 0 0 0 3\n1 0 0 5\n")
        self.assert_rejected([path], path, "line 3", "file ends inside the keyframe")

    def test_missing_output_option_is_a_usage_error(self):
        result = run("mesh", KITTI)
        self.assertEqual(result.returncode, 2)
        self.assertIn("--output", result.stderr)


if __name__ == "__main__":
    unittest.main()
