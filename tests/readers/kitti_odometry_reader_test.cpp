#include "datasets/kitti_odometry_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <set>
#include <sstream>
#include <unordered_map>

#include "datasets/stream_reader.h"
#include "mesher/mesh_io.h"
#include "reader_test_util.h"
#include "test_support/temp_dir.h"

namespace terramesh::test {
namespace {

namespace fs = std::filesystem;
using datasets::KittiOdometryOptions;

const fs::path kSequence = sharedData("kitti00_lidar");
const fs::path kPoses = sharedData("kitti_poses/00.txt");

KittiOdometryOptions withPoses(const fs::path& poses = kPoses) {
  KittiOdometryOptions options;
  options.poses_path = poses;
  return options;
}

/// Nearest-neighbour distances to a point cloud, by a uniform grid: exact up to `cell_m`,
/// infinity beyond (enough for a median).
class NearestNeighbourGrid {
 public:
  NearestNeighbourGrid(const std::vector<Eigen::Vector3d>& points, double cell_m)
      : cell_m_(cell_m) {
    for (const Eigen::Vector3d& p : points) cells_[key(cell(p))].push_back(p);
  }

  double distance(const Eigen::Vector3d& q) const {
    double best_sq = std::numeric_limits<double>::infinity();
    const Eigen::Vector3i centre = cell(q);
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find(key(centre + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (const Eigen::Vector3d& p : it->second)
            best_sq = std::min(best_sq, (p - q).squaredNorm());
        }
      }
    }
    return best_sq <= cell_m_ * cell_m_ ? std::sqrt(best_sq)
                                        : std::numeric_limits<double>::infinity();
  }

 private:
  Eigen::Vector3i cell(const Eigen::Vector3d& p) const {
    return (p / cell_m_).array().floor().cast<int>();
  }
  static std::int64_t key(const Eigen::Vector3i& c) {
    return (std::int64_t{c.x()} * 73856093) ^ (std::int64_t{c.y()} * 19349663) ^
           (std::int64_t{c.z()} * 83492791);
  }
  double cell_m_;
  std::unordered_map<std::int64_t, std::vector<Eigen::Vector3d>> cells_;
};

TEST(KittiOdometryReader, ReadsEveryReturnOfTheTenScans) {
  const datasets::SlamStream stream = datasets::readKittiOdometry(kSequence, withPoses());
  const auto keyframes = keyframesOf(stream);
  ASSERT_EQ(keyframes.size(), 10u);
  const std::vector<std::size_t> returns = {124605, 124478, 124167, 123969, 123924,
                                            123373, 122765, 122123, 121357, 121018};
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    EXPECT_EQ(keyframes[k].id.value, k + 1);
    EXPECT_EQ(keyframes[k].observations.size(), returns[k]);
  }
  // Every return has its own point id.
  EXPECT_EQ(countStream(stream), (StreamCounts{10, 10, 1231779, 1231779}));
  EXPECT_EQ(stream.recommended_min_views, 1);
  EXPECT_EQ(stream.recommended_steiner_step_m, datasets::kLidarSteinerStepM);
  EXPECT_EQ(stream.sensor_up_S, Eigen::Vector3d::UnitZ());
  EXPECT_TRUE(stream.scale_known);
  EXPECT_EQ(stream.metres_per_unit, 1.0);
  EXPECT_EQ(stream.keyframe_names.at(mesher::KeyframeId{3}), "000003.bin");
  EXPECT_EQ(keyframes[0].observations[5].point.value, (std::uint64_t{1} << 32) | 5u);

  // The sensor sits about 0.27 m from cam0 (Tr's translation), and cam0 of frame 1 is at
  // (-0.04690294, -0.02839928, 0.8586941) in the world.
  const Eigen::Isometry3d tr = datasets::readKittiVelodyneToCam0(kSequence / "calib.txt");
  const double sensor_to_cam0_m = tr.inverse().translation().norm();
  EXPECT_NEAR(
      (keyframes[0].position_W_C - Eigen::Vector3d(-0.04690294, -0.02839928, 0.8586941)).norm(),
      sensor_to_cam0_m, 1e-6);
}

