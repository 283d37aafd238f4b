"""Tests of the figure scripts in scripts/figures/ on fixtures written here (and on a tiny real
`terramesh bench` run when TERRAMESH_BIN is set).

Run by ctest with the Python that has matplotlib: python3 -m unittest figures_test
(TERRAMESH_SOURCE_DIR, and optionally TERRAMESH_BIN and TERRAMESH_SHARED_DIR, set).
"""

import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import unittest

import numpy as np

SOURCE = os.environ.get("TERRAMESH_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
SCRIPTS = os.path.join(SOURCE, "scripts", "figures")
sys.path.insert(0, SCRIPTS)
import common  # noqa: E402
import ply  # noqa: E402

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def png_size(path):
    """(width, height) from the IHDR chunk; fails the caller's assertion if not a PNG."""
    with open(path, "rb") as handle:
        head = handle.read(24)
    if head[:8] != PNG_SIGNATURE or head[12:16] != b"IHDR":
        return None
    return struct.unpack(">II", head[16:24])


def pixels(path):
    """The PNG's pixels as an (H, W, 3) float array in [0, 1] (matplotlib reads PNGs itself)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.image
    return matplotlib.image.imread(path)[:, :, :3]


def share_of_colour(image, rgb, tolerance=0.03):
    """Fraction of the pixels within `tolerance` of `rgb` in every channel."""
    return float(np.mean(np.all(np.abs(image - np.array(rgb)) <= tolerance, axis=2)))


class ScriptCase(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="terramesh_figures_")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def path(self, *parts):
        return os.path.join(self.dir, *parts)

    def write(self, name, text):
        path = self.path(name)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w", encoding="utf-8") as handle:
            handle.write(text)
        return path

    def run_script(self, script, *args):
        return subprocess.run([sys.executable, os.path.join(SCRIPTS, script), *args],
                              capture_output=True, text=True, timeout=300)

    def assert_ok(self, result):
        self.assertEqual(result.returncode, 0, result.stderr)

    def assert_rejected(self, result, *fragments):
        self.assertEqual(result.returncode, 2, result.stdout + result.stderr)
        for fragment in fragments:
            self.assertIn(fragment, result.stderr)
        self.assertNotIn("Traceback", result.stderr)

    def assert_png(self, path, width, height):
        """A valid PNG of the given size, not blank, and no temporary file left beside it."""
        self.assertTrue(os.path.isfile(path), path)
        self.assertEqual(png_size(path), (width, height), path)
        image = pixels(path)
        self.assertEqual(image.shape[:2], (height, width))
        self.assertGreater(float(np.var(image)), 1e-3, f"{path} looks blank")
        leftovers = [name for name in os.listdir(os.path.dirname(path)) if name.startswith(".tmp-")]
        self.assertEqual(leftovers, [])
        self.assertEqual(os.stat(path).st_mode & 0o777, 0o644, path)
        return image


def keyframes_csv(rows, scale):
    """A keyframes.csv like bench writes: kind column, step times; one removal row in between."""
    header = "event,kind,id,time_steiner_s,time_shrink_s,time_insertion_s,time_ray_tracing_s,time_grow_s,time_total_s"
    lines = [header]
    for i in range(rows):
        steps = [scale * (1 + k) * 1e-3 * (1 + 0.1 * i) for k in range(5)]
        lines.append(",".join([str(i), "keyframe", str(i)] + [f"{t:.6e}" for t in steps + [sum(steps)]]))
        if i == rows // 2:
            lines.append(f"{i},removal,7,0,0,0,0,0,1e-6")
    return "\n".join(lines) + "\n"


class BenchFiguresTest(ScriptCase):
    def make_bench_dir(self, with_index=True):
        for mode, scale in (("proposed", 1.0), ("romanoni15", 10.0)):
            self.write(os.path.join("bench", mode, "keyframes.csv"), keyframes_csv(30, scale))
        if with_index:
            self.write(os.path.join("bench", "runs.csv"),
                       "mode,stream,keyframes_csv,summary\n"
                       "romanoni15,\"data/a,b.tmstream\",romanoni15/keyframes.csv,romanoni15/summary.txt\n"
                       "proposed,\"data/a,b.tmstream\",proposed/keyframes.csv,proposed/summary.txt\n")
        return self.path("bench")

    def test_figures_of_every_mode(self):
        bench = self.make_bench_dir()
        result = self.run_script("bench_figures.py", bench)
        self.assert_ok(result)
        plots = os.path.join(bench, "plots")
        for name in ("time_per_keyframe.png", "steps_proposed.png", "steps_romanoni15.png"):
            self.assert_png(os.path.join(plots, name), 1200, 700)
        self.assertEqual(sorted(result.stdout.split()), sorted(os.path.join(plots, name) for name in os.listdir(plots)))

    def test_without_index_and_a_chosen_mode_and_folder(self):
        bench = self.make_bench_dir(with_index=False)
        out = self.path("figs")
        self.assert_ok(self.run_script("bench_figures.py", bench, "--modes", "romanoni15", "-o", out))
        self.assertEqual(sorted(os.listdir(out)), ["steps_romanoni15.png", "time_per_keyframe.png"])
        self.assert_png(os.path.join(out, "steps_romanoni15.png"), 1200, 700)

    def test_bad_input_exits_2(self):
        self.assert_rejected(self.run_script("bench_figures.py", self.path("nowhere")), "no such folder")
        bench = self.make_bench_dir()
        self.assert_rejected(self.run_script("bench_figures.py", bench, "--modes", "litvinov13"), "litvinov13")
        self.write(os.path.join("bench", "proposed", "keyframes.csv"),
                   "event,kind,time_total_s\n0,keyframe,0.1\n")
        self.assert_rejected(self.run_script("bench_figures.py", bench), "keyframes.csv", "line 1",
                             "time_steiner_s")
        self.write(os.path.join("bench", "proposed", "keyframes.csv"),
                   keyframes_csv(3, 1.0).replace("keyframe,1,", "keyframe,1,abc", 1))
        self.assert_rejected(self.run_script("bench_figures.py", bench), "line 3", "expected a number")
        os.remove(self.path("bench", "romanoni15", "keyframes.csv"))
        self.assert_rejected(self.run_script("bench_figures.py", bench), "romanoni15", "no such file")

    def test_every_script_has_help(self):
        for script in ("bench_figures.py", "traversability_figures.py", "planner_figures.py"):
            result = self.run_script(script, "--help")
            self.assert_ok(result)
            self.assertIn("--output-dir", result.stdout)
            self.assertIn("Exit codes", result.stdout)


@unittest.skipUnless(os.environ.get("TERRAMESH_BIN"), "TERRAMESH_BIN not set")
class BenchRealRunTest(ScriptCase):
    """A real `terramesh bench` (4 keyframes of the KITTI 00 ORB-SLAM export, two modes)."""

    def test_bench_output_gives_the_figures(self):
        stream = os.path.join(os.environ["TERRAMESH_SHARED_DIR"], "data", "kitti00_orbslam",
                              "slam_data_version0.1_KITTI00_50frames.json")
        out = self.path("bench")
        result = subprocess.run([os.environ["TERRAMESH_BIN"], "bench", stream, "-o", out, "--modes",
                                 "proposed,romanoni15", "--max-keyframes", "4", "--metres-per-unit", "16.589"],
                                capture_output=True, text=True, timeout=600)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("scripts/figures/bench_figures.py " + out, result.stdout)
        self.assertFalse(os.path.exists(os.path.join(out, "plots")))
        rows = common.read_csv(os.path.join(out, "runs.csv"), ["mode", "stream", "keyframes_csv", "summary"])
        self.assertEqual([row["mode"] for row in rows], ["proposed", "romanoni15"])
        self.assertEqual(rows[0]["stream"], stream)
        self.assert_ok(self.run_script("bench_figures.py", out))
        for name in ("time_per_keyframe.png", "steps_proposed.png", "steps_romanoni15.png"):
            self.assert_png(os.path.join(out, "plots", name), 1200, 700)


def terrain_fixture(up_axis):
    """A 12 x 8 m grid (1 m cells, two triangles each) in the plane perpendicular to `up_axis`
    (2: z up; 1: -y up, as in KITTI's camera frame), with a bridge deck 3 m above its middle.
    Returns (vertices, faces, layers): cost rises with x; the cells with x < 2 are unknown; the
    cells with x >= 10 are lethal, slope 40 degrees; the deck is flat and known."""
    def to_world(u, v, h):
        return (u, v, h) if up_axis == 2 else (u, -h, v)

    vertices, faces, layers = [], [], {name: [] for name in
                                        ("cost", "slope_deg", "step_m", "roughness_m", "contact", "clearance_m",
                                         "lethal", "unknown", "reasons")}

    def grid(nu, nv, height, u0, v0, deck):
        base = len(vertices)
        for j in range(nv + 1):
            for i in range(nu + 1):
                vertices.append(to_world(u0 + i, v0 + j, height))
        for j in range(nv):
            for i in range(nu):
                a = base + j * (nu + 1) + i
                for tri in ((a, a + 1, a + nu + 2), (a, a + nu + 2, a + nu + 1)):
                    faces.append(tri)
                    x = u0 + i + 0.5
                    unknown = not deck and x < 2
                    lethal = not deck and x >= 10
                    layers["unknown"].append(1 if unknown else 0)
                    layers["lethal"].append(1 if lethal else 0)
                    # Why not free: too steep (bit 0) where lethal, closing geometry (bit 11) where unknown.
                    layers["reasons"].append(1 if lethal else (1 << 11) if unknown else 0)
                    layers["cost"].append(math.nan if unknown else (1.0 if lethal else x / 12.0))
                    layers["slope_deg"].append(40.0 if lethal else 2.0 + 1.5 * (i % 5))
                    layers["step_m"].append(0.02 * (i % 4))
                    layers["roughness_m"].append(0.01 * (j % 3))
                    layers["contact"].append(0.5 if lethal else 0.7 + 0.05 * (j % 5))
                    layers["clearance_m"].append(math.inf if deck else 3.0)

    grid(12, 8, 0.0, 0.0, 0.0, False)
    grid(4, 2, 3.0, 4.0, 3.0, True)
    return np.array(vertices, dtype=float), np.array(faces, dtype=np.uint32), layers


def write_map(folder, up_axis=2, metres_per_unit=1.0):
    vertices, faces, layers = terrain_fixture(up_axis)
    vertices = vertices / metres_per_unit
    os.makedirs(folder, exist_ok=True)
    face_props = [("vertex_indices", "list uchar uint", faces)]
    for name in ("cost", "slope_deg", "step_m", "roughness_m", "contact", "clearance_m"):
        face_props.append((name, "float", np.array(layers[name], dtype=np.float32)))
    face_props += [("lethal", "uchar", np.array(layers["lethal"], dtype=np.uint8)),
                   ("unknown", "uchar", np.array(layers["unknown"], dtype=np.uint8)),
                   ("reasons", "ushort", np.array(layers["reasons"], dtype=np.uint16))]
    # The bits' names as terramesh writes them (traversability/layer_registry.h, reason::names()).
    bits = ("too_steep no_heading_fits low_clearance guessed_wall possible_step slope_may_exceed worst_case_relief "
            "possible_obstacle obstacle_extension unconfirmed_point unknown_low_clearance closing_geometry few_rays")
    ply.write_binary(os.path.join(folder, "traversability.ply"),
                     [("vertex", [(axis, "double", vertices[:, k]) for k, axis in enumerate("xyz")]),
                      ("face", face_props)], comments=["reasons bits, lowest first: " + bits])
    up = "[0, 0, 1]" if up_axis == 2 else "[0, -1, 0]"
    with open(os.path.join(folder, "map_frame.yaml"), "w", encoding="utf-8") as handle:
        handle.write(f"# test map frame\nup: {up}\nmetres_per_unit: {metres_per_unit}\n")
    return vertices, faces, layers


class PlyReaderTest(ScriptCase):
    def test_binary_round_trip_of_the_fixture(self):
        vertices, faces, layers = write_map(self.path("map"))
        elements = ply.read(self.path("map", "traversability.ply"))
        self.assertEqual(list(elements), ["vertex", "face"])
        np.testing.assert_array_equal(np.column_stack([elements["vertex"][a] for a in "xyz"]), vertices)
        np.testing.assert_array_equal(elements["face"]["vertex_indices"], faces)
        np.testing.assert_array_equal(elements["face"]["cost"], np.array(layers["cost"], dtype=np.float32))
        np.testing.assert_array_equal(elements["face"]["unknown"], layers["unknown"])
        self.assertEqual(elements["face"]["lethal"].dtype, np.uint8)
        self.assertEqual(os.stat(self.path("map", "traversability.ply")).st_mode & 0o777, 0o644)

    def test_ascii_big_endian_and_polygons_of_mixed_sizes(self):
        self.write("a.ply", "ply\nformat ascii 1.0\ncomment hi\nelement vertex 4\nproperty float x\n"
                            "property float y\nproperty float z\nelement face 2\n"
                            "property list uchar int vertex_indices\nproperty uint8 flag\nend_header\n"
                            "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3 7\n3 0 1 2 9\n")
        elements = ply.read(self.path("a.ply"))
        np.testing.assert_array_equal(elements["vertex"]["x"], [0, 1, 1, 0])
        self.assertEqual([list(f) for f in elements["face"]["vertex_indices"]], [[0, 1, 2, 3], [0, 1, 2]])
        np.testing.assert_array_equal(elements["face"]["flag"], [7, 9])
        header = (b"ply\nformat binary_big_endian 1.0\nelement face 2\n"
                  b"property list uchar int vertex_indices\nproperty short s\nend_header\n")
        body = (struct.pack(">B4ih", 4, 0, 1, 2, 3, -5) + struct.pack(">B3ih", 3, 4, 5, 6, 300))
        with open(self.path("b.ply"), "wb") as handle:
            handle.write(header + body)
        face = ply.read(self.path("b.ply"))["face"]
        self.assertEqual([list(f) for f in face["vertex_indices"]], [[0, 1, 2, 3], [4, 5, 6]])
        np.testing.assert_array_equal(face["s"], [-5, 300])

    def test_errors_name_the_file_and_place(self):
        cases = [("ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nend_header\n"
                  .encode() + struct.pack("<f", 1.0), "vertex 1", "truncated"),
                 (b"plx\n", "line 1", "ply"),
                 (b"ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty half x\nend_header\n",
                  "line 4", "PLY type"),
                 (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\nabc\n",
                  "vertex 0", "expected a number"),
                 (b"ply\nformat ascii 1.0\nelement vertex 1\n", "line 4", "end_header")]
        for data, *fragments in cases:
            with open(self.path("bad.ply"), "wb") as handle:
                handle.write(data)
            with self.assertRaises(common.InputError) as raised:
                ply.read(self.path("bad.ply"))
            for fragment in fragments:
                self.assertIn(fragment, str(raised.exception))
            self.assertIn("bad.ply", str(raised.exception))


class TraversabilityFiguresTest(ScriptCase):
    def write_path(self, name, points):
        return self.write(name, "x,y,z,yaw,face,cost\n" + "".join(f"{x},{y},{z},0,1,0.5\n" for x, y, z in points))

    def write_trajectory(self, name, positions):
        return self.write(name, "".join(f"1 0 0 {x} 0 1 0 {y} 0 0 1 {z}\n" for x, y, z in positions))

    def test_top_view_shows_cost_unknown_lethal_and_paths(self):
        write_map(self.path("map"))
        self.write_path(os.path.join("map", "path.csv"), [(2.5, 1.0, 0.0), (6.0, 4.0, 0.0), (9.5, 7.0, 0.0)])
        trajectory = self.write_trajectory("trajectory.txt", [(0.5 * i, 4.0, 1.5) for i in range(24)])
        result = self.run_script("traversability_figures.py", self.path("map"), "--trajectory", trajectory)
        self.assert_ok(result)
        top = self.assert_png(self.path("map", "plots", "traversability_top.png"), 1200, 1000)
        # One sixth of the ground is lethal (red), one sixth unknown (grey), in plan area.
        red = share_of_colour(top, (0.85, 0.0, 0.0))
        grey = share_of_colour(top, (0.62, 0.62, 0.62))
        self.assertGreater(red, 0.02)
        self.assertGreater(grey, 0.02)
        self.assertGreater(share_of_colour(top, (0.0, 1.0, 1.0), 0.05), 0.0005)  # the cyan path
        # Why not free: the lethal sixth is too steep (dark red), the known rest free (light green).
        reasons = self.assert_png(self.path("map", "plots", "traversability_reasons.png"), 1200, 1000)
        self.assertGreater(share_of_colour(reasons, (0.55, 0.0, 0.0)), 0.02)
        self.assertGreater(share_of_colour(reasons, (0.55, 0.8, 0.55)), 0.1)
        self.assertEqual(share_of_colour(reasons, (0.85, 0.0, 0.0)), 0.0, "no class red in the reasons view")
        self.assert_png(self.path("map", "plots", "traversability_histograms.png"), 1200, 700)
        # The 40 m detail view is no closer than the whole 10 m map: not drawn.
        self.assertFalse(os.path.exists(self.path("map", "plots", "traversability_top_detail.png")))

    def test_detail_view_zooms_on_the_paths_middle(self):
        write_map(self.path("map"))
        self.write_path(os.path.join("map", "path.csv"), [(2.5, 1.0, 0.0), (6.0, 4.0, 0.0), (9.5, 7.0, 0.0)])
        result = self.run_script("traversability_figures.py", self.path("map"), "--detail-m", "3", "-o", self.path("f"))
        self.assert_ok(result)
        top = self.assert_png(self.path("f", "traversability_top.png"), 1200, 1000)
        detail = self.assert_png(self.path("f", "traversability_top_detail.png"), 1200, 1000)
        self.assertIn(self.path("f", "traversability_top_detail.png"), result.stdout)
        # A 3 m window around the path's middle, (6, 4): x from 4.5 to 7.5, away from the lethal
        # (x >= 10, red) and unknown (x < 2, grey) cells the whole view shows (only the legend's
        # patches keep those colours); the path crosses it.
        red, grey = (0.85, 0.0, 0.0), (0.62, 0.62, 0.62)
        self.assertGreater(share_of_colour(top, red), 0.02)
        self.assertLess(share_of_colour(detail, red), 0.001)
        self.assertLess(share_of_colour(detail, grey), 0.001)
        self.assertGreater(share_of_colour(detail, (0.0, 1.0, 1.0), 0.05), 0.0005)
        result = self.run_script("traversability_figures.py", self.path("map"), "--detail-m", "0", "-o", self.path("g"))
        self.assert_ok(result)
        self.assertFalse(os.path.exists(self.path("g", "traversability_top_detail.png")))

    def test_kitti_up_axis_scale_and_several_paths(self):
        write_map(self.path("map"), up_axis=1, metres_per_unit=16.589)
        a = self.write_path("a.csv", [(x / 16.589, 0.0, 4.0 / 16.589) for x in (2.5, 6.0, 9.0)])
        b = self.write_path("b.csv", [(x, 5.0, 0.0) for x in (3.0, 8.0)])
        out = self.path("figs")
        self.assert_ok(self.run_script("traversability_figures.py", self.path("map"), "--path", "mesh=" + a, "-o", out))
        top_a = self.assert_png(os.path.join(out, "traversability_top.png"), 1200, 1000)
        self.assertGreater(share_of_colour(top_a, (0.85, 0.0, 0.0)), 0.02)
        self.assert_ok(self.run_script("traversability_figures.py", self.path("map"), "--path", a, "--path",
                                       "planned=" + b, "--path-frame", "plan", "-o", out))
        self.assert_png(os.path.join(out, "traversability_top.png"), 1200, 1000)

    def test_bad_input_exits_2(self):
        run = lambda *args: self.run_script("traversability_figures.py", self.path("map"), *args)  # noqa: E731
        self.assert_rejected(run(), "map_frame.yaml", "no such file")
        write_map(self.path("map"))
        self.write(os.path.join("map", "map_frame.yaml"), "up: [0, 0]\nmetres_per_unit: 1\n")
        self.assert_rejected(run(), "map_frame.yaml", "key up")
        self.write(os.path.join("map", "map_frame.yaml"), "up: [0, 0, 1]\nmetres_per_unit: [\n")
        self.assert_rejected(run(), "map_frame.yaml", "malformed YAML")
        self.write(os.path.join("map", "map_frame.yaml"), "up: [0, 0, 1]\nmetres_per_unit: -2\n")
        self.assert_rejected(run(), "metres_per_unit", "positive")
        self.write(os.path.join("map", "map_frame.yaml"), "up: [0, 0, 1]\nmetres_per_unit: 1\n")
        ply_path = self.path("map", "traversability.ply")
        with open(ply_path, "rb") as handle:
            data = handle.read()
        with open(ply_path, "wb") as handle:
            handle.write(data[:-10])
        self.assert_rejected(run(), "traversability.ply", "face", "truncated")
        write_map(self.path("map"))
        bad_path = self.write("bad.csv", "x,y\n1,2\n")
        self.assert_rejected(run("--path", bad_path), "bad.csv", "missing column(s) z")
        bad_trajectory = self.write("t.txt", "1 0 0 1 0 1 0 2 0 0 1\n")
        self.assert_rejected(run("--trajectory", bad_trajectory), "t.txt", "line 1", "12 numbers")


class PlannerFiguresTest(ScriptCase):
    CSV = ("planner,query,success,cost,time_s,path_length_m\n"
           "rrtstar,q1,1,10.5,0.8,12.0\nrrtstar,q2,1,20.0,1.1,22.0\nrrtstar,q3,0,,5.0,\n"
           "graph,q1,1,9.5,0.01,11.0\ngraph,q2,1,19.0,0.02,21.0\ngraph,q3,1,30.0,0.015,31.0\n"
           "prm,q1,true,11.0,0.5,13.0\nprm,q2,false,nan,5.0,\nprm,q3,1,33.0,0.6,35.0\n")

    def test_comparison_figure(self):
        csv_path = self.write(os.path.join("plan", "planners.csv"), self.CSV)
        self.assert_ok(self.run_script("planner_figures.py", csv_path))
        self.assert_png(self.path("plan", "plots", "planner_comparison.png"), 1200, 500)
        # Without the optional column and with no query solved by all: still a figure.
        csv_path = self.write("p2.csv", "planner,query,success,cost,time_s\na,q1,1,1.0,0.1\nb,q1,0,,0.2\n")
        self.assert_ok(self.run_script("planner_figures.py", csv_path, "-o", self.path("o")))
        self.assert_png(self.path("o", "planner_comparison.png"), 1200, 500)

    def test_reads_the_pairs_csv_of_plan_and_planner_demo(self):
        import planner_figures
        plan_csv = self.write("plan_pairs.csv",
                              "pair,start_x,start_y,start_z,goal_x,goal_y,goal_z,status,length_m,cost,time_s,graph_cost,graph_time_s\n"
                              "0,0,0,0,1,1,0,solved,12.5,3.0,0.4,2.5,0.01\n"
                              "1,0,0,0,2,2,0,timeout,nan,nan,1.0,inf,0.02\n")
        runs, has_length = planner_figures.read_runs(plan_csv)
        self.assertEqual([run[:3] for run in runs], [("BIT* (OMPL)", "0", True), ("graph A*", "0", True),
                                                     ("BIT* (OMPL)", "1", False), ("graph A*", "1", False)])
        self.assertEqual([run[3] for run in runs[:2]], [3.0, 2.5])
        self.assertEqual([run[4] for run in runs], [0.4, 0.01, 1.0, 0.02])
        self.assertFalse(has_length)  # graph A* reports no length
        self.assert_ok(self.run_script("planner_figures.py", plan_csv, "-o", self.path("plan_plots")))
        self.assert_png(self.path("plan_plots", "planner_comparison.png"), 1200, 500)
        demo_csv = self.write("demo_pairs.csv", "pair,map,status,length_m,cost,time_s,truth_valid\n"
                              "0,mesh,solved,10,4,0.5,1\n0,octomap,solved,11,5,0.1,1\n1,mesh,failed,nan,nan,0.7,0\n")
        runs, has_length = planner_figures.read_runs(demo_csv)
        self.assertEqual([(run[0], run[2], run[5] if run[2] else None) for run in runs],
                         [("mesh", True, 10.0), ("octomap", True, 11.0), ("mesh", False, None)])
        self.assertTrue(has_length)
        self.assert_rejected(self.run_script("planner_figures.py", self.write(
            "bad_pairs.csv", "pair,map,status,length_m,cost,time_s\n0,mesh,solved,1,nan,0.1\n")),
            "bad_pairs.csv", "line 2", "cost")

    def test_bad_input_exits_2(self):
        run = lambda path: self.run_script("planner_figures.py", path)  # noqa: E731
        self.assert_rejected(run(self.path("missing.csv")), "missing.csv", "no such file")
        self.assert_rejected(run(self.write("a.csv", "planner,query,success,cost\n")), "a.csv", "time_s")
        self.assert_rejected(run(self.write("b.csv", "planner,query,success,cost,time_s\nx,q,maybe,1,1\n")),
                             "b.csv", "line 2", "success")
        self.assert_rejected(run(self.write("c.csv", "planner,query,success,cost,time_s\nx,q,1,,1\n")),
                             "c.csv", "line 2", "cost")
        self.assert_rejected(run(self.write("d.csv", "planner,query,success,cost,time_s\n")), "d.csv", "no run")
        self.assert_rejected(run(self.write("e.csv", "planner,query,success,cost,time_s\nx,q,1,1\n")),
                             "e.csv", "line 2", "expected 5 fields")


if __name__ == "__main__":
    unittest.main()
