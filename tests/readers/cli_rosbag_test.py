"""ROS 1 bags through `terramesh mesh BAG.bag`: test bags written with Debian's python3-rosbag (no ROS
master), meshed and compared with the same data read by terramesh's other readers.

- SyntheticBagTest: a synthetic camera stream written as registered PointCloud2s (float64 x y z and an
  `id` field) with an Odometry at each stamp gives a byte-identical mesh.ply to the .tmstream.
- KittiBagTest: KITTI Velodyne scans in the sensor frame with Odometry from the KITTI poses, against the
  KITTI reader on the same scans (see the test for why the meshes are close, not identical).
- SyntheticLidarBagTest: the generator's LiDAR model (`generate --lidar`, a KITTI sequence folder),
  converted to a .tmstream and written as registered clouds with an Odometry per scan: the folder,
  the stream and the bag give one byte-identical mesh.ply.
- BadBagTest: missing topic, wrong type, several candidates, a cloud without z, no pose near a cloud.
Bags posed by the tf tree: cli_rosbag_tf_test.py.

Run by ctest with the system Python (python3-rosbag): /usr/bin/python3 -m unittest cli_rosbag_test
(TERRAMESH_BIN and TERRAMESH_SHARED_DIR set).
"""
import os
import re
import shutil

import numpy as np
import rosbag
from std_msgs.msg import String

from rosbag_test_util import (BadBagCase, BagCase, FLOAT32, FLOAT64, LIDAR, POSES, StreetStreamCase, UINT32,
    cloud_message, mesh_counts, odometry, pose_stamped, quaternion_xyzw, read_points_ply,
    read_tmstream_keyframes, run, small_cloud, stamp)


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


class BadBagTest(BadBagCase):
    """Each refusal: exit 2, one line naming the bag, the topic and, for a message, its index; no output."""

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
