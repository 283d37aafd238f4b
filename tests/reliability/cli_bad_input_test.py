"""Bad input, everywhere: every reader of `terramesh mesh` and `terramesh traverse` and the CLI
options, fed truncated files, wrong types, NaN/Inf, negative counts, ids that do not exist and
counts that would allocate gigabytes. Each must end in exit code 2, a last stderr line that names
the file (and the line, field or byte) and what was expected, and no output directory.

Run by ctest with: python3 -m unittest cli_bad_input_test (TERRAMESH_BIN and TERRAMESH_SHARED_DIR set).
"""
import json
import os
import shutil
import struct
import subprocess
import tempfile
import unittest

BIN = os.environ["TERRAMESH_BIN"]
SHARED = os.environ["TERRAMESH_SHARED_DIR"]
DATA = os.path.join(SHARED, "data")
KITTI_JSON = os.path.join(DATA, "kitti00_orbslam", "slam_data_version0.1_KITTI00_50frames.json")
COLMAP_TXT = os.path.join(DATA, "colmap_statue_of_liberty", "txt_model_40img")
COLMAP_BIN = os.path.join(DATA, "colmap_statue_of_liberty", "bin_model_40img")
OPENMVG = os.path.join(DATA, "openmvg_dinoring", "sfm_data.json")
LIDAR = os.path.join(DATA, "kitti00_lidar")
POSES = os.path.join(DATA, "kitti_poses", "00.txt")
SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ROBOT = os.path.join(SOURCE, "traversability", "robots", "car.yaml")

IDENTITY = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]


def run(*args):
    return subprocess.run([BIN, *args], capture_output=True, text=True, timeout=300)


class BadInputCase(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="terramesh_bad_input_")
        self.out = os.path.join(self.dir, "out")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def path(self, name):
        return os.path.join(self.dir, name)

    def write(self, name, data):
        path = self.path(name)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "wb" if isinstance(data, bytes) else "w") as f:
            f.write(data)
        return path

    def copy_dir(self, source, name):
        target = self.path(name)
        shutil.copytree(source, target)
        for root, _, files in os.walk(target):
            for f in files:
                os.chmod(os.path.join(root, f), 0o644)
        return target

    def assert_refused(self, args, *fragments, one_line=True):
        """Exit 2; the last stderr line holds every fragment; nothing written at self.out."""
        result = run(*args)
        self.assertEqual(result.returncode, 2, f"{args}: exit {result.returncode}: {result.stderr}")
        lines = result.stderr.strip().splitlines()
        self.assertTrue(lines, "an error message is expected")
        if one_line:
            self.assertEqual(len(lines), 1, result.stderr)
        last = lines[-1]
        self.assertTrue(last.startswith("terramesh"), last)
        for fragment in fragments:
            self.assertIn(fragment, last)
        self.assertFalse(os.path.exists(self.out), "no output may be written for bad input")
        return last

    def mesh(self, input_path, *fragments, extra=()):
        return self.assert_refused(["mesh", input_path, "-o", self.out, *extra], *fragments)


def slam_json(center=(0, 0, 0), key=0, observations=None, rotation=None):
    view = {"key": key, "extrinsic": {"rotation": rotation or IDENTITY, "center": list(center)},
            "observations": observations if observations is not None else [{"key": 1, "X": [0, 0, 5]}]}
    return {"slam_data_version": "0.1", "views": [view]}


