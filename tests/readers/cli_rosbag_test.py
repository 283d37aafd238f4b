"""ROS 1 bags through `terramesh mesh BAG.bag`: test bags written with Debian's python3-rosbag (no ROS
master), meshed and compared with the same data read by terramesh's other readers.

- SyntheticBagTest: a synthetic camera stream written as registered PointCloud2s (float64 x y z and an
  `id` field) with an Odometry at each stamp gives a byte-identical mesh.ply to the .tmstream.
- TfTreeBagTest: the same camera stream as a robot records it: clouds in the camera's frame, posed by
  odom -> base_link on /tf (or an Odometry of base_link) and base_link -> camera on /tf_static; the
  composed chain gives the stream's mesh (vertices within 1e-9 m: see the class for why not bytes).
- KittiBagTest: KITTI Velodyne scans in the sensor frame with Odometry from the KITTI poses, against the
  KITTI reader on the same scans (see the test for why the meshes are close, not identical).
- SyntheticLidarBagTest: the generator's LiDAR model (`generate --lidar`, a KITTI sequence folder),
  converted to a .tmstream and written as registered clouds with an Odometry per scan: the folder,
  the stream and the bag give one byte-identical mesh.ply.
- BadBagTest: missing topic, wrong type, several candidates, a cloud without z, no pose near a cloud;
  tf: a cloud frame not in the tree, a frame with two parents, a cycle.

Run by ctest with the system Python (python3-rosbag): /usr/bin/python3 -m unittest cli_rosbag_test
(TERRAMESH_BIN and TERRAMESH_SHARED_DIR set).
"""
import os
import re
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
from std_msgs.msg import String

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


class SyntheticBagTest(StreetStreamCase):
    """A camera stream with tracked points: ids from the `id` field, clouds already in the world."""

    def write_bag(self, name, pose_kind="odometry", cloud_frame="map"):
        path = self.path(name)
        with rosbag.Bag(path, "w") as bag:
            bag.write("/rosout_like", String(data="not a cloud"), t=stamp(99.0))
            for index, (_, centre, q_wxyz, observations) in enumerate(self.keyframes):
                time = self.stamp_of(index)
                q_xyzw = q_wxyz[1:] + q_wxyz[:1]
                if pose_kind == "odometry":
                    bag.write("/odom", odometry(time, "map", "camera_optical_frame", centre, q_xyzw), t=time)
                else:
                    bag.write("/pose", pose_stamped(time, "map", centre, q_xyzw), t=time)
                bag.write("/slam/points", self.id_cloud(observations, time, cloud_frame), t=time)
        return path

    def test_bag_gives_the_same_mesh_file_as_the_stream(self):
        bag = self.write_bag("odom.bag")
        stream_out, _ = self.mesh(self.stream, "from_stream", "--quiet")
        bag_out, stderr = self.mesh(bag, "from_bag")
        self.assertEqual(self.file_bytes(bag_out, "mesh.ply"), self.file_bytes(stream_out, "mesh.ply"))
        # The mesh is not trivial, and the run says what it inferred from the bag.
        self.assertGreater(len(self.file_bytes(bag_out, "mesh.ply")), 10000)
        self.assertIn("terramesh: input: clouds from /slam/points (sensor_msgs/PointCloud2, "
                      f"{len(self.keyframes)} messages), the bag's only PointCloud2 topic", stderr)
        self.assertIn("poses from /odom (nav_msgs/Odometry), " + str(len(self.keyframes)) +
                      " poses, the bag's only pose topic", stderr)
        self.assertIn("clouds in the world frame (points used as they are): its header.frame_id \"map\" is "
                      "the poses' frame", stderr)
        self.assertIn("point ids from the field \"id\"", stderr)
        self.assertIn("sensor up axis -y (sensor frame \"camera_optical_frame\")", stderr)
        with open(os.path.join(bag_out, "summary.txt")) as f:
            self.assertIn("input: point ids from the field \"id\"", f.read())
        # The keyframes (centres, rotations) are the stream's, bit for bit.
        self.assertEqual(self.file_bytes(bag_out, "trajectory.csv"), self.file_bytes(stream_out, "trajectory.csv"))

    def test_pose_stamped_and_the_frame_override(self):
        bag = self.write_bag("pose.bag", pose_kind="pose_stamped", cloud_frame="registered")
        refused = run("mesh", bag, "-o", self.path("refused"))
        self.assertEqual(refused.returncode, 2, refused.stderr)
        self.assertIn("topic /slam/points: message 0: PointCloud2 header.frame_id \"registered\" is neither the "
                      "poses' frame \"map\"", refused.stderr)
        self.assertFalse(os.path.exists(self.path("refused")))
        stream_out, _ = self.mesh(self.stream, "from_stream", "--quiet")
        bag_out, stderr = self.mesh(bag, "from_bag", "--cloud-frame", "world", "--pose-topic", "/pose")
        self.assertIn("clouds in the world frame (points used as they are): as --cloud-frame says", stderr)
        self.assertIn("poses from /pose (geometry_msgs/PoseStamped)", stderr)
        # A PoseStamped names no sensor frame: the reader takes a REP 103 body frame (+z up) and
        # says so; up, which mesh.ply's header records, then differs from the camera stream's.
        self.assertIn("sensor up axis +z (sensor frame unnamed: REP 103 body frame)", stderr)
        without_up = [re.sub(rb"comment frame\.up[^\n]*\n", b"", self.file_bytes(out, "mesh.ply"))
                      for out in (bag_out, stream_out)]
        self.assertEqual(without_up[0], without_up[1])


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


