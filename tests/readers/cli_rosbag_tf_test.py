"""ROS 1 bags posed by the tf tree through `terramesh mesh BAG.bag` (test bags written with Debian's
python3-rosbag):

- TfTreeBagTest: the synthetic camera stream as a robot records it: clouds in the camera's frame, posed by
  odom -> base_link on /tf (or an Odometry of base_link) and base_link -> camera on /tf_static; the
  composed chain gives the stream's mesh (vertices within 1e-9 m: see the class for why not bytes).
- BadTfBagTest: tf with --tf-frames and inferred, a chain composed, a late cloud dropped; refused: a cloud
  frame not in the tree, a frame with two parents, a cycle.

Run by ctest with the system Python (python3-rosbag): /usr/bin/python3 -m unittest cli_rosbag_tf_test
(TERRAMESH_BIN and TERRAMESH_SHARED_DIR set).
"""
import os

import numpy as np
import rosbag

from rosbag_test_util import (BadBagCase, StreetStreamCase, mesh_counts, odometry, quaternion_xyzw,
    read_ply_vertices, rotation_matrix, run, small_cloud, stamp, tf_message, transform_stamped)


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


class BadTfBagTest(BadBagCase):
    """Poses from tf, and the tf trees a bag may break."""

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
