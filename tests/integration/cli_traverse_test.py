"""End-to-end tests of the traversability map: `terramesh mesh --robot` on synthetic streams (the
exports rewritten every K keyframes), `terramesh traverse` on the finished mesh, and bad input.
Files are parsed here independently of the C++ readers (PLY header and size, PGM, map YAML).

Run by ctest with: python3 -m unittest cli_traverse_test (TERRAMESH_BIN and TERRAMESH_SHARED_DIR set).
"""
import csv
import json
import math
import os
import re
import shutil
import subprocess
import tempfile
import unittest

BIN = os.environ["TERRAMESH_BIN"]
SHARED = os.environ["TERRAMESH_SHARED_DIR"]
SOURCE = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CHECKER = os.path.join(SHARED, "tools", "check_mesh.py")
ROBOT = os.path.join(SOURCE, "traversability", "robots", "small_wheeled.yaml")

# list, cost, lethal, unknown, uncertain, 7 floats, height_uncertainty_m, evidence, rays, reasons (ushort),
# heading_fits, front_crossings, back_crossings, back_depth (double), view_sides, steiner
FACE_BYTES = 1 + 3 * 4 + 4 + 1 + 1 + 1 + 7 * 4 + 4 + 1 + 4 + 2 + 4 + 4 + 4 + 8 + 1 + 1
VERTEX_BYTES = 3 * 8 + 1 + 4  # x y z, steiner, cost


def run(*args):
    return subprocess.run([BIN, *args], capture_output=True, text=True, timeout=900)


def read_simple_yaml(path):
    """Top-level `key: value` lines of a flat YAML file (comments skipped)."""
    values = {}
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].rstrip()
            if not line or line.startswith(" "):
                continue
            key, _, value = line.partition(":")
            values[key.strip()] = value.strip()
    return values


def read_pgm(path):
    with open(path, "rb") as f:
        data = f.read()
    tokens, pos = [], 0
    while len(tokens) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos) + 1
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        tokens.append(data[pos:end].decode())
        pos = end
    pos += 1  # one whitespace after maxval
    assert tokens[0] == "P5", tokens
    width, height, maxval = int(tokens[1]), int(tokens[2]), int(tokens[3])
    pixels = data[pos:]
    return width, height, maxval, pixels


def read_ply_header(path):
    with open(path, "rb") as f:
        header = b""
        while not header.endswith(b"end_header\n"):
            line = f.readline()
            if not line:
                raise AssertionError("no end_header")
            header += line
    lines = header.decode().splitlines()
    elements, current = [], None
    for line in lines:
        words = line.split()
        if words[0] == "element":
            current = {"name": words[1], "count": int(words[2]), "properties": []}
            elements.append(current)
        elif words[0] == "property":
            current["properties"].append(words[-1])
    return lines, elements, len(header)


def class_counts(summary_path):
    with open(summary_path) as f:
        text = f.read()
    match = re.search(r"faces: (\d+) \(free (\d+), lethal (\d+), unknown (\d+), uncertain (\d+)\)", text)
    levels = int(re.search(r"^levels: (\d+)$", text, re.M).group(1))
    return tuple(int(g) for g in match.groups()), levels