class TfTreeBagTest(StreetStreamCase):
    """The street camera stream as a robot records it: the camera's points in its own frame
    (camera_optical_frame), mounted on base_link by a static extrinsic on /tf_static (0.2 m ahead,
    1.1 m up, REP 103's optical rotation), and base_link posed in odom on /tf (time-varying) or by
    an Odometry of base_link. The reader composes odom -> base_link -> camera_optical_frame per
    cloud, as tf2's lookupTransform does.

    Why not byte-identical to the stream: the test splits each keyframe pose T_odom_camera into
    T_odom_base = T_odom_camera * T_base_camera^-1 and moves the points into the camera frame in
    float64 (numpy); the reader composes the pose back and moves the points out again (Eigen), which
    rounds differently in the last bits (1.4e-14 m at most in mesh.ply's float64 vertices when this
    was written). So the meshes are compared by vertex count, face count and vertex positions within
    1e-9 m, the keyframe centres within 1e-9 m."""

    EXTRINSIC_T = (0.2, 0.0, 1.1)
    EXTRINSIC_Q = (-0.5, 0.5, -0.5, 0.5)  # base_link (x forward, z up) -> optical (z forward, y down)

    def sensor_frame_data(self):
        """[(stamp, base_link position, base_link quaternion xyzw, camera-frame observations)]."""
        r_bc, t_bc = rotation_matrix(self.EXTRINSIC_Q), np.array(self.EXTRINSIC_T)
        data = []
        for index, (_, centre, q_wxyz, observations) in enumerate(self.keyframes):
            r_wc, c = rotation_matrix(q_wxyz[1:] + q_wxyz[:1]), np.array(centre)
            r_wb = r_wc @ r_bc.T
            points = (np.array([o[1:] for o in observations]) - c) @ r_wc  # rows: R_wc^T (x_W - c)
            local = [(o[0], *p) for o, p in zip(observations, points)]
            data.append((self.stamp_of(index), c - r_wb @ t_bc, quaternion_xyzw(r_wb), local))
        return data

    def write_tf_bag(self, name, pose_topic=False, static_parent="base_link", registered=False):
        path = self.path(name)
        with rosbag.Bag(path, "w") as bag:
            first = self.stamp_of(0)
            bag.write("/tf_static", tf_message(transform_stamped(first, static_parent, "camera_optical_frame",
                                                                 self.EXTRINSIC_T, self.EXTRINSIC_Q)), t=first)
            for (time, position, q_xyzw, local), keyframe in zip(self.sensor_frame_data(), self.keyframes):
                if pose_topic:
                    bag.write("/odom", odometry(time, "odom", "base_link", position, q_xyzw), t=time)
                else:
                    bag.write("/tf", tf_message(transform_stamped(time, "odom", "base_link", position, q_xyzw)), t=time)
                cloud = self.id_cloud(keyframe[3], time, "odom") if registered else \
                    self.id_cloud(local, time, "camera_optical_frame")
                bag.write("/camera/points", cloud, t=time)
        return path

    def assert_same_mesh(self, out, stream_out):
        stream_vertices, stream_faces, _ = mesh_counts(stream_out)
        vertices, faces, _ = mesh_counts(out)
        self.assertEqual((vertices, faces), (stream_vertices, stream_faces))
        self.assertGreater(faces, 1000)
        mesh, reference = (read_ply_vertices(os.path.join(o, "mesh.ply")) for o in (out, stream_out))
        self.assertEqual(mesh.shape, reference.shape)
        self.assertLess(np.abs(mesh - reference).max(), 1e-9)
        with open(os.path.join(out, "trajectory.csv")) as f, open(os.path.join(stream_out, "trajectory.csv")) as g:
            rows = [[float(v) for v in line.split(",")[2:5]] for line in f.read().splitlines()[1:]]
            expected = [[float(v) for v in line.split(",")[2:5]] for line in g.read().splitlines()[1:]]
        self.assertEqual(len(rows), len(self.keyframes))
        np.testing.assert_allclose(rows, expected, rtol=0, atol=1e-9)

    def test_tf_tree_gives_the_stream_mesh(self):
        stream_out, _ = self.mesh(self.stream, "from_stream", "--quiet")
        bag_out, stderr = self.mesh(self.write_tf_bag("tf.bag"), "from_tf")
        self.assert_same_mesh(bag_out, stream_out)
        # No flag: the world frame is the tree's root, the sensor the clouds' frame, and the run says so.
        self.assertIn("terramesh: input: poses from tf on /tf (%d messages), /tf_static (1 messages), the bag has no "
                      "pose topic" % len(self.keyframes), stderr)
        self.assertIn("terramesh: input: poses: tf odom -> base_link -> camera_optical_frame (base_link -> "
                      "camera_optical_frame static); world frame \"odom\" (the tf tree's root), sensor frame "
                      "\"camera_optical_frame\"", stderr)
        self.assertIn("clouds in the sensor frame (points moved into the world by the pose): its header.frame_id "
                      "\"camera_optical_frame\" is in the tf tree under \"odom\"", stderr)
        self.assertIn("sensor up axis -y (sensor frame \"camera_optical_frame\")", stderr)
        # --tf-frames names the same chain: the same bytes.
        named_out, _ = self.mesh(self.path("tf.bag"), "named", "--tf-frames", "/odom", "camera_optical_frame", "--quiet")
        self.assertEqual(self.file_bytes(named_out, "mesh.ply"), self.file_bytes(bag_out, "mesh.ply"))
        # Registered clouds (in the root frame): posed by the tree's only leaf, the camera.
        registered_out, stderr = self.mesh(self.write_tf_bag("registered.bag", registered=True), "registered")
        self.assert_same_mesh(registered_out, stream_out)
        self.assertIn("clouds in the world frame (points used as they are): its header.frame_id \"odom\" is the tf "
                      "tree's root", stderr)
        self.assertIn("sensor frame \"camera_optical_frame\" (the only leaf frame under \"odom\")", stderr)

    def test_odometry_of_base_link_with_a_static_extrinsic(self):
        stream_out, _ = self.mesh(self.stream, "from_stream", "--quiet")
        bag_out, stderr = self.mesh(self.write_tf_bag("odom.bag", pose_topic=True), "from_odom")
        self.assert_same_mesh(bag_out, stream_out)
        self.assertIn("terramesh: input: poses: /odom (nav_msgs/Odometry) odom -> base_link, then /tf_static base_link "
                      "-> camera_optical_frame (base_link -> camera_optical_frame static); world frame \"odom\", "
                      "sensor frame \"camera_optical_frame\"", stderr)
        # Without the extrinsic the cloud frame is unexplained: exit 2, naming it.
        refused = run("mesh", self.write_tf_bag("no_extrinsic.bag", pose_topic=True, static_parent="imu"),
                      "-o", self.path("refused"))
        self.assertEqual(refused.returncode, 2, refused.stderr)
        self.assertIn("topic /camera/points: message 0: PointCloud2 header.frame_id \"camera_optical_frame\" is neither "
                      "the poses' frame \"odom\" nor their child frame \"base_link\", nor below it on /tf_static",
                      refused.stderr)


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
class KittiBagTest(BagCase):
    """KITTI scans in the sensor frame, posed by Odometry messages, against the KITTI reader.

    Both readers get the same returns: every STEP-th return of frames 1-3, written into the bag and
    into a KITTI sequence folder in the temporary directory (the KITTI reader's own thinning draws a
    random subset that a bag cannot repeat). The two streams still differ, for two reasons the test
    pins down, so the meshes are compared for equivalence, not bytes. (1) Ids: the bag's keyframe
    ids are the clouds' indices (0, 1, 2), the KITTI reader's the frame numbers (1, 2, 3), and the
    point ids (keyframe << 32 | index of the return) follow. (2) Rotations: the KITTI reader moves the
    returns by the 3x4 matrix T_W_cam0 * Tr as read, orthonormal only to the poses' printed digits,
    while an Odometry message carries a unit quaternion: world positions differ by ~1e-5 m. Asserted:
    the same keyframes (centres to 1e-9 m, the same rotations), the same returns in the same order
    within 1e-4 m, the same counts in every update's row of keyframes.csv but the id, and closed
    2-manifolds whose vertex and face counts agree within 1 %.
    """

    FRAMES = (1, 2, 3)
    STEP = 6

    def write_inputs(self):
        """The bag and the KITTI sequence folder, holding the same thinned scans."""
        with open(os.path.join(LIDAR, "calib.txt")) as f:
            tr = next(line for line in f if line.startswith("Tr:")).split()[1:]
        cam0_from_velodyne = np.vstack([np.array(tr, dtype=float).reshape(3, 4), [0, 0, 0, 1]])
        with open(POSES) as f:
            poses = [np.vstack([np.array(line.split(), dtype=float).reshape(3, 4), [0, 0, 0, 1]]) for line in f]
        with open(os.path.join(LIDAR, "times.txt")) as f:
            times = [float(line) for line in f]
        sequence = self.path("sequence")
        os.makedirs(os.path.join(sequence, "velodyne"))
        shutil.copyfile(os.path.join(LIDAR, "calib.txt"), os.path.join(sequence, "calib.txt"))
        bag_path = self.path("kitti.bag")
        with rosbag.Bag(bag_path, "w") as bag:
            for frame in self.FRAMES:
                time = stamp(1000.0 + times[frame])
                world_from_velodyne = poses[frame] @ cam0_from_velodyne
                bag.write("/odom", odometry(time, "world", "velodyne", world_from_velodyne[:3, 3],
                                            quaternion_xyzw(world_from_velodyne[:3, :3])), t=time)
                scan = np.fromfile(os.path.join(LIDAR, "velodyne", f"{frame:06d}.bin"), dtype="<f4").reshape(-1, 4)
                scan = scan[::self.STEP]
                scan.tofile(os.path.join(sequence, "velodyne", f"{frame:06d}.bin"))
                columns = [(name, FLOAT32, scan[:, k]) for k, name in enumerate(("x", "y", "z", "intensity"))]
                bag.write("/velodyne_points", cloud_message(columns, time, "velodyne"), t=time)
        return bag_path, sequence

    def test_sensor_frame_scans_match_the_kitti_reader(self):
        bag, sequence = self.write_inputs()
        first, last = self.FRAMES[0], self.FRAMES[-1]
        # Every return as its own point (--lidar-voxel-m 0): the voxels would turn the readers'
        # 1e-5 m differences into different returns kept where one lies on a voxel's face.
        kitti_out, _ = self.mesh(sequence, "kitti", "--poses", POSES, "--frames", f"{first}:{last}",
                                 "--lidar-voxel-m", "0", "--quiet")
        bag_out, stderr = self.mesh(bag, "bag", "--lidar-voxel-m", "0")
        self.assertIn("clouds in the sensor frame (points moved into the world by the pose): its header.frame_id "
                      "\"velodyne\" is the poses' child frame", stderr)
        self.assertIn("no field \"id\": every return is its own point (seen once), min_views 1 advised", stderr)
        self.assertIn("sensor up axis +z (sensor frame \"velodyne\")", stderr)

        def table(out, name):
            with open(os.path.join(out, name)) as f:
                lines = f.read().splitlines()
            return lines[0].split(","), [line.split(",") for line in lines[1:]]

        # The same keyframes: centres to rounding, rotations equal up to sign and rounding.
        columns, kitti_trajectory = table(kitti_out, "trajectory.csv")
        _, bag_trajectory = table(bag_out, "trajectory.csv")
        self.assertEqual([r[1] for r in kitti_trajectory], [str(f) for f in self.FRAMES])
        self.assertEqual([r[1] for r in bag_trajectory], [str(i) for i in range(len(self.FRAMES))])
        for kitti_row, bag_row in zip(kitti_trajectory, bag_trajectory):
            np.testing.assert_allclose(np.array(bag_row[2:5], dtype=float), np.array(kitti_row[2:5], dtype=float),
                                       rtol=0, atol=1e-9)
            dot = float(np.array(kitti_row[5:9], dtype=float) @ np.array(bag_row[5:9], dtype=float))
            self.assertGreater(abs(dot), 1 - 1e-12)
        # The same returns in the same order (points.ply lists points by id), within 1e-4 m.
        kitti_points = read_points_ply(os.path.join(kitti_out, "points.ply"))
        bag_points = read_points_ply(os.path.join(bag_out, "points.ply"))
        self.assertEqual(kitti_points.shape, bag_points.shape)
        self.assertGreater(len(kitti_points), 50000)
        self.assertLess(np.abs(kitti_points - bag_points).max(), 1e-4)
        # Every update saw and inserted the same numbers of points, rays and cells' worth of input.
        header, kitti_rows = table(kitti_out, "keyframes.csv")
        _, bag_rows = table(bag_out, "keyframes.csv")
        counted = [header.index(name) for name in ("new_points", "observations", "observations_too_far",
                                                   "points_waiting", "steiner_points")]
        self.assertEqual([[r[i] for i in counted] for r in bag_rows], [[r[i] for i in counted] for r in kitti_rows])
        kitti_vertices, kitti_faces, kitti_closed = mesh_counts(kitti_out)
        bag_vertices, bag_faces, bag_closed = mesh_counts(bag_out)
        self.assertTrue(kitti_closed and bag_closed)
        self.assertGreater(kitti_faces, 20000)
        self.assertLess(abs(bag_vertices - kitti_vertices), 0.01 * kitti_vertices)
        self.assertLess(abs(bag_faces - kitti_faces), 0.01 * kitti_faces)