TEST(KittiOdometryReader, FirstScanLiesOnTheGroundTruthCloud) {
  KittiOdometryOptions options = withPoses();
  options.last_frame = 1;
  const auto keyframes = keyframesOf(datasets::readKittiOdometry(kSequence, options));
  ASSERT_EQ(keyframes.size(), 1u);
  const mesher::TriangleMesh cloud =
      mesher::readMesh(kSequence / "lidar_gt_frames01-10_cam0world_vox10cm.ply");
  ASSERT_EQ(cloud.vertices.size(), 359474u);
  EXPECT_TRUE(cloud.faces.empty());
  const NearestNeighbourGrid grid(cloud.vertices, 0.5);
  std::vector<double> distances;
  for (std::size_t i = 0; i < keyframes[0].observations.size(); i += 10) {
    distances.push_back(grid.distance(keyframes[0].observations[i].position_W));
  }
  std::nth_element(distances.begin(), distances.begin() + distances.size() / 2, distances.end());
  const double median_m = distances[distances.size() / 2];
  // The cloud is a 10 cm voxel grid of these returns and nine more scans.
  EXPECT_LT(median_m, 0.03);
  std::nth_element(distances.begin(), distances.begin() + distances.size() * 9 / 10,
                   distances.end());
  EXPECT_LT(distances[distances.size() * 9 / 10], 0.08);
}

TEST(KittiOdometryReader, FramesStepRangeAndSubsample) {
  KittiOdometryOptions options = withPoses();
  options.first_frame = 2;
  options.frame_step = 4;
  options.max_returns_per_scan = 1000;
  options.lidar.max_range_m = 20.0;
  const auto keyframes = keyframesOf(datasets::readKittiOdometry(kSequence, options));
  ASSERT_EQ(keyframes.size(), 3u);
  EXPECT_EQ(keyframes[0].id.value, 2u);
  EXPECT_EQ(keyframes[1].id.value, 6u);
  EXPECT_EQ(keyframes[2].id.value, 10u);
  for (const mesher::Keyframe& keyframe : keyframes) {
    ASSERT_EQ(keyframe.observations.size(), 1000u);
    for (const auto& observation : keyframe.observations) {
      ASSERT_LE((observation.position_W - keyframe.position_W_C).norm(), 20.0 + 1e-4);
    }
  }

  // Frame 6's subset does not depend on the other frames read; another seed gives another one.
  options.first_frame = options.last_frame = 6;
  const auto alone = keyframesOf(datasets::readKittiOdometry(kSequence, options));
  ASSERT_EQ(alone.size(), 1u);
  EXPECT_TRUE(std::equal(alone[0].observations.begin(), alone[0].observations.end(),
                         keyframes[1].observations.begin(),
                         [](const auto& a, const auto& b) { return a.point == b.point; }));
  options.seed = 2;
  const auto reseeded = keyframesOf(datasets::readKittiOdometry(kSequence, options));
  EXPECT_FALSE(std::equal(reseeded[0].observations.begin(), reseeded[0].observations.end(),
                          alone[0].observations.begin(),
                          [](const auto& a, const auto& b) { return a.point == b.point; }));
}

TEST(KittiOdometryReader, InvalidOptionsListEveryProblem) {
  KittiOdometryOptions options = withPoses();
  options.frame_step = 0;
  options.lidar.min_range_m = 5;
  options.lidar.max_range_m = 2;
  EXPECT_EQ(options.problems().size(), 2u);
  EXPECT_THROW(datasets::readKittiOdometry(kSequence, options), std::invalid_argument);
}