class AuthorsJsonTest(BadInputCase):
    def test_truncated(self):
        with open(KITTI_JSON) as f:
            text = f.read()
        path = self.write("cut.json", text[: len(text) // 2])
        self.mesh(path, path, "malformed JSON")

    def test_wrong_type(self):
        path = self.write("t.json", json.dumps(slam_json(center=(0, "north", 0))))
        self.mesh(path, path, "views[0].extrinsic.center[1]", "expected a number")

    def test_number_overflow_is_not_a_crash(self):
        path = self.write("inf.json", json.dumps(slam_json()).replace("[0, 0, 0]", "[1e999, 0, 0]"))
        self.mesh(path, path, "out of range")

    def test_nan_literal(self):
        path = self.write("nan.json", json.dumps(slam_json()).replace("[0, 0, 0]", "[NaN, 0, 0]"))
        self.mesh(path, path, "malformed JSON")

    def test_negative_id(self):
        path = self.write("neg.json", json.dumps(slam_json(key=-4)))
        self.mesh(path, path, "views[0].key", "non-negative")

    def test_missing_field(self):
        path = self.write("miss.json", json.dumps(slam_json(observations=[{"key": 3}])))
        self.mesh(path, path, "views[0].observations[0].X")

    def test_not_a_rotation(self):
        path = self.write("rot.json", json.dumps(slam_json(rotation=[[2, 0, 0], [0, 1, 0], [0, 0, 1]])))
        self.mesh(path, path, "views[0].extrinsic.rotation")


class TmStreamTest(BadInputCase):
    HEADER = "terramesh_stream 1\n"

    def stream(self, body):
        return self.write("s.tmstream", self.HEADER + body)

    def test_truncated(self):
        path = self.stream("keyframe 0 0 0 0 1 0 0 0 3\n1 0 0 5\n")
        self.mesh(path, path, "line 3", "file ends inside the keyframe")

    def test_nan_and_inf(self):
        for value in ("nan", "inf", "-inf", "1e999"):
            path = self.stream(f"keyframe 0 0 0 0 1 0 0 0 1\n1 {value} 0 5\n")
            self.mesh(path, path, "line 3", "finite")

    def test_negative_count(self):
        path = self.stream("keyframe 0 0 0 0 1 0 0 0 -3\n")
        self.mesh(path, path, "line 2", "non-negative")

    def test_huge_counts_are_refused_before_allocating(self):
        path = self.stream("keyframe 0 0 0 0 1 0 0 0 999999999999\n1 0 0 5\n")
        self.mesh(path, path, "line 3")
        path = self.stream("remove_points 99999999999 1 2\n")
        self.mesh(path, path, "line 2", "remove_points")

    def test_wrong_type_and_bad_quaternion(self):
        path = self.stream("keyframe zero 0 0 0 1 0 0 0 0\n")
        self.mesh(path, path, "line 2")
        path = self.stream("keyframe 0 0 0 0 2 0 0 0 0\n")
        self.mesh(path, path, "line 2", "quaternion")

    def test_wrong_magic(self):
        path = self.write("m.tmstream", "terramesh_stream 99\n")
        self.mesh(path, path, "line 1")


class ColmapTest(BadInputCase):
    def text_model(self):
        return self.copy_dir(COLMAP_TXT, "txt")

    def edit(self, path, edit):
        with open(path) as f:
            lines = f.read().split("\n")
        with open(path, "w") as f:
            f.write("\n".join(edit(lines)))

    @staticmethod
    def first_data(lines):
        return next(i for i, line in enumerate(lines) if line and not line.startswith("#"))

    def test_text_truncated(self):
        model = self.text_model()
        images = os.path.join(model, "images.txt")
        with open(images) as f:
            text = f.read()
        with open(images, "w") as f:
            f.write(text[: len(text) // 3])
        self.mesh(model, "images.txt", "line")

    def test_text_nan_point(self):
        model = self.text_model()
        points = os.path.join(model, "points3D.txt")

        def nan(lines):
            i = self.first_data(lines)
            fields = lines[i].split()
            fields[1] = "nan"
            lines[i] = " ".join(fields)
            return lines
        self.edit(points, nan)
        self.mesh(model, "points3D.txt", "line")

    def test_text_unknown_point_id(self):
        model = self.text_model()
        images = os.path.join(model, "images.txt")

        def unknown(lines):
            i = self.first_data(lines) + 1  # the first image's points line
            fields = lines[i].split()
            fields[2] = "987654321"
            lines[i] = " ".join(fields)
            return lines
        self.edit(images, unknown)
        self.mesh(model, "images.txt", "987654321")

    def test_text_unknown_camera_and_wrong_type(self):
        model = self.text_model()
        images = os.path.join(model, "images.txt")

        def camera(lines):
            i = self.first_data(lines)
            fields = lines[i].split()
            fields[8] = "77"
            lines[i] = " ".join(fields)
            return lines
        self.edit(images, camera)
        self.mesh(model, "images.txt", "77")
        model = self.copy_dir(COLMAP_TXT, "txt2")
        cameras = os.path.join(model, "cameras.txt")

        def width(lines):
            i = self.first_data(lines)
            fields = lines[i].split()
            fields[2] = "wide"
            lines[i] = " ".join(fields)
            return lines
        self.edit(cameras, width)
        self.mesh(model, "cameras.txt", "line")

    def binary_model(self):
        return self.copy_dir(COLMAP_BIN, "bin")

    def test_binary_truncated(self):
        model = self.binary_model()
        images = os.path.join(model, "images.bin")
        with open(images, "rb") as f:
            data = f.read()
        with open(images, "wb") as f:
            f.write(data[: len(data) // 2])
        self.mesh(model, "images.bin", "byte")

    def test_binary_huge_count(self):
        model = self.binary_model()
        points = os.path.join(model, "points3D.bin")
        with open(points, "r+b") as f:
            f.write(struct.pack("<Q", 2**60))
        self.mesh(model, "points3D.bin", "byte 0")

    def test_binary_nan(self):
        model = self.binary_model()
        points = os.path.join(model, "points3D.bin")
        with open(points, "r+b") as f:
            f.seek(8 + 8)  # count, first point id, then X
            f.write(struct.pack("<d", float("nan")))
        self.mesh(model, "points3D.bin", "byte")


class OpenMvgTest(BadInputCase):
    def load(self):
        with open(OPENMVG) as f:
            return json.load(f)

    def test_truncated(self):
        with open(OPENMVG) as f:
            text = f.read()
        path = self.write("sfm_data.json", text[: len(text) // 2])
        self.mesh(path, path, "malformed JSON")

    def test_wrong_type(self):
        data = self.load()
        data["extrinsics"][0]["value"]["center"][0] = "east"
        path = self.write("sfm_data.json", json.dumps(data))
        self.mesh(path, path, "extrinsics[0].value.center[0]")

    def test_observation_of_a_view_that_does_not_exist(self):
        data = self.load()
        data["structure"][0]["value"]["observations"][0]["key"] = 999999
        path = self.write("sfm_data.json", json.dumps(data))
        self.mesh(path, path, "structure[0].value.observations[0]", "999999")

    def test_overflowing_number(self):
        data = self.load()
        text = json.dumps(data)
        data["structure"][0]["value"]["X"][0] = 12345.678
        text = json.dumps(data).replace("12345.678", "1e999")
        path = self.write("sfm_data.json", text)
        self.mesh(path, path, "out of range")


BUNDLE_HEADER = "# Bundle file v0.3\n"
CAMERA = "500 0 0\n1 0 0\n0 1 0\n0 0 1\n0 0 0\n"


class BundlerTest(BadInputCase):
    def bundle(self, body):
        return self.write("bundle.out", BUNDLE_HEADER + body)

    def test_truncated(self):
        # Too short for its header's counts: refused at the header, before reading cameras.
        path = self.bundle("2 1\n" + CAMERA)
        self.mesh(path, path, "line 2", "truncated file")

    def test_huge_counts_are_refused_before_allocating(self):
        path = self.bundle("999999999999 999999999999\n" + CAMERA)
        self.mesh(path, path, "line 2", "cannot fit")

    def test_negative_count(self):
        path = self.bundle("-2 1\n" + CAMERA)
        self.mesh(path, path, "line 2", "number of cameras")

    def test_nan(self):
        path = self.bundle("1 1\n" + CAMERA + "nan 0 1\n255 255 255\n1 0 0 0 0\n")
        self.mesh(path, path, "point 0", "position")

    def test_camera_that_does_not_exist(self):
        path = self.bundle("1 1\n" + CAMERA + "0 0 1\n255 255 255\n1 7 0 0 0\n")
        self.mesh(path, path, "point 0", "camera 7 out of range")


class KittiTest(BadInputCase):
    def sequence(self):
        seq = self.path("seq")
        os.makedirs(os.path.join(seq, "velodyne"))
        shutil.copy(os.path.join(LIDAR, "calib.txt"), seq)
        for frame in ("000001.bin", "000002.bin"):
            shutil.copy(os.path.join(LIDAR, "velodyne", frame), os.path.join(seq, "velodyne"))
        return seq

    def mesh_kitti(self, seq, *fragments, poses=POSES):
        return self.mesh(seq, *fragments, extra=("--poses", poses, "--frames", "1:3"))

    def test_scan_size_not_a_multiple_of_16(self):
        seq = self.sequence()
        with open(os.path.join(seq, "velodyne", "000002.bin"), "ab") as f:
            f.write(b"\0\0\0")
        self.mesh_kitti(seq, "000002.bin", "multiple of 16")

    def test_nan_in_a_scan(self):
        seq = self.sequence()
        with open(os.path.join(seq, "velodyne", "000001.bin"), "r+b") as f:
            f.seek(16 * 5 + 4)
            f.write(struct.pack("<f", float("nan")))
        self.mesh_kitti(seq, "000001.bin", "byte")

    def test_calib_without_tr(self):
        seq = self.sequence()
        self.write("seq/calib.txt", "P0: 1 0 0 0 0 1 0 0 0 0 1 0\n")
        self.mesh_kitti(seq, "calib.txt", "Tr")

    def test_malformed_and_truncated_poses(self):
        seq = self.sequence()
        poses = self.write("poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 zero 0 1 0 0 0 0 1 0\n")
        self.mesh_kitti(seq, "poses.txt", "line 2", poses=poses)
        poses = self.write("short.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n")
        self.mesh_kitti(seq, "short.txt", poses=poses)

    def test_tum_poses_with_nan_and_time_going_back(self):
        seq = self.sequence()
        self.write("seq/times.txt", "0.0\n0.1\n0.2\n")
        poses = self.write("tum.txt", "0.0 0 0 0 0 0 0 1\n0.1 nan 0 0 0 0 0 1\n0.2 0 0 0 0 0 0 1\n")
        self.mesh_kitti(seq, "tum.txt", "line 2", poses=poses)
        poses = self.write("tum2.txt", "0.0 0 0 0 0 0 0 1\n0.2 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 0 1\n")
        self.mesh_kitti(seq, "tum2.txt", "line 3", poses=poses)


PLY_HEADER = ("ply\nformat ascii 1.0\nelement vertex {v}\nproperty float x\nproperty float y\n"
              "property float z\nelement face {f}\nproperty list uchar int vertex_indices\nend_header\n")
TETRAHEDRON = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"


class TraverseTest(BadInputCase):
    def traverse(self, mesh, *fragments, robot=ROBOT):
        # traverse may print notes first (e.g. about gravity); the error is the last line.
        return self.assert_refused(["traverse", mesh, "--robot", robot, "-o", self.out], *fragments,
                                   one_line=False)

    def test_valid_tetrahedron_is_accepted(self):
        mesh = self.write("tet.ply", PLY_HEADER.format(v=4, f=4) + TETRAHEDRON)
        result = run("traverse", mesh, "--robot", ROBOT, "-o", self.out, "--no-geotiff", "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)

    def test_truncated(self):
        mesh = self.write("cut.ply", PLY_HEADER.format(v=4, f=4) + TETRAHEDRON[:20])
        self.traverse(mesh, "cut.ply")

    def test_huge_counts_are_refused_before_allocating(self):
        mesh = self.write("huge.ply", PLY_HEADER.format(v=999999999999, f=1) + "0 0 0\n")
        self.traverse(mesh, "huge.ply")
        mesh = self.write("huge2.ply", PLY_HEADER.format(v=4, f=999999999999) + TETRAHEDRON)
        self.traverse(mesh, "huge2.ply")

    def test_negative_count_and_index_out_of_range(self):
        mesh = self.write("neg.ply", PLY_HEADER.format(v=-4, f=4) + TETRAHEDRON)
        self.traverse(mesh, "neg.ply")
        mesh = self.write("idx.ply", PLY_HEADER.format(v=4, f=4) + TETRAHEDRON.replace("3 1 2 3", "3 1 2 9"))
        self.traverse(mesh, "idx.ply", "face 3")

    def test_nan_vertex(self):
        mesh = self.write("nan.ply", PLY_HEADER.format(v=4, f=4) + TETRAHEDRON.replace("1 0 0\n", "nan 0 0\n", 1))
        self.traverse(mesh, "nan.ply")

    def test_robot_yaml(self):
        mesh = self.write("tet.ply", PLY_HEADER.format(v=4, f=4) + TETRAHEDRON)
        cases = {
            "type.yaml": ("name: r\nfootprint: {radius_m: 0.3}\nmax_slope_deg: steep\n", "max_slope_deg"),
            "nan.yaml": ("name: r\nfootprint: {radius_m: .nan}\n", "radius_m"),
            "neg.yaml": ("name: r\nfootprint: {radius_m: 0.3}\nmax_step_m: -1\n", "max_step_m"),
            "unknown.yaml": ("name: r\nfootprint: {radius_m: 0.3}\nwarp_drive: 1\n", "warp_drive"),
            "broken.yaml": ("name: r\nfootprint: {radius_m: 0.3\n", "broken.yaml"),
            "count.yaml": ("name: r\nfootprint: {radius_m: 0.3}\ncontact_headings: 1000000000000\n",
                           "contact_headings"),
        }
        for name, (text, fragment) in cases.items():
            with self.subTest(name):
                robot = self.write(name, text)
                self.traverse(mesh, fragment, robot=robot)
        missing = self.path("absent.yaml")
        self.traverse(mesh, "absent.yaml", robot=missing)


class CliOptionsTest(BadInputCase):
    def stream(self):
        return self.write("ok.tmstream", "terramesh_stream 1\nkeyframe 0 0 0 0 1 0 0 0 1\n1 0 0 5\n")

    def test_unknown_options(self):
        for command in ("mesh", "traverse", "generate", "bench", "eval", "plan"):
            with self.subTest(command):
                result = run(command, "--warp-drive", "9")
                self.assertEqual(result.returncode, 2, result.stderr)
                self.assertIn("warp-drive", result.stderr)
        result = run("teleport")
        self.assertEqual(result.returncode, 2)

    def test_out_of_range_values(self):
        stream = self.stream()
        # The message names the option or the configuration field it sets.
        cases = [("--min-views", "-1", "min"), ("--min-views", "many", "min"),
                 ("--max-distance-m", "nan", "distance"), ("--max-distance-m", "-5", "distance"),
                 ("--steiner-step-m", "0", "steiner"), ("--steiner-step-m", "inf", "steiner"),
                 ("--metres-per-unit", "-2", "metres"), ("--metres-per-unit", "1e999", "metres"),
                 ("--mode", "fastest", "mode")]
        for option, value, fragment in cases:
            with self.subTest(option=option, value=value):
                self.assert_refused(["mesh", stream, "-o", self.out, option, value], fragment)

    def test_output_directory_that_cannot_be_created(self):
        # A path under a regular file cannot be created by anyone, root included.
        blocker = self.write("a_file", "not a directory\n")
        self.out = os.path.join(blocker, "sub")
        last = self.assert_refused(["mesh", self.stream(), "-o", self.out], "a_file")
        self.assertIn("cannot", last)
        with open(blocker) as f:
            self.assertEqual(f.read(), "not a directory\n")


if __name__ == "__main__":
    unittest.main()
