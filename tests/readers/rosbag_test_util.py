"""Shared by the ROS bag CLI tests (cli_rosbag_test.py, cli_rosbag_tf_test.py): message builders
written with Debian's python3-rosbag, readers of terramesh's outputs and the test cases' bases."""
import os
import shutil
import subprocess
import tempfile
import unittest

import numpy as np
import rosbag
from genpy import Time
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import PointCloud2, PointField

BIN = os.environ["TERRAMESH_BIN"]
SHARED = os.environ["TERRAMESH_SHARED_DIR"]
LIDAR = os.path.join(SHARED, "data", "kitti00_lidar")
POSES = os.path.join(SHARED, "data", "kitti_poses", "00.txt")

FLOAT32, FLOAT64, UINT32 = PointField.FLOAT32, PointField.FLOAT64, PointField.UINT32
NUMPY_TYPES = {FLOAT32: "<f4", FLOAT64: "<f8", UINT32: "<u4"}


def run(*args):
    return subprocess.run([BIN, *args], capture_output=True, text=True, timeout=600)


def stamp(seconds):
    return Time.from_sec(seconds)


def cloud_message(columns, time, frame):
    """A PointCloud2 of one row: columns = [(name, datatype, values)], packed in that order."""
    dtype = np.dtype([(name, NUMPY_TYPES[kind]) for name, kind, _ in columns])
    records = np.zeros(len(columns[0][2]), dtype=dtype)
    for name, _, values in columns:
        records[name] = values
    msg = PointCloud2()
    msg.header.stamp = time
    msg.header.frame_id = frame
    msg.height, msg.width = 1, len(records)
    msg.fields = [PointField(name=name, offset=dtype.fields[name][1], datatype=kind, count=1)
                  for name, kind, _ in columns]
    msg.is_bigendian = False
    msg.point_step = dtype.itemsize
    msg.row_step = dtype.itemsize * len(records)
    msg.data = records.tobytes()
    msg.is_dense = True
    return msg


def odometry(time, frame, child, position, quaternion_xyzw):
    msg = Odometry()
    msg.header.stamp = time
    msg.header.frame_id = frame
    msg.child_frame_id = child
    p, q = msg.pose.pose.position, msg.pose.pose.orientation
    p.x, p.y, p.z = (float(v) for v in position)
    q.x, q.y, q.z, q.w = (float(v) for v in quaternion_xyzw)
    return msg


def pose_stamped(time, frame, position, quaternion_xyzw):
    msg = PoseStamped()
    msg.header.stamp = time
    msg.header.frame_id = frame
    p, q = msg.pose.position, msg.pose.orientation
    p.x, p.y, p.z = (float(v) for v in position)
    q.x, q.y, q.z, q.w = (float(v) for v in quaternion_xyzw)
    return msg


def read_tmstream_keyframes(path):
    """[(id, centre, quaternion wxyz, [(point id, x, y, z)])] of a .tmstream holding only keyframes."""
    keyframes = []
    with open(path) as f:
        lines = iter(f.read().splitlines())
    for line in lines:
        fields = line.split()
        if not fields or fields[0] != "keyframe":
            if fields and fields[0] in ("remove_points", "remove_keyframe"):
                raise AssertionError("the comparison needs a stream of keyframes only")
            continue
        count = int(fields[9])
        observations = [next(lines).split() for _ in range(count)]
        keyframes.append((int(fields[1]), [float(v) for v in fields[2:5]], [float(v) for v in fields[5:9]],
                          [(int(o[0]), float(o[1]), float(o[2]), float(o[3])) for o in observations]))
    return keyframes