class TempDirCase(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="terramesh_traverse_")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def path(self, *names):
        return os.path.join(self.dir, *names)

    def generate(self, scene, *args):
        data = self.path(scene)
        result = run("generate", scene, "-o", data, "--quiet", "--seed", "1", *args)
        self.assertEqual(result.returncode, 0, result.stderr)
        return os.path.join(data, "stream.tmstream")

    def mesh_with_robot(self, stream, name):
        out = self.path(name)
        result = run("mesh", stream, "-o", out, "--robot", ROBOT, "--export-every", "5", "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        return out

    def assert_map_directory(self, out, levels):
        for name in ["traversability.ply", "robot.yaml", "map_frame.yaml", "traversability_summary.txt"]:
            self.assertTrue(os.path.isfile(os.path.join(out, name)), name)
        self.assertFalse([n for n in os.listdir(out) if n.startswith(".")], "temporary files left behind")
        lines, elements, header_size = read_ply_header(os.path.join(out, "traversability.ply"))
        self.assertIn("format binary_little_endian 1.0", lines)
        # The reasons bits are named in the header, lowest first (docs/traversability.md's table).
        self.assertIn("comment reasons bits, lowest first: too_steep no_heading_fits low_clearance guessed_wall "
                      "possible_step slope_may_exceed worst_case_relief possible_obstacle obstacle_extension "
                      "unconfirmed_point unknown_low_clearance closing_geometry few_rays seen_from_behind", lines)
        vertex, face = elements
        self.assertEqual(vertex["properties"], ["x", "y", "z", "steiner", "cost"])
        self.assertEqual(face["properties"], ["vertex_indices", "cost", "lethal", "unknown", "uncertain", "slope_deg",
                                              "step_m", "roughness_m", "contact", "contact_best", "clearance_m",
                                              "lethal_distance_m", "height_uncertainty_m", "evidence", "rays",
                                              "reasons", "heading_fits", "front_crossings", "back_crossings", "back_depth",
                                              "view_sides", "steiner"])
        self.assertEqual(os.path.getsize(os.path.join(out, "traversability.ply")),
                         header_size + vertex["count"] * VERTEX_BYTES + face["count"] * FACE_BYTES)
        for level in range(levels):
            for suffix, mode, image in [("", "trinary", ".pgm"), ("_cost", "scale", ".png")]:
                meta = read_simple_yaml(os.path.join(out, f"level_{level}{suffix}.yaml"))
                self.assertEqual(meta["image"], f"level_{level}{suffix}{image}")
                self.assertEqual(meta["mode"], mode)
                self.assertEqual(meta["negate"], "0")
                self.assertEqual(float(meta["occupied_thresh"]), 0.65)
                self.assertEqual(float(meta["free_thresh"]), 0.196)
                self.assertEqual(float(meta["resolution"]), 0.1)
                self.assertEqual(len(json.loads(meta["origin"])), 3)
                self.assertTrue(os.path.isfile(os.path.join(out, meta["image"])))
            width, height, maxval, pixels = read_pgm(os.path.join(out, f"level_{level}.pgm"))
            self.assertEqual(maxval, 255)
            self.assertEqual(len(pixels), width * height)
            self.assertLessEqual(set(pixels), {0, 205, 254})
            self.assertGreater(pixels.count(254), 500, "a level has free cells (5 m^2 at 0.1 m)")
            self.assertTrue(os.path.isfile(os.path.join(out, f"layers_level_{level}.tif")))
        self.assertFalse(os.path.exists(os.path.join(out, f"level_{levels}.pgm")))
        if shutil.which("gdalinfo"):
            info = json.loads(subprocess.run(["gdalinfo", "-json", os.path.join(out, "layers_level_0.tif")],
                                             capture_output=True, text=True, check=True).stdout)
            self.assertEqual([b["description"] for b in info["bands"]],
                             ["cost", "class", "slope_deg", "step_m", "roughness_m", "contact", "contact_best",
                              "clearance_m", "lethal_distance_m", "height_uncertainty_m", "evidence", "rays",
                              "reasons", "heading_fits", "height_m"])
            self.assertTrue(all(b["type"] == "Float32" and str(b["noDataValue"]).lower() == "nan" for b in info["bands"]))


class StreetTest(TempDirCase):
    def test_online_map_and_traverse_on_the_mesh_agree(self):
        stream = self.generate("street", "--length-m", "60")
        out = self.mesh_with_robot(stream, "online")
        counts, levels = class_counts(os.path.join(out, "traversability_summary.txt"))
        self.assertEqual(levels, 1, "a street is one level")
        self.assert_map_directory(out, levels)
        checked = subprocess.run(["python3", CHECKER, os.path.join(out, "mesh.ply"), "--json"], capture_output=True,
                                 text=True, timeout=300)
        self.assertEqual(checked.returncode, 0, checked.stdout + checked.stderr)
        with open(os.path.join(out, "summary.txt")) as f:
            self.assertIn("traversability: robot small_wheeled", f.read())
        with open(os.path.join(out, "traversability_updates.csv")) as f:
            rows = list(csv.DictReader(f))
        with open(os.path.join(out, "keyframes.csv")) as f:
            events = list(csv.DictReader(f))
        self.assertEqual(len(rows), len(events) + 1)  # one per event, then the final export
        self.assertEqual(rows[-1]["event"], "end")
        self.assertTrue(all(float(r["layer_update_s"]) >= 0 for r in rows))
        self.assertEqual(int(rows[-1]["faces_total"]), counts[0])
        exports = [r for r in rows if float(r["export_s"]) > 0]
        self.assertGreaterEqual(len(exports), int(rows[-1]["keyframes"]) // 5)

        # The same robot on the finished mesh, with the up vector the online run estimated.
        up = read_simple_yaml(os.path.join(out, "map_frame.yaml"))["up"]
        up = ",".join(repr(v) for v in json.loads(up))
        offline = self.path("offline")
        result = run("traverse", os.path.join(out, "mesh.ply"), "--robot", ROBOT, "-o", offline, "--up=" + up,
                     "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        offline_counts, offline_levels = class_counts(os.path.join(offline, "traversability_summary.txt"))
        self.assertEqual(offline_levels, levels)
        # Same faces; mesh.ply keeps every Steiner flag and every face's observation counts (rays,
        # rays through the space in front), so the evidence and the classes agree, except that the
        # online map also knows the SLAM points too few keyframes saw to mesh (possible obstacles):
        # only those turn free faces uncertain, never lethal or unknown.
        self.assertEqual(offline_counts[0], counts[0])
        self.assertEqual((offline_counts[2], offline_counts[3]), (counts[2], counts[3]),
                         "mesh.ply keeps the Steiner flags and the observation counts, so lethal and unknown agree")
        made_uncertain = offline_counts[1] - counts[1]
        self.assertGreaterEqual(made_uncertain, 0)
        self.assertEqual(counts[4] - offline_counts[4], made_uncertain)
        unconfirmed = int(rows[-1]["unconfirmed_points"])
        if made_uncertain > 0:
            self.assertGreater(unconfirmed, 0)
        self.assertLess(made_uncertain, 0.02 * counts[0])
        self.assert_map_directory(offline, offline_levels)

        # traverse-eval --path checks paths on the truth: the road 1.65 m under the generator's
        # camera path is drivable; the same line 1 m up is not on the ground; a malformed file exits 2.
        data = os.path.dirname(stream)
        road, lifted = self.path("road.csv"), self.path("lifted.csv")
        with open(os.path.join(data, "trajectory.txt")) as f:
            poses = [[float(v) for v in line.split()] for line in f if line.strip()]
        for name, lift in [(road, 0.0), (lifted, 1.0)]:
            with open(name, "w") as f:
                f.write("x,y,z,yaw,face,cost\n")
                for pose in poses[2:-2]:
                    f.write(f"{pose[3]},{pose[7]},{pose[11] - 1.65 + lift},0,0,0\n")
        report = self.path("check.txt")
        result = run("traverse-eval", out, "--gt-mesh", os.path.join(data, "ground_truth.ply"), "--path", road, lifted,
                     "--report", report, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(report) as f:
            lines = [line.split(" ", 2) for line in f.read().splitlines()]
        valid = {words[1]: words[2] for words in lines if words[0] == "path_valid"}
        reasons = {words[1]: words[2] for words in lines if words[0] == "path_reason"}
        self.assertEqual(valid, {road: "1", lifted: "0"}, reasons)
        self.assertIn("1.000 m above the true", reasons[lifted])
        self.assertIn(["paths_valid", "1"], [w[:2] for w in lines])
        with open(road, "a") as f:
            f.write("1.0,2.0\n")
        result = run("traverse-eval", out, "--gt-mesh", os.path.join(data, "ground_truth.ply"), "--path", road,
                     "--quiet")
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("road.csv", result.stderr)
        self.assertIn(f"line {len(poses) - 4 + 2}", result.stderr)
        result = run("traverse-eval", out, "--road-under-path", stream, "--path", lifted, "--quiet")
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("--path needs --gt-mesh", result.stderr)

        # --lidar-ground: measured points under the path (here the truth's vertices) against the
        # map over them: the driven road is found, near the truth.
        truth = os.path.join(data, "ground_truth.ply")
        result = run("traverse-eval", out, "--road-under-path", stream, "--lateral-m", "0.34", "--lidar-ground", truth,
                     "--report", report, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(report) as f:
            values = dict(line.split(" ", 1) for line in f.read().splitlines())
        self.assertGreater(int(values["lidar_ground_points"]), 20)
        self.assertGreater(float(values["lidar_covered_path_m"]), 20.0)
        self.assertLess(float(values["lidar_free_height_median_m"]), 0.05)
        self.assertGreater(float(values["lidar_free_fraction"]), 0.5)
        result = run("traverse-eval", out, "--gt-mesh", truth, "--lidar-ground", truth, "--quiet")
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("--lidar-ground and --lidar-sim3 need --road-under-path", result.stderr)

        # --gt-mesh with --road-under-path: the truth judges the swept strip for the map's robot
        # (the small robot fits on the generator's road under the path); the free part where it
        # fits is part of the strip's free area.
        result = run("traverse-eval", out, "--gt-mesh", truth, "--road-under-path", stream, "--lateral-m", "0.34",
                     "--report", report, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(report) as f:
            values = dict(line.split(" ", 1) for line in f.read().splitlines())
        self.assertGreater(float(values["road_truth_fits_fraction"]), 0.95)
        self.assertLessEqual(float(values["road_truth_fits_free_m2"]), float(values["road_free_m2"]))
        self.assertGreater(float(values["road_free_where_truth_fits_fraction"]), 0.5)
        keyframe_path_m = float(values["path_length_m"])

        # The camera's true path frame by frame (frames.txt of generate, from the first keyframe's
        # frame to the last's) instead of the keyframes: the same road, along every 10 Hz frame.
        with open(os.path.join(data, "frames.txt")) as f:
            frames = f.read().splitlines()
        with open(os.path.join(data, "trajectory.txt")) as f:
            keyframes = f.read().splitlines()
        self.assertGreater(len(frames), len(keyframes))
        self.assertEqual((frames[0], frames[-1]), (keyframes[0], keyframes[-1]))
        result = run("traverse-eval", out, "--road-under-path", os.path.join(data, "frames.txt"), "--lateral-m",
                     "0.34", "--report", report, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(report) as f:
            values = dict(line.split(" ", 1) for line in f.read().splitlines())
        self.assertEqual(int(values["path_keyframes"]), len(frames))
        self.assertAlmostEqual(float(values["path_length_m"]), keyframe_path_m, delta=0.02 * keyframe_path_m)
        self.assertGreater(float(values["road_underfoot_free_fraction"]), 0.5)
        # The same poses as a TUM trajectory (time, position, quaternion x y z w): the same path.
        tum = self.path("frames_tum.txt")
        with open(tum, "w") as f:
            for i, line in enumerate(frames):
                m = [float(v) for v in line.split()]
                f.write(" ".join(repr(v) for v in [0.1 * i, m[3], m[7], m[11]] + quaternion_xyzw(m)) + "\n")
        result = run("traverse-eval", out, "--road-under-path", tum, "--lateral-m", "0.34", "--report", report,
                     "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(report) as f:
            tum_values = dict(line.split(" ", 1) for line in f.read().splitlines())
        self.assertEqual(tum_values["path_length_m"], values["path_length_m"])
        self.assertEqual(tum_values["path_up"], values["path_up"])
        bad = self.path("bad_frames.txt")
        with open(bad, "w") as f:
            f.write("\n".join(frames[:3] + ["1 0 0 0 0 1 0"]) + "\n")
        result = run("traverse-eval", out, "--road-under-path", bad, "--quiet")
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("bad_frames.txt", result.stderr)
        self.assertIn("line 4", result.stderr)


def quaternion_xyzw(m):
    """The rotation of a KITTI pose line's 3x4 matrix `m` (12 numbers by rows) as x, y, z, w."""
    r = [[m[0], m[1], m[2]], [m[4], m[5], m[6]], [m[8], m[9], m[10]]]
    w = math.sqrt(max(0.0, 1.0 + r[0][0] + r[1][1] + r[2][2])) / 2
    x = math.copysign(math.sqrt(max(0.0, 1.0 + r[0][0] - r[1][1] - r[2][2])) / 2, r[2][1] - r[1][2])
    y = math.copysign(math.sqrt(max(0.0, 1.0 - r[0][0] + r[1][1] - r[2][2])) / 2, r[0][2] - r[2][0])
    z = math.copysign(math.sqrt(max(0.0, 1.0 - r[0][0] - r[1][1] + r[2][2])) / 2, r[1][0] - r[0][1])
    return [x, y, z, w]


class GarageTest(TempDirCase):
    def test_two_floors_give_two_levels(self):
        # The default 48 m garage: on a 40 m one (seed 1) the sensor's height above the points
        # beneath varies by 0.17 m, and the run calls the path not driven.
        stream = self.generate("garage")
        out = self.mesh_with_robot(stream, "garage")
        _, levels = class_counts(os.path.join(out, "traversability_summary.txt"))
        self.assertEqual(levels, 2)
        self.assert_map_directory(out, levels)
        heights = [float(m) for m in re.findall(r"^level \d+: mean height ([-\d.e]+) m",
                                                 open(os.path.join(out, "traversability_summary.txt")).read(), re.M)]
        self.assertGreater(heights[1] - heights[0], 1.5, "the levels are a storey apart")
        # The ground floor's sensor lies beneath the deck's drive: the run says how many drives got
        # undersides (docs/traversability.md, "The underside of driven ground").
        with open(os.path.join(out, "summary.txt")) as f:
            summary = f.read()
        undersided = re.search(r"(\d+) keyframe\(s\) with a level beneath their drive", summary)
        self.assertIsNotNone(undersided, summary)
        self.assertGreater(int(undersided.group(1)), 0)


class BadInputTest(TempDirCase):
    def assert_rejected(self, args, output, *fragments):
        result = run(*args)
        self.assertEqual(result.returncode, 2, result.stderr)
        lines = result.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, result.stderr)
        for fragment in fragments:
            self.assertIn(fragment, lines[0])
        self.assertFalse(os.path.exists(output), "no output may be written for bad input")

    def setUp(self):
        super().setUp()
        self.stream = self.generate("street", "--length-m", "30")
        self.mesh = self.path("mesh.ply")
        # A tiny valid mesh for traverse.
        with open(self.mesh, "w") as f:
            f.write("ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
                    "property double z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n"
                    "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")

    def bad_robot(self, text):
        path = self.path("bad_robot.yaml")
        with open(path, "w") as f:
            f.write(text)
        return path

    def test_bad_robot_yaml_exits_2_naming_file_and_key(self):
        robot = self.bad_robot("name: r\nmax_slope_deg: steep\n")
        out = self.path("out")
        self.assert_rejected(["mesh", self.stream, "-o", out, "--robot", robot], out, "bad_robot.yaml",
                             "max_slope_deg")
        self.assert_rejected(["traverse", self.mesh, "-o", out, "--robot", robot], out, "bad_robot.yaml",
                             "max_slope_deg")
        robot = self.bad_robot("name: r\nwheel_count: 4\n")
        self.assert_rejected(["traverse", self.mesh, "-o", out, "--robot", robot], out, "wheel_count")
        self.assert_rejected(["traverse", self.mesh, "-o", out, "--robot", self.path("missing.yaml")], out,
                             "missing.yaml")

    def test_bad_options_exit_2(self):
        out = self.path("out")
        self.assert_rejected(["traverse", self.mesh, "-o", out, "--robot", ROBOT, "--up", "0,0"], out, "--up")
        self.assert_rejected(["traverse", self.mesh, "-o", out, "--robot", ROBOT, "--grid-resolution-m", "0"], out,
                             "--grid-resolution-m")
        self.assert_rejected(["traverse", self.mesh, "-o", out], out, "--robot")
        self.assert_rejected(["mesh", self.stream, "-o", out, "--export-every", "5"], out, "--robot")
        self.assert_rejected(["mesh", self.stream, "-o", out, "--robot", ROBOT, "--export-every", "-1"], out,
                             "--export-every")


if __name__ == "__main__":
    unittest.main()