/// Writes the first `count` KITTI poses of sequence 00 as a TUM trajectory at times.txt's times.
void writeTumPoses(const fs::path& path, std::size_t count) {
  const auto poses = datasets::readKittiPoses(kPoses);
  const auto times = datasets::readKittiTimes(kSequence / "times.txt");
  std::ostringstream out;
  out << std::setprecision(17) << "# timestamp tx ty tz qx qy qz qw\n";
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Quaterniond q(poses[i].linear());
    const Eigen::Vector3d& t = poses[i].translation();
    out << times[i] << ' ' << t.x() << ' ' << t.y() << ' ' << t.z() << ' ' << q.x() << ' ' << q.y()
        << ' ' << q.z() << ' ' << q.w() << '\n';
  }
  writeFile(path, out.str());
}

TEST(KittiOdometryReader, TumPosesGiveTheSameStream) {
  TempDir dir;
  writeTumPoses(dir / "00_tum.txt", 11);
  KittiOdometryOptions options = withPoses(dir / "00_tum.txt");
  options.last_frame = 3;
  EXPECT_EQ(datasets::detectPoseFileFormat(dir / "00_tum.txt"), datasets::PoseFileFormat::kTum);
  const datasets::SlamStream tum = datasets::readKittiOdometry(kSequence, options);
  options.poses_path = kPoses;
  const datasets::SlamStream kitti = datasets::readKittiOdometry(kSequence, options);
  // KITTI prints rotations with 7 digits; the quaternion path re-orthonormalises them.
  EXPECT_TRUE(sameStreams(tum, kitti, 1e-4));

  // A scan with no pose within the tolerance of its time.
  writeTumPoses(dir / "00_tum.txt", 2);
  options.poses_path = dir / "00_tum.txt";
  expectErrorAt(expectInputError([&] { datasets::readKittiOdometry(kSequence, options); }),
                dir / "00_tum.txt", "", "no pose within 0.01");
}

/// A KITTI sequence folder with scans 1 and 2 (copied, so they can be damaged).
class KittiCopyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(sequence_ / "velodyne");
    for (const char* scan : {"000001.bin", "000002.bin"}) {
      writeFile(sequence_ / "velodyne" / scan, readFile(kSequence / "velodyne" / scan));
    }
    writeFile(sequence_ / "calib.txt", readFile(kSequence / "calib.txt"));
    writeFile(sequence_ / "times.txt", readFile(kSequence / "times.txt"));
    writeFile(sequence_ / "poses.txt", readFile(kPoses));
  }
  InputError read() {
    return expectInputError([&] { datasets::readKittiOdometry(sequence_); });
  }
  TempDir dir_;
  fs::path sequence_ = dir_ / "sequences" / "00";
};

TEST_F(KittiCopyTest, DetectedAndReadWithPosesInTheFolder) {
  EXPECT_EQ(datasets::detectStreamFormat(sequence_), datasets::StreamFormat::kKittiOdometry);
  EXPECT_EQ(countStream(datasets::readAnyStream(sequence_)).observations, 124605u + 124478u);
}

TEST_F(KittiCopyTest, KittiPosesNeedNoTimes) {
  const datasets::SlamStream expected = datasets::readKittiOdometry(sequence_);
  fs::remove(sequence_ / "times.txt");
  EXPECT_TRUE(sameStreams(datasets::readAnyStream(sequence_), expected));
}

