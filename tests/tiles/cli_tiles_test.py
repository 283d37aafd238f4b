"""Tiles meshed apart and joined (docs/tiles.md): a short street cut into 4 tiles, meshed serially and
on a one-node Slurm cluster started here; the merged maps must be byte-identical. Borders and bad
input are checked too."""
import filecmp
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import unittest

SOURCE = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(SOURCE / "scripts" / "slurm"))
from local_cluster import SlurmCluster, missing_programs  # noqa: E402

BIN = os.environ["TERRAMESH_BIN"]
SHARED = os.environ["TERRAMESH_SHARED_DIR"]
ROBOT = str(SOURCE / "traversability" / "robots" / "small_wheeled.yaml")
SUBMIT = str(SOURCE / "scripts" / "slurm" / "submit_tiles.sh")
CHECKER = os.path.join(SHARED, "tools", "check_mesh.py")
# A street of 140 m (seed 1, no gross outliers) cut into 65 m tiles gives 4 tiles.
STREET = ["street", "--length-m", "140", "--seed", "1", "--outlier-fraction", "0"]
TILING = ["--tile-m", "65", "--overlap-m", "10"]
TILES = 4
# Measured on this street (docs/tiles.md, "Borders"): the target of 99 % is not reached; this floor
# catches tiles that do not line up (another frame, no overlap, a wrong input rule).
MIN_BORDER_AGREEMENT = 0.70
# Whether a cell is free (the drivable decision) agrees far better; measured 0.986 to 0.996 here.
MIN_FREE_AGREEMENT = 0.98


def run(*args, check=True):
    result = subprocess.run([BIN, *args], capture_output=True, text=True, timeout=600)
    if check and result.returncode != 0:
        raise AssertionError(f"terramesh {' '.join(args)} exited {result.returncode}:\n{result.stderr}")
    return result


def merged_files(plan_dir):
    """Every file of the merged map: the index, the overview and each tile's owned map and record."""
    index = json.loads((plan_dir / "tiles.json").read_text())
    files = ["tiles.json", *index["overview"]["files"]]
    for tile in index["tiles"]:
        files += tile["files"] + [tile["name"] + "/tile.json"]
    return sorted(files)


class TilesTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = pathlib.Path(tempfile.mkdtemp(prefix="terramesh-tiles-"))
        run("generate", *STREET, "-o", str(cls.tmp / "data"), "--quiet")
        cls.stream = str(cls.tmp / "data" / "stream.tmstream")
        cls.serial = cls.tmp / "serial"
        cls.plan = cls.serial / "plan.json"
        run("tiles", "plan", cls.stream, *TILING, "--robot", ROBOT, "-o", str(cls.plan), "--quiet")
        for i in range(TILES):
            run("mesh", cls.stream, "--tile", f"{cls.plan}:{i}", "--robot", ROBOT, "--quiet")
        cls.merge_output = run("tiles", "merge", str(cls.plan), "--check-borders").stdout

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_plan_has_four_tiles_with_disjoint_bounds(self):
        plan = json.loads(self.plan.read_text())
        self.assertEqual(len(plan["tiles"]), TILES)
        for tile in plan["tiles"]:
            bounds = tile["bounds_m"]
            self.assertAlmostEqual(bounds["max_x"] - bounds["min_x"], 65.0)
            self.assertGreater(tile["keyframes"], 0)
        cells = {(tile["column"], tile["row"]) for tile in plan["tiles"]}
        self.assertEqual(len(cells), TILES)

    def test_each_tile_surface_is_a_closed_manifold(self):
        for i in range(TILES):
            mesh = self.serial / f"tile_{i:03d}" / "mesh.ply"
            result = subprocess.run(["python3", CHECKER, str(mesh), "--json"], capture_output=True, text=True,
                                    timeout=300)
            self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
            self.assertEqual(json.loads(result.stdout)["boundary_edges"], 0)

    def test_index_lists_every_tile_and_owned_faces_add_up(self):
        index = json.loads((self.serial / "tiles.json").read_text())
        self.assertEqual([tile["index"] for tile in index["tiles"]], list(range(TILES)))
        owned = 0
        for tile in index["tiles"]:
            record = json.loads((self.serial / tile["name"] / "tile.json").read_text())
            self.assertEqual(record["revision"], tile["revision"])
            self.assertGreater(tile["revision"], 0)
            owned += tile["faces"]
            for name in tile["files"]:
                self.assertTrue((self.serial / name).is_file(), name)
            self.assertIn(tile["name"] + "/map/traversability.h5", tile["files"])
            for level in tile["levels"]:
                self.assertIn(level["nav2_map"], tile["files"])
        self.assertGreater(sum(len(tile["levels"]) for tile in index["tiles"]), 0)
        merged = int(re.search(r"merged: \d+ tile\(s\), (\d+) faces", self.merge_output).group(1))
        self.assertEqual(owned, merged)
        overview = (self.serial / "overview" / "level_0.yaml").read_text()
        self.assertIn("resolution: 1\n", overview)
        self.assertTrue((self.serial / "overview" / "level_0.pgm").is_file())

    def test_classes_agree_across_borders(self):
        borders = re.findall(r"border (\d+)\|(\d+): classes agree on ([0-9.]+) \(free or not: ([0-9.]+)\) "
                             r"of ([0-9.]+) m2", self.merge_output)
        self.assertGreaterEqual(len(borders), TILES - 1, self.merge_output)
        for a, b, fraction, free_fraction, area in borders:
            self.assertGreater(float(area), 100.0, f"border {a}|{b}")
            self.assertGreaterEqual(float(fraction), MIN_BORDER_AGREEMENT, f"border {a}|{b}: {self.merge_output}")
            self.assertGreaterEqual(float(free_fraction), MIN_FREE_AGREEMENT, f"border {a}|{b}: {self.merge_output}")

    def test_slurm_run_is_byte_identical_to_serial(self):
        missing = missing_programs()
        self.assertEqual(missing, [], "the Slurm test needs slurm-wlm and munge (scripts/install_deps.sh): missing "
                         + ", ".join(missing))
        slurm = self.tmp / "slurm"
        plan = slurm / "plan.json"
        run("tiles", "plan", self.stream, *TILING, "--robot", ROBOT, "-o", str(plan), "--quiet")
        self.assertEqual(plan.read_bytes(), self.plan.read_bytes())
        cluster = SlurmCluster(cpus=2)
        self.addCleanup(cluster.stop)
        cluster.start()
        env = dict(cluster.env, TERRAMESH=BIN)
        result = subprocess.run(["bash", SUBMIT, "--wait", self.stream, str(plan), "--robot", ROBOT], env=env,
                                capture_output=True, text=True, timeout=600)
        logs = "\n".join(p.read_text(errors="replace") for p in sorted(slurm.glob("slurm-tiles-*.out")))
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr + logs + cluster.logs())
        files = merged_files(self.serial)
        self.assertEqual(merged_files(slurm), files)
        match, mismatch, errors = filecmp.cmpfiles(self.serial, slurm, files, shallow=False)
        self.assertEqual((mismatch, errors), ([], []))
        self.assertEqual(len(match), len(files))


class TilesBadInputTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = pathlib.Path(tempfile.mkdtemp(prefix="terramesh-tiles-bad-"))
        run("generate", "street", "--length-m", "40", "--seed", "2", "-o", str(cls.tmp / "data"), "--quiet")
        cls.stream = str(cls.tmp / "data" / "stream.tmstream")
        cls.plan = cls.tmp / "plan" / "plan.json"
        run("tiles", "plan", cls.stream, "--tile-m", "20", "--overlap-m", "5", "-o", str(cls.plan), "--quiet")
        cls.tiles = len(json.loads(cls.plan.read_text())["tiles"])

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def assertBadInput(self, result, *fragments):
        self.assertEqual(result.returncode, 2, result.stderr)
        for fragment in fragments:
            self.assertIn(fragment, result.stderr)

    def test_tile_index_beyond_the_plan(self):
        result = run("mesh", self.stream, "--tile", f"{self.plan}:{self.tiles + 5}", "--robot", ROBOT, check=False)
        self.assertBadInput(result, str(self.plan), f"no tile {self.tiles + 5}", f"has {self.tiles} tiles")
        self.assertFalse((self.plan.parent / f"tile_{self.tiles + 5:03d}").exists())

    def test_malformed_manifest_names_the_field(self):
        plan = json.loads(self.plan.read_text())
        plan["tiles"][0]["bounds_m"]["min_x"] = "west"
        broken = self.tmp / "broken" / "plan.json"
        broken.parent.mkdir(exist_ok=True)
        broken.write_text(json.dumps(plan))
        result = run("mesh", self.stream, "--tile", f"{broken}:0", "--robot", ROBOT, check=False)
        self.assertBadInput(result, str(broken), "tiles[0].bounds_m.min_x", "expected a number")
        (broken.parent / "truncated.json").write_text(self.plan.read_text()[:40])
        result = run("tiles", "merge", str(broken.parent / "truncated.json"), check=False)
        self.assertBadInput(result, "truncated.json", "malformed JSON")

    def test_missing_stream_and_other_stream(self):
        result = run("mesh", str(self.tmp / "nowhere.tmstream"), "--tile", f"{self.plan}:0", "--robot", ROBOT,
                     check=False)
        self.assertBadInput(result, "nowhere.tmstream")
        run("generate", "street", "--length-m", "30", "--seed", "3", "-o", str(self.tmp / "other"), "--quiet")
        result = run("mesh", str(self.tmp / "other" / "stream.tmstream"), "--tile", f"{self.plan}:0", "--robot",
                     ROBOT, check=False)
        self.assertBadInput(result, "not the stream", str(self.plan))

    def test_malformed_tile_option_and_missing_robot(self):
        self.assertBadInput(run("mesh", self.stream, "--tile", str(self.plan), "--robot", ROBOT, check=False),
                            "--tile must be PLAN:I")
        self.assertBadInput(run("mesh", self.stream, "--tile", f"{self.plan}:0", check=False), "--tile needs --robot")

    def test_merge_before_the_tiles_are_meshed(self):
        result = run("tiles", "merge", str(self.plan), check=False)
        self.assertBadInput(result, "tile_000/tile.json", "has no result yet")


if __name__ == "__main__":
    unittest.main()