def quaternion_xyzw(rotation):
    """The unit quaternion of a 3x3 rotation matrix (x, y, z, w)."""
    m = rotation
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    if trace > 0:
        s = 2.0 * np.sqrt(trace + 1.0)
        q = [(m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, 0.25 * s]
    else:
        i = int(np.argmax([m[0, 0], m[1, 1], m[2, 2]]))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * np.sqrt(1.0 + m[i, i] - m[j, j] - m[k, k])
        q = [0.0, 0.0, 0.0, (m[k, j] - m[j, k]) / s]
        q[i] = 0.25 * s
        q[j] = (m[j, i] + m[i, j]) / s
        q[k] = (m[k, i] + m[i, k]) / s
    q = np.array(q)
    return q / np.linalg.norm(q)


class BagCase(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="terramesh_rosbag_")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def path(self, name):
        return os.path.join(self.dir, name)

    def mesh(self, source, name, *options):
        out = self.path(name)
        result = run("mesh", source, "-o", out, *options)
        self.assertEqual(result.returncode, 0, result.stderr)
        return out, result.stderr

    def file_bytes(self, *parts):
        with open(os.path.join(*parts), "rb") as f:
            return f.read()


class StreetStreamCase(BagCase):
    """The generator's street camera stream (tracked points with ids) in self.stream / self.keyframes."""

    def setUp(self):
        super().setUp()
        generated = run("generate", "street", "-o", self.path("gen"), "--length-m", "40", "--quiet")
        self.assertEqual(generated.returncode, 0, generated.stderr)
        self.stream = self.path("gen/stream.tmstream")
        self.keyframes = read_tmstream_keyframes(self.stream)
        self.assertGreater(len(self.keyframes), 10)
        # The bag's keyframe ids are the clouds' indices on the topic.
        self.assertEqual([k[0] for k in self.keyframes], list(range(len(self.keyframes))))

    @staticmethod
    def stamp_of(index):
        return Time(100 + index // 10, (index % 10) * 100_000_000)

    @staticmethod
    def id_cloud(observations, time, frame):
        """A cloud of float64 x y z and a uint32 `id` field: (id, x, y, z) observations."""
        columns = [(axis, FLOAT64, [o[k + 1] for o in observations]) for k, axis in enumerate("xyz")]
        return cloud_message(columns + [("id", UINT32, [o[0] for o in observations])], time, frame)


def transform_stamped(time, parent, child, position, q_xyzw):
    from geometry_msgs.msg import TransformStamped
    msg = TransformStamped()
    msg.header.stamp, msg.header.frame_id, msg.child_frame_id = time, parent, child
    v, q = msg.transform.translation, msg.transform.rotation
    v.x, v.y, v.z = (float(x) for x in position)
    q.x, q.y, q.z, q.w = (float(x) for x in q_xyzw)
    return msg


def tf_message(*transforms):
    from tf2_msgs.msg import TFMessage
    return TFMessage(transforms=list(transforms))


def rotation_matrix(q_xyzw):
    x, y, z, w = q_xyzw
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def read_points_ply(path):
    """x y z (float32) of the run's points.ply: element vertex with float x y z and uint first_keyframe."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode()
    count = int(header.split("element vertex ")[1].split()[0])
    layout = "property float x\nproperty float y\nproperty float z\nproperty uint first_keyframe\n"
    assert layout in header, header
    records = np.frombuffer(data, dtype=[("xyz", "<f4", 3), ("first", "<u4")], count=count, offset=end)
    return records["xyz"].astype(float)


def read_ply_vertices(path):
    """x y z of the vertices of a binary little-endian PLY whose vertex element starts with x y z."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    assert "format binary_little_endian 1.0" in header, header[:3]
    count, properties, in_vertex = 0, [], False
    sizes = {"float": "<f4", "double": "<f8", "uchar": "u1", "uint": "<u4", "int": "<i4", "ushort": "<u2"}
    for line in header:
        words = line.split()
        if words[:2] == ["element", "vertex"]:
            count, in_vertex = int(words[2]), True
        elif words and words[0] == "element":
            in_vertex = False
        elif in_vertex and words[0] == "property":
            properties.append((words[2], sizes[words[1]]))
    records = np.frombuffer(data, dtype=properties, count=count, offset=end)
    return np.stack([records["x"], records["y"], records["z"]], axis=1).astype(float)


def mesh_counts(out):
    """(vertices, faces, closed 2-manifold) from a run's summary.txt."""
    with open(os.path.join(out, "summary.txt")) as f:
        line = next(line for line in f if line.startswith("mesh: "))
    words = line.replace("(", " ").replace(",", " ").split()
    return int(words[words.index("vertices") - 1]), int(words[words.index("faces") - 1]), "closed 2-manifold" in line


@unittest.skipUnless(os.path.isdir(os.path.join(LIDAR, "velodyne")) and os.path.isfile(POSES),
                     "the shared KITTI 00 LiDAR data is not there")
def small_cloud(time, frame="velodyne", names=("x", "y", "z"), kind=FLOAT32, offset=0.0):
    """Four points 5 m around the sensor, with the fields `names`."""
    values = {"x": [5.0 + offset, 0.0, -5.0, 0.0], "y": [0.0, 5.0, 0.0, -5.0], "z": [0.5, 0.5, 0.5, float("nan")]}
    return cloud_message([(name, kind, values[name]) for name in names], time, frame)


class BadBagCase(BagCase):
    """Bags built to be refused: each refusal exits 2 with one line naming the bag, the topic and, for a
    message, its index; no output is written."""

    def write_bag(self, name, messages, compression="none"):
        path = self.path(name)
        with rosbag.Bag(path, "w", compression=compression) as bag:
            for topic, message, seconds in messages:
                bag.write(topic, message, t=stamp(seconds))
        return path

    def lidar_bag(self, name="lidar.bag", clouds=3, extra=(), compression="none"):
        messages = []
        for i in range(clouds):
            t = 10.0 + i
            messages.append(("/odom", odometry(stamp(t), "odom", "velodyne", (i, 0, 0), (0, 0, 0, 1)), t))
            messages.append(("/points", small_cloud(stamp(t), offset=i), t))
        return self.write_bag(name, messages + list(extra), compression)

    def assert_refused(self, bag, *fragments, options=()):
        out = self.path("out")
        result = run("mesh", bag, "-o", out, *options)
        self.assertEqual(result.returncode, 2, result.stderr)
        lines = result.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, result.stderr)
        self.assertTrue(lines[0].startswith("terramesh: " + bag + ": "), lines[0])
        for fragment in fragments:
            self.assertIn(fragment, lines[0])
        self.assertFalse(os.path.exists(out), "no output may be written for bad input")
        return lines[0]