TEST_F(KittiCopyTest, TumPosesWithoutTimesAreMatchedByOrder) {
  const datasets::SlamStream expected = datasets::readKittiOdometry(sequence_);
  fs::remove(sequence_ / "times.txt");
  // One TUM pose per scan (frames 1 and 2), with times that match nothing.
  const auto poses = datasets::readKittiPoses(kPoses);
  std::ostringstream out;
  out << std::setprecision(17);
  for (std::size_t frame : {1, 2}) {
    const Eigen::Quaterniond q(poses[frame].linear());
    const Eigen::Vector3d& t = poses[frame].translation();
    out << 1000.0 + static_cast<double>(frame) << ' ' << t.x() << ' ' << t.y() << ' ' << t.z()
        << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << q.w() << '\n';
  }
  writeFile(sequence_ / "poses.txt", out.str());
  EXPECT_TRUE(sameStreams(datasets::readKittiOdometry(sequence_), expected, 1e-4));
  KittiOdometryOptions second;
  second.first_frame = 2;
  const auto only_second = keyframesOf(datasets::readKittiOdometry(sequence_, second));
  ASSERT_EQ(only_second.size(), 1u);
  EXPECT_LT((only_second[0].position_W_C - keyframesOf(expected)[1].position_W_C).norm(), 1e-6);

  // A trajectory with fewer poses than scans cannot be matched without times.
  writeFile(sequence_ / "poses.txt", out.str().substr(0, out.str().find('\n') + 1));
  expectErrorAt(read(), sequence_ / "times.txt", "", "1 poses for 2 scans");
}

TEST_F(KittiCopyTest, PosesInKittisOwnLayout) {
  fs::create_directories(dir_ / "poses");
  fs::rename(sequence_ / "poses.txt", dir_ / "poses" / "00.txt");
  EXPECT_EQ(datasets::findKittiPoses(sequence_), dir_ / "poses" / "00.txt");
  EXPECT_EQ(datasets::findKittiPoses(sequence_ / ""), dir_ / "poses" / "00.txt");
  EXPECT_EQ(countStream(datasets::readKittiOdometry(sequence_)).keyframe_events, 2u);
  fs::remove(dir_ / "poses" / "00.txt");
  expectErrorAt(read(), sequence_, "", "no poses");
}

TEST_F(KittiCopyTest, ScanSizeNotAMultipleOf16) {
  const fs::path scan = sequence_ / "velodyne" / "000002.bin";
  fs::resize_file(scan, 1991648 - 3);
  expectErrorAt(read(), scan, "size 1991645 bytes", "not a multiple of 16");
}

TEST_F(KittiCopyTest, NaNInAScanNamesItsByte) {
  const fs::path scan = sequence_ / "velodyne" / "000001.bin";
  const float nan = std::numeric_limits<float>::quiet_NaN();
  patchFile(scan, 16 * 7 + 8, &nan, sizeof(nan));
  expectErrorAt(read(), scan, "byte 120 (return 7)", "expected a finite number");
}

TEST_F(KittiCopyTest, CalibWithoutTr) {
  const fs::path calib = sequence_ / "calib.txt";
  replaceLine(calib, 5, "Tx: 0 0 0");
  expectErrorAt(read(), calib, "", "no \"Tr:\" line");
  replaceLine(calib, 5, "Tr: 1 0 0 0 0 1 0 0 0 0 1");
  expectErrorAt(read(), calib, "line 5", "Tr: followed by 12 numbers");
}

TEST_F(KittiCopyTest, MalformedPoseLine) {
  const fs::path poses = sequence_ / "poses.txt";
  replaceLine(poses, 2, "9.999978e-01 5.272628e-04 -2.066935e-03 -4.690294e-02 -5.296506e-04");
  expectErrorAt(read(), poses, "line 2", "12 fields, got 5");
  replaceLine(poses, 2, "2 0 0 0 0 1 0 0 0 0 1 0");
  expectErrorAt(read(), poses, "line 2", "must be a rotation");
}

TEST_F(KittiCopyTest, ScanWithoutPose) {
  writeFile(sequence_ / "poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 1\n");
  expectErrorAt(read(), sequence_ / "poses.txt", "", "but scan");
}

TEST_F(KittiCopyTest, NoScanSelected) {
  KittiOdometryOptions options;
  options.first_frame = 50;
  expectErrorAt(expectInputError([&] { datasets::readKittiOdometry(sequence_, options); }),
                sequence_ / "velodyne", "", "no scan");
}

}  // namespace
}  // namespace terramesh::test
