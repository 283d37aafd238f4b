"""End-to-end tests of `terramesh mesh` and `terramesh eval`: real KITTI 00 data through the independent mesh checker,
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

    def assert_cli_rejected(self, args, output, *fragments):
        """Exit code 2, one stderr line holding every fragment, and nothing written at `output`."""
        result = run(*args)
        self.assertEqual(result.returncode, 2, result.stderr)
        lines = result.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, result.stderr)
        for fragment in fragments:
            self.assertIn(fragment, lines[0])
        self.assertFalse(os.path.exists(output), "no output may be written for bad input")


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
        # Two processes (different memory layouts) and two formats: byte-identical meshes, but for
        # the scale the header records: the stream states it, the authors' JSON cannot.
        stream = self.generate("street", "--length-m", "60")
        meshes = []
        for path in (stream, stream.replace(".tmstream", ".json")):
            out = self.out("m_" + os.path.basename(path))
            self.assertEqual(run("mesh", path, "-o", out, "--quiet").returncode, 0)
            with open(os.path.join(out, "mesh.ply"), "rb") as f:
                meshes.append(f.read())
        frames, bodies = [], []
        for data in meshes:
            header, body = data.split(b"end_header\n", 1)
            lines = header.decode("ascii").splitlines()
            frames.append(dict(line.split(" ", 2)[1:] for line in lines if line.startswith("comment frame.")))
            bodies.append(([line for line in lines if not line.startswith("comment frame.")], body))
        self.assertEqual(bodies[0], bodies[1])
        self.assertEqual(frames[0]["frame.metres_per_unit"], "1")
        self.assertNotIn("frame.metres_per_unit", frames[1])
        # Up from the same rotations, parsed from two formats: equal to rounding.
        ups = [[float(v) for v in frame["frame.up"].split()] for frame in frames]
        for a, b in zip(*ups):
            self.assertAlmostEqual(a, b, places=12)

    def test_ablation_switches_and_camera_enclosing_keep_the_invariants(self):
        stream = self.generate("garage", "--length-m", "40")
        _, default_rows = self.assert_meshes(stream)
        for options in (["--camera-enclosing-radius-cells", "2"],
                        ["--disable", "incremental-steiner-grid,next-cell-cache,ray-scheduler"]):
            with self.subTest(options=options):
                report, rows = self.assert_meshes(stream, *options)
                self.assertGreater(report["faces"], 500)
                # The options are in effect: the enclosing sets (or the grid) differ from the default.
                self.assertNotEqual([(r["enclosing_cells"], r["steiner_points"]) for r in rows],
                                    [(r["enclosing_cells"], r["steiner_points"]) for r in default_rows])

    def test_every_mode_on_a_synthetic_street(self):
        stream = self.generate("street", "--length-m", "60")
        for mode in ("litvinov13", "romanoni15"):
            with self.subTest(mode=mode):
                self.assert_meshes(stream, "--mode", mode)


def read_report(path):
    """An eval report: one `name value` pair per line (values after the first field kept as text)."""
    values = {}
    with open(path) as f:
        for line in f:
            name, _, value = line.strip().partition(" ")
            values[name] = value
    return values


class EvalTest(TempDirCase):
    """`terramesh eval` on real and synthetic data, with known-good and deliberately wrong inputs."""

    LIDAR = os.path.join(SHARED, "data", "kitti00_lidar")
    POSES = os.path.join(SHARED, "data", "kitti_poses", "00.txt")

    def eval_kitti(self, mesh, sim3, name):
        report = self.out(name + ".txt")
        result = run("eval", mesh, "--gt-lidar", self.LIDAR, "--poses", self.POSES, "--frames", "1:10",
                     "--sim3", sim3, "--samples", "20000", "--report", report, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        return read_report(report)

    def test_kitti_mesh_against_the_lidar_and_a_misaligned_copy(self):
        out = self.out("kitti")
        self.assertEqual(run("mesh", KITTI, "-o", out, "--metres-per-unit", KITTI_SCALE, "--quiet").returncode, 0)
        mesh = os.path.join(out, "mesh.ply")
        good = self.eval_kitti(mesh, os.path.join(self.LIDAR, "piazza_sim3_to_gt_icp.txt"), "good")
        self.assertEqual(int(good["truth_scans"]), 10)
        self.assertGreater(int(good["depth_truth_rays"]), 100000)
        self.assertGreater(float(good["depth_coverage_within_0.50m"]), 0.2)
        self.assertLess(float(good["accuracy_median_m"]), 0.5)
        self.assertLess(float(good["completeness_median_m"]), 0.5)
        # The same similarity lifted by 1 m (KITTI's y points down): every measure must get clearly worse.
        shifted = self.out("shifted_sim3.txt")
        with open(os.path.join(self.LIDAR, "piazza_sim3_to_gt_icp.txt")) as src, open(shifted, "w") as dst:
            for line in src:
                if line.startswith("t "):
                    t = [float(x) for x in line.split()[1:]]
                    line = "t %r %r %r\n" % (t[0], t[1] - 1.0, t[2])
                dst.write(line)
        bad = self.eval_kitti(mesh, shifted, "bad")
        self.assertLess(float(bad["depth_coverage_within_0.50m"]),
                        0.5 * float(good["depth_coverage_within_0.50m"]))
        self.assertGreater(float(bad["accuracy_median_m"]), 2 * float(good["accuracy_median_m"]))

    def test_synthetic_ground_truth_scores_perfectly_and_the_mesh_well(self):
        data = self.out("garage")
        self.assertEqual(run("generate", "garage", "-o", data, "--quiet").returncode, 0)
        truth = os.path.join(data, "ground_truth.ply")
        views = os.path.join(data, "trajectory.txt")
        report = self.out("self.txt")
        result = run("eval", truth, "--gt-mesh", truth, "--views", views, "--view-step", "5",
                     "--samples", "20000", "--report", report, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        perfect = read_report(report)
        self.assertEqual(perfect["depth_rays_hitting_mesh"], perfect["depth_truth_rays"])
        self.assertLess(float(perfect["depth_mean_abs_error_m"]), 1e-3)
        self.assertEqual(float(perfect["depth_coverage_within_0.50m"]), 1.0)
        self.assertLess(float(perfect["accuracy_p90_m"]), 1e-3)
        mesh_out = self.out("mesh")
        self.assertEqual(run("mesh", os.path.join(data, "stream.tmstream"), "-o", mesh_out, "--quiet").returncode, 0)
        result = run("eval", os.path.join(mesh_out, "mesh.ply"), "--gt-mesh", truth, "--views", views,
                     "--view-step", "5", "--samples", "20000", "--report", report, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        ours = read_report(report)
        self.assertGreater(int(ours["mesh_steiner_vertices"]), 0)
        self.assertGreater(float(ours["depth_coverage_within_0.50m"]), 0.3)
        self.assertLess(float(ours["accuracy_median_m"]), 0.3)

    def assert_eval_rejected(self, args, *fragments):
        report = self.out("report.txt")
        self.assert_cli_rejected(["eval", *args, "--report", report], report, *fragments)

    def test_bad_input(self):
        missing = os.path.join(self.dir, "absent.ply")
        self.assert_eval_rejected([missing, "--gt-mesh", missing, "--views", self.POSES], missing)
        sim3 = os.path.join(self.LIDAR, "piazza_sim3_to_gt_icp.txt")
        self.assert_eval_rejected([missing, "--gt-lidar", self.LIDAR], "--poses")
        self.assert_eval_rejected([missing, "--gt-lidar", self.LIDAR, "--gt-mesh", missing], "exactly one")
        bad_sim3 = os.path.join(self.dir, "bad_sim3.txt")
        with open(bad_sim3, "w") as f:
            f.write("s 1\nR 1 0 0 0 1 0 0 0 1\n")
        out = self.out("kitti")
        self.assertEqual(run("mesh", KITTI, "-o", out, "--metres-per-unit", KITTI_SCALE, "--quiet").returncode, 0)
        mesh = os.path.join(out, "mesh.ply")
        self.assert_eval_rejected([mesh, "--gt-lidar", self.LIDAR, "--poses", self.POSES, "--sim3", bad_sim3],
                                  bad_sim3, "missing t")
        self.assert_eval_rejected([mesh, "--gt-lidar", self.LIDAR, "--poses", self.POSES, "--sim3", sim3,
                                   "--frames", "200:210"], "no scan for frames 200 to 210")


class BadInputTest(TempDirCase):
    def write(self, name, text):
        path = os.path.join(self.dir, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def assert_rejected(self, args, *expected_fragments):
        out = self.out()
        self.assert_cli_rejected(["mesh", *args, "-o", out], out, *expected_fragments)

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
        self.assert_rejected([KITTI, "--camera-enclosing-radius-cells", "9"], "camera_enclosing_radius_cells")
        self.assert_rejected([KITTI, "--disable", "boundary-hash,warp-drive"], "--disable", "warp-drive")

    def test_truncated_stream_file(self):
        path = self.write("cut.tmstream", "terramesh_stream 1\nkeyframe 0 0 0 0 1 0 0 0 3\n1 0 0 5\n")
        self.assert_rejected([path], path, "line 3", "file ends inside the keyframe")

    def test_missing_output_option_is_a_usage_error(self):
        result = run("mesh", KITTI)
        self.assertEqual(result.returncode, 2)
        self.assertIn("--output", result.stderr)


if __name__ == "__main__":
    unittest.main()
