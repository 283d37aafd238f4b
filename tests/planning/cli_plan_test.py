"""End-to-end: terramesh generate -> mesh -> traverse -> plan, and planner_demo against the truth."""
import csv
import math
import os
import subprocess
import tempfile
import unittest

BIN = os.environ.get("TERRAMESH_BIN", "terramesh")
DEMO = os.environ.get("PLANNER_DEMO_BIN", "planner_demo")
# Whether a path is found must not depend on the load of the machine running the tests: a planner
# without one after its budget keeps searching, up to this cap.
CAP = ("--time-cap-s", "60")


def run(*args):
    return subprocess.run([str(a) for a in args], capture_output=True, text=True, timeout=600)


def read_pairs(out):
    """The rows of OUT/pairs.csv that `terramesh plan --random-pairs` wrote."""
    with open(f"{out}/pairs.csv") as f:
        return list(csv.DictReader(f))


class PlanStreetTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        d = cls.tmp.name
        robot = os.path.join(os.path.dirname(__file__), "..", "..", "traversability", "robots", "small_wheeled.yaml")
        for args in (("generate", "street", "--length-m", "60", "-o", f"{d}/scene", "--quiet"),
                     ("mesh", f"{d}/scene/stream.tmstream", "-o", f"{d}/mesh", "--quiet"),
                     ("traverse", f"{d}/mesh/mesh.ply", "--robot", robot, "-o", f"{d}/map", "--no-geotiff", "--quiet")):
            result = run(BIN, *args)
            assert result.returncode == 0, result.stderr
        cls.dir = d

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_random_pairs_and_benchmark_database(self):
        out = f"{self.dir}/pairs"
        result = run(BIN, "plan", f"{self.dir}/map", "--random-pairs", "3", "--time-budget-s", "0.5", *CAP, "-o", out, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        rows = read_pairs(out)
        self.assertEqual(len(rows), 3)
        for row in rows:
            self.assertEqual(row["status"], "solved")
            # The graph optimum is no worse than the sampling planner's, up to discretisation.
            self.assertLessEqual(float(row["graph_cost"]), float(row["cost"]) * 1.02)
        db = f"{out}/bench.db"
        result = run("python3", "/usr/bin/ompl_benchmark_statistics", f"{out}/benchmark.log", "-d", db)
        self.assertEqual(result.returncode, 0, result.stderr)
        import sqlite3
        count = sqlite3.connect(db).execute("SELECT count(*) FROM runs").fetchone()[0]
        self.assertEqual(count, 6)  # 3 pairs x (planner + graph baseline)

    def test_random_pairs_with_the_graph_planner_plan_with_the_graph(self):
        out = f"{self.dir}/pairs_graph"
        result = run(BIN, "plan", f"{self.dir}/map", "--planner", "graph", "--random-pairs", "3", "-o", out, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(f"{out}/plan.txt") as f:
            self.assertIn("planner graph\n", f.read())
        rows = read_pairs(out)
        self.assertEqual(len(rows), 3)
        for row in rows:
            # The chosen planner is the graph A* itself: its cost is the graph optimum, exactly.
            self.assertEqual(row["status"], "solved")
            self.assertEqual(float(row["cost"]), float(row["graph_cost"]))
        db = f"{out}/bench.db"
        result = run("python3", "/usr/bin/ompl_benchmark_statistics", f"{out}/benchmark.log", "-d", db)
        self.assertEqual(result.returncode, 0, result.stderr)
        import sqlite3
        connection = sqlite3.connect(db)
        self.assertEqual(connection.execute("SELECT count(*) FROM runs").fetchone()[0], 3)
        names = [r[0] for r in connection.execute("SELECT name FROM plannerConfigs")]
        self.assertEqual(names, ["graph_astar"])

    def test_single_query_outputs(self):
        out = f"{self.dir}/pairs1"
        self.assertEqual(run(BIN, "plan", f"{self.dir}/map", "--random-pairs", "1", *CAP, "-o", out, "--quiet").returncode, 0)
        with open(f"{out}/pairs.csv") as f:
            row = next(csv.DictReader(f))
        start = [row["start_x"], row["start_y"], row["start_z"]]
        goal = [row["goal_x"], row["goal_y"], row["goal_z"]]
        single = f"{self.dir}/single"
        result = run(BIN, "plan", f"{self.dir}/map", "--start", *start, "--goal", *goal, "-o", single,
                     "--time-budget-s", "0.5", *CAP, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(f"{single}/path.csv") as f:
            lines = f.read().splitlines()
        self.assertEqual(lines[0], "x,y,z,yaw,face,cost")
        self.assertGreaterEqual(len(lines), 3)
        with open(f"{single}/path.ply") as f:
            ply = f.read()
        self.assertIn(f"element vertex {len(lines) - 1}", ply)
        self.assertIn(f"element edge {len(lines) - 2}", ply)
        with open(f"{single}/plan.txt") as f:
            self.assertIn("status solved", f.read())

    def test_legged_robot_keeps_its_own_heading(self):
        # legged.yaml's motion_model omni: the graph A*'s yaw is the body's own heading, a judged
        # one (k x 22.5 deg), not the direction of travel; traverse-eval checks the body at it, and
        # needs the yaw column to.
        robots = os.path.join(os.path.dirname(__file__), "..", "..", "traversability", "robots")
        legged = f"{self.dir}/map_legged"
        result = run(BIN, "traverse", f"{self.dir}/mesh/mesh.ply", "--robot", os.path.join(robots, "legged.yaml"),
                     "-o", legged, "--no-geotiff", "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        out = f"{self.dir}/legged_pairs"
        result = run(BIN, "plan", legged, "--planner", "graph", "--random-pairs", "1", "-o", out, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        row = read_pairs(out)[0]
        self.assertEqual(row["status"], "solved")
        single = f"{self.dir}/legged_single"
        result = run(BIN, "plan", legged, "--planner", "graph", "--start", row["start_x"], row["start_y"],
                     row["start_z"], "--goal", row["goal_x"], row["goal_y"], row["goal_z"], "-o", single, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(f"{single}/path.csv") as f:
            rows = list(csv.DictReader(f))
        self.assertGreaterEqual(len(rows), 2)
        for r in rows:
            steps = float(r["yaw"]) / (math.pi / 8)
            self.assertAlmostEqual(steps, round(steps), places=6, msg=f"yaw {r['yaw']} is no judged heading")
        report = f"{single}/check.txt"
        truth = f"{self.dir}/scene/ground_truth.ply"
        result = run(BIN, "traverse-eval", legged, "--gt-mesh", truth, "--path", f"{single}/path.csv",
                     "--report", report, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(report) as f:
            self.assertIn("paths_checked 1", f.read())
        without_yaw = f"{single}/no_yaw.csv"
        with open(without_yaw, "w") as f:
            f.write("x,y,z\n" + "".join(f"{r['x']},{r['y']},{r['z']}\n" for r in rows))
        result = run(BIN, "traverse-eval", legged, "--gt-mesh", truth, "--path", without_yaw, "--quiet")
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("no_yaw.csv", result.stderr)
        self.assertIn("x,y,z,yaw", result.stderr)
        self.assertIn("motion_model omni", result.stderr)

    def test_allow_unknown_option(self):
        out = f"{self.dir}/unknown"
        result = run(BIN, "plan", f"{self.dir}/map", "--random-pairs", "2", "--allow-unknown", "--time-budget-s", "0.3",
                     *CAP, "-o", out, "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        rows = read_pairs(out)
        self.assertEqual(len(rows), 2)
        for row in rows:
            self.assertEqual(row["status"], "solved")
            self.assertGreaterEqual(float(row["unknown_length_m"]), 0.0)
            self.assertLessEqual(float(row["unknown_length_m"]), float(row["length_m"]) + 1e-9)
        bad = run(BIN, "plan", f"{self.dir}/map", "--random-pairs", "1", "--allow-unknown", "--unknown-cost", "2",
                  "-o", f"{out}_bad")
        self.assertEqual(bad.returncode, 2, bad.stderr)

    def test_a_map_file_instead_of_its_directory_names_what_is_expected(self):
        # The map's traversability.ply given as MAP: exit 2, naming the file and the directory wanted
        # (a .json file is read as a tile index instead).
        ply = f"{self.dir}/map/traversability.ply"
        result = run(BIN, "plan", ply, "--start", "0", "0", "0", "--goal", "1", "0", "0", "-o", f"{self.dir}/file_map")
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn(ply, result.stderr)
        self.assertIn("expected the map's directory (traversability.ply, robot.yaml, map_frame.yaml)", result.stderr)

    def test_goal_in_unobserved_region_is_unreachable(self):
        result = run(BIN, "plan", f"{self.dir}/map", "--start", "0", "0", "0", "--goal", "30", "0", "40",
                     "-o", f"{self.dir}/unreachable")
        self.assertEqual(result.returncode, 3, result.stderr)
        self.assertEqual(len(result.stderr.strip().splitlines()), 1)
        self.assertIn("plan:", result.stderr)

    def test_demo_compares_with_octomap_on_ground_truth(self):
        out = f"{self.dir}/demo"
        result = run(DEMO, f"{self.dir}/scene", f"{self.dir}/map", out, "--pairs", "3", "--time-budget-s", "0.5", *CAP)
        self.assertEqual(result.returncode, 0, result.stderr)
        for name in ("octomap.bt", "mesh.log", "octomap.log", "comparison.md", "pairs.csv"):
            self.assertTrue(os.path.exists(f"{out}/{name}"), name)
        with open(f"{out}/pairs.csv") as f:
            rows = [r for r in csv.DictReader(f) if r["map"] == "mesh" and r["status"] == "solved"]
        self.assertEqual(len(rows), 3)


if __name__ == "__main__":
    unittest.main()