class SyntheticLidarBagTest(BagCase):
    """LiDAR scans of the generator's sensor model (64 beams, about 120k returns a scan), thinned to
    every STEP-th return so that the test is quick: the KITTI sequence folder `generate --lidar`
    writes, that folder converted to a .tmstream (`terramesh convert`), and a bag of the stream's
    keyframes as registered float64 clouds (no `id` field: the bag reader numbers the returns as the
    KITTI reader does) posed by Odometry messages of the Velodyne frame. With the LiDAR defaults on
    (one return per 0.15 m voxel and scan, merged into the voxel's point), the folder and the bag are
    filtered by the same rule and the stream holds its result, which filtering again leaves as it is."""

    SCANS = 3
    STEP = 20

    def thinned_sequence(self):
        generated = run("generate", "street", "-o", self.path("gen"), "--length-m", "40", "--lidar",
                        "--lidar-scans", str(self.SCANS), "--quiet")
        self.assertEqual(generated.returncode, 0, generated.stderr)
        source, sequence = self.path("gen/lidar"), self.path("thin")
        os.makedirs(os.path.join(sequence, "velodyne"))
        for name in ("calib.txt", "poses.txt", "times.txt"):
            shutil.copyfile(os.path.join(source, name), os.path.join(sequence, name))
        scans = sorted(os.listdir(os.path.join(source, "velodyne")))
        self.assertEqual(scans, [f"{i:06d}.bin" for i in range(self.SCANS)])
        for name in scans:
            scan = np.fromfile(os.path.join(source, "velodyne", name), dtype="<f4").reshape(-1, 4)
            self.assertGreater(len(scan), 50000)  # the model's full scan
            scan[::self.STEP].tofile(os.path.join(sequence, "velodyne", name))
        return sequence

    def test_folder_stream_and_bag_give_one_mesh(self):
        sequence = self.thinned_sequence()
        folder_out, _ = self.mesh(sequence, "from_folder", "--quiet")
        stream = self.path("lidar.tmstream")
        converted = run("convert", sequence, stream)
        self.assertEqual(converted.returncode, 0, converted.stderr)
        self.assertIn(f"stream: {self.SCANS} events", converted.stdout)
        stream_out, _ = self.mesh(stream, "from_stream", "--quiet")
        self.assertEqual(self.file_bytes(stream_out, "mesh.ply"), self.file_bytes(folder_out, "mesh.ply"))

        keyframes = read_tmstream_keyframes(stream)
        self.assertEqual([k[0] for k in keyframes], list(range(self.SCANS)))
        # One observation per voxel and scan; later scans see earlier scans' points again (same id,
        # same position) and add new ones.
        seen = {}
        for _, _, _, observations in keyframes:
            ids = [o[0] for o in observations]
            self.assertEqual(len(set(ids)), len(ids))
            for point, x, y, z in observations:
                self.assertEqual(seen.setdefault(point, (x, y, z)), (x, y, z))
        first_ids, last_ids = ({o[0] for o in k[3]} for k in (keyframes[0], keyframes[-1]))
        self.assertGreater(len(first_ids & last_ids), 0)
        self.assertGreater(len(last_ids - first_ids), 0)
        bag_path = self.path("lidar.bag")
        with rosbag.Bag(bag_path, "w") as bag:
            for index, (_, centre, q_wxyz, observations) in enumerate(keyframes):
                time = stamp(100.0 + 0.1 * index)
                bag.write("/odom", odometry(time, "map", "velodyne", centre, q_wxyz[1:] + q_wxyz[:1]), t=time)
                columns = [(axis, FLOAT64, [o[k + 1] for o in observations]) for k, axis in enumerate("xyz")]
                bag.write("/velodyne_registered", cloud_message(columns, time, "map"), t=time)
        bag_out, stderr = self.mesh(bag_path, "from_bag")
        self.assertEqual(self.file_bytes(bag_out, "mesh.ply"), self.file_bytes(stream_out, "mesh.ply"))
        self.assertIn("no field \"id\": untracked LiDAR returns, min_views 1 advised", stderr)
        self.assertIn("one per 0.15 m voxel and scan", stderr)
        self.assertIn("sensor up axis +z (sensor frame \"velodyne\")", stderr)
        vertices, faces, closed = mesh_counts(bag_out)
        self.assertTrue(closed)
        self.assertGreater(faces, 5000)


