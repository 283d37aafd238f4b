"""What the data holds, the commands take without a flag (issue 23, "No flag a user must guess"):
`terramesh mesh` says which settings it took from the stream and records the scale, up and
sensor height it inferred in mesh.ply's header;
`traverse` takes scale and up from there, `traverse-eval --road-under-path` the sensor height (and,
without a value, the run's own keyframes from trajectory.csv), `convert STREAM OUT.pcd` the views a
point needs, and
`eval --gt-mesh` the views from trajectory.txt beside the truth, else from the run's own
trajectory.csv beside the mesh. Flags override; a malformed record
exits 2 naming the file and line.

Run by ctest with: python3 -m unittest cli_inference_test (TERRAMESH_BIN and TERRAMESH_SHARED_DIR set).
"""
import json
import os
import re
import shutil
import subprocess
import tempfile
import unittest

BIN = os.environ["TERRAMESH_BIN"]
SOURCE = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
ROBOT = os.path.join(SOURCE, "traversability", "robots", "small_wheeled.yaml")


def run(*args):
    return subprocess.run([BIN, *args], capture_output=True, text=True, timeout=900)


def ply_comments(path):
    with open(path, "rb") as f:
        header = f.read(4096).split(b"end_header", 1)[0].decode("ascii")
    return dict(line[len("comment "):].split(" ", 1) for line in header.splitlines()
                if line.startswith("comment frame."))


def yaml_vector(path, key):
    with open(path) as f:
        for line in f:
            if line.startswith(key + ":"):
                return json.loads(line.split(":", 1)[1])
    raise AssertionError(f"{path}: no {key}")


def report_values(path):
    with open(path) as f:
        return dict(line.split(" ", 1) for line in f.read().splitlines())


class InferredFrameTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="terramesh_inference_")
        cls.scene = os.path.join(cls.dir, "scene")
        result = run("generate", "hazards", "-o", cls.scene, "--seed", "3", "--quiet")
        assert result.returncode == 0, result.stderr
        cls.stream = os.path.join(cls.scene, "stream.tmstream")
        cls.map = os.path.join(cls.dir, "map")
        result = run("mesh", cls.stream, "-o", cls.map, "--robot", ROBOT, "--quiet")
        assert result.returncode == 0, result.stderr

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def path(self, name):
        return os.path.join(self.dir, name)

    def test_mesh_records_what_it_inferred(self):
        comments = ply_comments(os.path.join(self.map, "mesh.ply"))
        self.assertEqual(float(comments["frame.metres_per_unit"]), 1.0)
        up = [float(v) for v in comments["frame.up"].split()]
        self.assertEqual(up, yaml_vector(os.path.join(self.map, "map_frame.yaml"), "up"))
        self.assertRegex(comments["frame.up_source"], r"estimated from \d+ keyframe rotations")
        with open(os.path.join(self.map, "summary.txt")) as f:
            estimated = re.search(r"sensor height estimated from the points beneath the path: ([0-9.]+) m", f.read())
        self.assertIsNotNone(estimated)
        self.assertAlmostEqual(float(comments["frame.sensor_height_m"]), float(estimated.group(1)), places=3)
        self.assertEqual(comments["frame.sensor_height_source"], "the data")
        # Without --robot there is no sensor height, but the scale and up are still known.
        plain = self.path("plain")
        result = run("mesh", self.stream, "-o", plain, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        comments = ply_comments(os.path.join(plain, "mesh.ply"))
        self.assertIn("frame.up", comments)
        self.assertNotIn("frame.sensor_height_m", comments)

    def test_traverse_takes_scale_and_up_from_the_mesh(self):
        out = self.path("traverse")
        result = run("traverse", os.path.join(self.map, "mesh.ply"), "--robot", ROBOT, "-o", out)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("from the mesh's header", result.stderr)
        self.assertEqual(yaml_vector(os.path.join(out, "map_frame.yaml"), "up"),
                         yaml_vector(os.path.join(self.map, "map_frame.yaml"), "up"))
        # --up overrides, silently.
        out = self.path("traverse_tilted")
        result = run("traverse", os.path.join(self.map, "mesh.ply"), "--robot", ROBOT, "-o", out, "--up=0,0.6,0.8")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertNotIn("up (", result.stderr)
        self.assertEqual(yaml_vector(os.path.join(out, "map_frame.yaml"), "up"), [0, 0.6, 0.8])

    def test_a_malformed_record_exits_2_naming_file_and_line(self):
        with open(os.path.join(self.map, "mesh.ply"), "rb") as f:
            data = f.read()
        header, body = data.split(b"end_header\n", 1)
        lines = header.decode("ascii").split("\n")
        number = next(i for i, line in enumerate(lines) if line.startswith("comment frame.up "))
        lines[number] = "comment frame.up 0 0 up"
        bad = self.path("bad.ply")
        with open(bad, "wb") as f:
            f.write("\n".join(lines).encode("ascii") + b"end_header\n" + body)
        result = run("traverse", bad, "--robot", ROBOT, "-o", self.path("bad_out"), "--quiet")
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("bad.ply", result.stderr)
        self.assertIn(f"line {number + 1}", result.stderr)
        self.assertIn("frame.up", result.stderr)

    def test_road_under_path_takes_the_recorded_sensor_height(self):
        comments = ply_comments(os.path.join(self.map, "mesh.ply"))
        report = self.path("road.txt")
        result = run("traverse-eval", self.map, "--road-under-path", self.stream, "--report", report, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        values = report_values(report)
        self.assertAlmostEqual(float(values["camera_height_m"]), float(comments["frame.sensor_height_m"]), places=3)
        self.assertIn("mesh.ply records", values["camera_height_source"])
        result = run("traverse-eval", self.map, "--road-under-path", self.stream, "--camera-height-m", "1.2",
                     "--report", report, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        values = report_values(report)
        self.assertEqual(values["camera_height_m"], "1.200")
        self.assertEqual(values["camera_height_source"], "--camera-height-m")

    def test_road_under_path_takes_the_run_s_own_keyframes_without_a_stream(self):
        from_stream, from_run = self.path("road_stream.txt"), self.path("road_run.txt")
        result = run("traverse-eval", self.map, "--road-under-path", self.stream, "--report", from_stream, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        result = run("traverse-eval", self.map, "--road-under-path", "--report", from_run, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        a, b = report_values(from_stream), report_values(from_run)
        self.assertEqual(b["path"], os.path.join(self.map, "trajectory.csv"))
        self.assertGreater(float(b["road_free_m2"]) + float(b["road_lethal_m2"]), 0)
        for key in a:
            if key != "path":
                self.assertEqual(a[key], b[key], key)

    def test_convert_to_pcd_keeps_the_points_the_stream_advises(self):
        def points(path):
            with open(path, "rb") as f:
                for line in f:
                    if line.startswith(b"POINTS "):
                        return int(line.split()[1])
            raise AssertionError(f"{path}: no POINTS line")
        counts = {}
        for views in ("1", None, "3"):
            out = self.path(f"points_{views}.pcd")
            result = run("convert", self.stream, out, *(["--min-views", views] if views else []))
            self.assertEqual(result.returncode, 0, result.stderr)
            counts[views] = points(out)
        self.assertGreater(counts["1"], counts[None])
        self.assertGreater(counts[None], counts["3"])
        # A LiDAR sequence advises 1 view: every return is a point (with 2 it would keep none).
        scene = self.path("lidar_scene")
        result = run("generate", "street", "--length-m", "20", "--seed", "2", "--lidar", "--lidar-scans", "2", "-o", scene,
                     "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        out = self.path("lidar.pcd")
        result = run("convert", os.path.join(scene, "lidar"), out)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("at least 1 keyframe(s) (as the input advises", result.stdout + result.stderr)
        self.assertGreater(points(out), 50000)  # two scans of ~120k returns, those in range

    def test_eval_takes_the_views_beside_the_truth(self):
        truth = os.path.join(self.scene, "ground_truth.ply")
        mesh = os.path.join(self.map, "mesh.ply")
        report = self.path("eval.txt")
        result = run("eval", mesh, "--gt-mesh", truth, "--samples", "2000", "--view-step", "10", "--report", report)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn(os.path.join(self.scene, "trajectory.txt"), result.stderr)
        with open(os.path.join(self.scene, "trajectory.txt")) as f:
            poses = sum(1 for line in f if line.strip())
        self.assertEqual(int(report_values(report)["truth_views"]), len(range(0, poses, 10)))

    def test_mesh_says_what_it_took_from_the_stream_and_what_from_a_flag(self):
        with open(os.path.join(self.map, "summary.txt")) as f:
            summary = f.read()
        self.assertIn("inferred: scale: 1 m per map unit, as the input states it", summary)
        self.assertIn("inferred: min_views: 2, the mesher's default: the input advises none", summary)
        self.assertIn("inferred: sensor up axis: 0,-1,0 in the sensor frame (a camera", summary)
        out = self.path("overridden")
        result = run("mesh", self.stream, "-o", out, "--metres-per-unit", "2", "--min-views", "3")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("terramesh: inferred: scale: 2 m per map unit, from --metres-per-unit", result.stderr)
        self.assertIn("terramesh: inferred: min_views: 3, from --min-views", result.stderr)

    def test_eval_takes_the_views_of_the_run_without_a_trajectory_beside_the_truth(self):
        truth = os.path.join(self.scene, "ground_truth.ply")
        mesh = os.path.join(self.map, "mesh.ply")
        alone = self.path("truth_alone")
        os.makedirs(alone)
        shutil.copy(truth, alone)
        truth_alone = os.path.join(alone, "ground_truth.ply")
        # The stream's keyframes are the poses trajectory.txt lists: the same views, the same report.
        beside, from_run = self.path("beside.txt"), self.path("from_run.txt")
        common = ["--samples", "2000", "--view-step", "10"]
        self.assertEqual(run("eval", mesh, "--gt-mesh", truth, *common, "--report", beside).returncode, 0)
        result = run("eval", mesh, "--gt-mesh", truth_alone, *common, "--report", from_run)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("the keyframes of " + os.path.join(self.map, "trajectory.csv"), result.stderr)
        a, b = report_values(beside), report_values(from_run)
        self.assertGreater(int(b["truth_views"]), 1)
        for key in a:
            if key != "truth":
                self.assertEqual(a[key], b[key], key)
        # Neither beside the truth nor beside the mesh: a clear usage error.
        mesh_alone = self.path("mesh_alone")
        os.makedirs(mesh_alone)
        shutil.copy(mesh, mesh_alone)
        result = run("eval", os.path.join(mesh_alone, "mesh.ply"), "--gt-mesh", truth_alone, "--quiet")
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("no trajectory.txt beside", result.stderr)
        self.assertIn("no trajectory.csv beside", result.stderr)
        # A malformed trajectory.csv names its file, line and field.
        with open(os.path.join(self.map, "trajectory.csv")) as f:
            lines = f.read().splitlines()
        fields = lines[2].split(",")
        fields[6] = "nan"
        lines[2] = ",".join(fields)
        with open(os.path.join(mesh_alone, "trajectory.csv"), "w") as f:
            f.write("\n".join(lines) + "\n")
        result = run("eval", os.path.join(mesh_alone, "mesh.ply"), "--gt-mesh", truth_alone, "--quiet")
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("trajectory.csv", result.stderr)
        self.assertIn("line 3, field 7", result.stderr)
        self.assertEqual(len(result.stderr.strip().splitlines()), 1, result.stderr)


if __name__ == "__main__":
    unittest.main()