def small_cloud(time, frame="velodyne", names=("x", "y", "z"), kind=FLOAT32, offset=0.0):
    """Four points 5 m around the sensor, with the fields `names`."""
    values = {"x": [5.0 + offset, 0.0, -5.0, 0.0], "y": [0.0, 5.0, 0.0, -5.0], "z": [0.5, 0.5, 0.5, float("nan")]}
    return cloud_message([(name, kind, values[name]) for name in names], time, frame)


class BadBagTest(BagCase):
    """Each refusal: exit 2, one line naming the bag, the topic and, for a message, its index; no output."""

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

    def test_bad_lidar_options_are_usage_errors(self):
        # LiDAR options are checked before anything is read or written (exit 2, the flag named).
        bag = self.lidar_bag()
        for options, fragment in ((("--lidar-voxel-m", "-0.1"), "--lidar-voxel-m: must be >= 0, got -0.1"),
                                  (("--lidar-max-views", "-1"), "--lidar-max-views"),
                                  (("--min-range-m", "50"), "max_range_m must exceed min_range_m")):
            out = self.path("out")
            result = run("mesh", bag, "-o", out, *options)
            self.assertEqual(result.returncode, 2, result.stderr)
            self.assertIn(fragment, result.stderr)
            self.assertFalse(os.path.exists(out))

    def test_a_good_small_bag_meshes(self):
        # The baseline of the refusals below: the same bag without the fault is read.
        out, stderr = self.mesh(self.lidar_bag(), "out")
        self.assertIn("terramesh: input: 3 non-finite points skipped", stderr)
        with open(os.path.join(out, "keyframes.csv")) as f:
            self.assertEqual(len(f.read().splitlines()), 4)
        # Another name needs --input-format rosbag, and reads the same.
        renamed = self.path("lidar.recording")
        shutil.copyfile(self.path("lidar.bag"), renamed)
        refused = run("mesh", renamed, "-o", self.path("refused"))
        self.assertEqual(refused.returncode, 2, refused.stderr)
        self.assertIn("unknown stream format \".recording\"", refused.stderr)
        named, _ = self.mesh(renamed, "named", "--input-format", "rosbag", "--quiet")
        self.assertEqual(self.file_bytes(named, "mesh.ply"), self.file_bytes(out, "mesh.ply"))
        # A compressed bag reads the same.
        compressed, _ = self.mesh(self.lidar_bag("bz2.bag", compression="bz2"), "bz2", "--quiet")
        self.assertEqual(self.file_bytes(compressed, "mesh.ply"), self.file_bytes(out, "mesh.ply"))

    def test_missing_topic(self):
        bag = self.lidar_bag()
        self.assert_refused(bag, "topic /velodyne: not in the bag (its topics: /odom (nav_msgs/Odometry, 3 messages), "
                                 "/points (sensor_msgs/PointCloud2, 3 messages))", options=["--cloud-topic", "/velodyne"])
        self.assert_refused(bag, "topic /tf: not in the bag", options=["--tf-frames", "odom", "velodyne"])

    def test_wrong_type(self):
        bag = self.lidar_bag()
        self.assert_refused(bag, "topic /points: message 0: is sensor_msgs/PointCloud2, expected nav_msgs/Odometry or "
                                 "geometry_msgs/PoseStamped", options=["--pose-topic", "/points"])
        self.assert_refused(bag, "topic /odom: message 0: is nav_msgs/Odometry, expected sensor_msgs/PointCloud2",
                            options=["--cloud-topic", "/odom"])

    def test_several_candidates_and_no_flag(self):
        two_clouds = self.lidar_bag("clouds.bag", extra=[("/points_raw", small_cloud(stamp(10.0)), 10.0)])
        self.assert_refused(two_clouds, "2 PointCloud2 topics: /points (sensor_msgs/PointCloud2, 3 messages), "
                                        "/points_raw (sensor_msgs/PointCloud2, 1 messages); choose one with --cloud-topic")
        out, stderr = self.mesh(two_clouds, "chosen", "--cloud-topic", "/points")
        self.assertIn("clouds from /points (sensor_msgs/PointCloud2, 3 messages), as --cloud-topic says", stderr)
        two_poses = self.lidar_bag("poses.bag", extra=[("/pose", pose_stamped(stamp(10.0), "odom", (0, 0, 0),
                                                                              (0, 0, 0, 1)), 10.0)])
        self.assert_refused(two_poses, "2 pose topics: /odom (nav_msgs/Odometry, 3 messages), /pose "
                                       "(geometry_msgs/PoseStamped, 1 messages); choose one with --pose-topic")

    def test_a_cloud_without_z(self):
        bag = self.lidar_bag(extra=[("/odom", odometry(stamp(13.0), "odom", "velodyne", (3, 0, 0), (0, 0, 0, 1)), 13.0),
                                    ("/points", small_cloud(stamp(13.0), names=("x", "y")), 13.0)])
        self.assert_refused(bag, "topic /points: message 3: PointCloud2 has no field \"z\"")

    def test_bad_fields_and_frames(self):
        integer_x = self.lidar_bag(extra=[("/points", cloud_message([("x", UINT32, [1]), ("y", FLOAT32, [0]),
                                                                     ("z", FLOAT32, [0])], stamp(13.0), "velodyne"), 13.0)])
        self.assert_refused(integer_x, "topic /points: message 3: PointCloud2 field \"x\" is uint32, expected float32 "
                                       "or float64")
        float_id = self.lidar_bag("id.bag", extra=[("/points", small_cloud(stamp(13.0), names=("x", "y", "z")), 13.0)])
        self.assert_refused(float_id, "topic /points: message 0: PointCloud2 field \"z\" is float32, expected one "
                                      "integer (the point id)", options=["--point-id-field", "z"])
        other_frame = self.lidar_bag("frame.bag", extra=[("/points", small_cloud(stamp(13.0), frame="base_link"), 13.0)])
        self.assert_refused(other_frame, "topic /points: message 3: PointCloud2 header.frame_id \"base_link\" differs "
                                         "from the first cloud's \"velodyne\"")
        self.mesh(other_frame, "forced", "--cloud-frame", "sensor")

    def test_not_a_bag(self):
        path = self.path("garbage.bag")
        with open(path, "wb") as f:
            f.write(b"#ROSBAG V2.0\n" + bytes(range(256)) * 4)
        self.assert_refused(path, "cannot read as a ROS 1 bag")

    def test_a_corrupt_message_header(self):
        # rosbag logs such errors through console_bridge before it throws: the run still prints one line.
        with open(self.lidar_bag(), "rb") as f:
            data = bytearray(f.read())
        first_message = data.index(b"op=\x02")
        data[first_message - 8:first_message - 4] = b"\xff\xff\xff\x7f"
        path = self.path("corrupt.bag")
        with open(path, "wb") as f:
            f.write(data)
        self.assert_refused(path, "topic /odom: message 0: cannot decode nav_msgs/Odometry: Error parsing header")

    def test_clouds_without_a_pose_are_dropped_and_counted(self):
        # Poses 1 s apart: a cloud halfway is dropped (default interval 0.2 s) or interpolated.
        messages = [("/odom", odometry(stamp(10.0), "odom", "velodyne", (0, 0, 0), (0, 0, 0, 1)), 10.0),
                    ("/odom", odometry(stamp(11.0), "odom", "velodyne", (2, 0, 0), (0, 0, 0, 1)), 11.0),
                    ("/points", small_cloud(stamp(10.0)), 10.0),
                    ("/points", small_cloud(stamp(10.5)), 10.5),
                    ("/points", small_cloud(stamp(10.75)), 10.75)]
        bag = self.write_bag("gap.bag", messages)
        out, stderr = self.mesh(bag, "dropped")
        self.assertIn("terramesh: input: 2 of 3 clouds dropped: no pose at the stamp", stderr)
        self.assertIn("terramesh: warning: most clouds were dropped (2 of 3)", stderr)
        out, stderr = self.mesh(bag, "interpolated", "--max-pose-interval-s", "2")
        self.assertNotIn("clouds dropped", stderr)
        with open(os.path.join(out, "trajectory.csv")) as f:
            rows = [line.split(",") for line in f.read().splitlines()[1:]]
        self.assertEqual([float(r[2]) for r in rows], [0.0, 1.0, 1.5])
        self.assert_refused(self.write_bag("none.bag", messages[:1] + messages[3:]),
                            "topic /points: all 2 clouds dropped: no pose at the stamp, none between two poses at most 0.2 s apart, "
                            "none within 0.01 s (the poses /odom (nav_msgs/Odometry) span 10 to 10 s)")

    def test_tf_poses(self):
        messages = []
        for i in range(3):
            t = 10.0 + i
            transform = transform_stamped(stamp(t), "/odom", "velodyne", (i, 0, 0), (0, 0, 0, 1))
            other = transform_stamped(stamp(t), "odom", "base_link", (0, 0, 0), (0, 0, 0, 1))
            messages += [("/tf", tf_message(other, transform), t), ("/points", small_cloud(stamp(t)), t)]
        bag = self.write_bag("tf.bag", messages)
        out, stderr = self.mesh(bag, "tf", "--tf-frames", "odom", "velodyne")
        self.assertIn("poses from tf on /tf (3 messages), as --tf-frames says: 2 time-varying and 0 static edges", stderr)
        self.assertIn("poses: tf odom -> velodyne; world frame \"odom\" (the world frame --tf-frames names), sensor "
                      "frame \"velodyne\"", stderr)
        with open(os.path.join(out, "trajectory.csv")) as f:
            trajectory = f.read()
        self.assertEqual([float(line.split(",")[2]) for line in trajectory.splitlines()[1:]], [0.0, 1.0, 2.0])
        self.assert_refused(bag, "--tf-frames: frame \"lidar\" is not in the tf tree of /tf (its frames: base_link, "
                                 "odom, velodyne)", options=["--tf-frames", "odom", "lidar"])
        # Without a pose topic or a flag, tf is used: the root of the clouds' frame's tree is the world.
        inferred, stderr = self.mesh(bag, "inferred")
        self.assertIn("world frame \"odom\" (the tf tree's root), sensor frame \"velodyne\"", stderr)
        with open(os.path.join(inferred, "trajectory.csv")) as f:
            self.assertEqual(f.read(), trajectory)

    def tf_tree_bag(self, name, extra_static=(), cloud_frame="velodyne", clouds=3):
        """odom -> base_link on /tf (x = i at 10 + i s), base_link -> velodyne on /tf_static, clouds in `cloud_frame`."""
        static = [transform_stamped(stamp(10.0), "base_link", "velodyne", (0, 0, 1), (0, 0, 0, 1)), *extra_static]
        messages = [("/tf_static", tf_message(*static), 10.0)]
        for i in range(3):
            t = 10.0 + i
            messages.append(("/tf", tf_message(transform_stamped(stamp(t), "odom", "base_link", (i, 0, 0),
                                                                 (0, 0, 0, 1))), t))
        for i in range(clouds):
            messages.append(("/points", small_cloud(stamp(10.0 + i), frame=cloud_frame), 10.0 + i))
        return self.write_bag(name, messages)

    def test_tf_tree_refusals(self):
        # The baseline: the chain is composed (the Velodyne 1 m above base_link) and the run says so.
        out, stderr = self.mesh(self.tf_tree_bag("tree.bag"), "tree")
        self.assertIn("poses: tf odom -> base_link -> velodyne (base_link -> velodyne static)", stderr)
        with open(os.path.join(out, "trajectory.csv")) as f:
            rows = [[float(v) for v in line.split(",")[2:5]] for line in f.read().splitlines()[1:]]
        self.assertEqual(rows, [[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [2.0, 0.0, 1.0]])
        # A cloud after the last transform is dropped and counted, not an error.
        _, stderr = self.mesh(self.tf_tree_bag("late.bag", clouds=4), "late")
        self.assertIn("terramesh: input: 1 of 4 clouds dropped: no pose at the stamp", stderr)
        self.assert_refused(self.tf_tree_bag("lidar.bag", cloud_frame="lidar"),
                            "topic /points: message 0: PointCloud2 header.frame_id \"lidar\" is not in the tf tree of "
                            "/tf, /tf_static (its frames: base_link, odom, velodyne)")
        two_parents = transform_stamped(stamp(10.0), "odom", "velodyne", (0, 0, 0), (0, 0, 0, 1))
        self.assert_refused(self.tf_tree_bag("parents.bag", extra_static=[two_parents]),
                            "topic /tf_static: message 0: tf: frame \"velodyne\" has two parents: \"base_link\" and "
                            "\"odom\"")
        cycle = transform_stamped(stamp(10.0), "velodyne", "odom", (0, 0, 0), (0, 0, 0, 1))
        self.assert_refused(self.tf_tree_bag("cycle.bag", extra_static=[cycle]),
                            "topic /tf_static: message 0: tf: the edge velodyne -> odom closes a cycle: \"odom\" is "
                            "already an ancestor of \"velodyne\"")
