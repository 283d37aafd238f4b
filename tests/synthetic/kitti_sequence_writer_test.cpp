#include "datasets/kitti_sequence_writer.h"

#include <gtest/gtest.h>

#include <variant>

#include "datasets/kitti_odometry_reader.h"
#include "datasets/lidar_simulation.h"
#include "datasets/stream_reader.h"
#include "test_support/temp_dir.h"

namespace terramesh::datasets {
namespace {

namespace fs = std::filesystem;

/// Three noisy scans of a street 1.6 m apart, taken along its trajectory.
class KittiSequenceWriterTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    StreetSceneConfig street;
    street.length_m = 60.0;
    scene_ = new SyntheticScene(buildStreetScene(street));
    const TriangleBvh bvh(scene_->ground_truth.mesh);
    LidarSimulationConfig config;
    config.speed_m_per_s = 16.0;
    const LidarSimulator simulator(scene_->ground_truth, bvh, config);
    scans_ = new std::vector<LidarScan>();
    const std::vector<Eigen::Isometry3d> poses = lidarScanPoses(*scene_, bvh, config, 3);
    for (std::size_t i = 0; i < poses.size(); ++i) scans_->push_back(simulator.scan(poses[i], i));
  }
  static void TearDownTestSuite() {
    delete scans_;
    delete scene_;
  }

  /// Writes the first `count` scans to `directory`.
  static void write(const fs::path& directory, std::size_t count) {
    KittiSequenceWriter writer(directory);
    for (std::size_t i = 0; i < count; ++i) {
      writer.addScan((*scans_)[i].returns, (*scans_)[i].T_W_S, (*scans_)[i].time_s);
    }
    writer.finish();
  }

  static std::vector<mesher::Keyframe> keyframes(const SlamStream& stream) {
    std::vector<mesher::Keyframe> result;
    for (const StreamEvent& event : stream.events)
      result.push_back(std::get<mesher::Keyframe>(event));
    return result;
  }

  static SyntheticScene* scene_;
  static std::vector<LidarScan>* scans_;
  test::TempDir dir_;
};
SyntheticScene* KittiSequenceWriterTest::scene_ = nullptr;
std::vector<LidarScan>* KittiSequenceWriterTest::scans_ = nullptr;

TEST_F(KittiSequenceWriterTest, TheReaderGetsBackPosesCalibrationAndEveryReturn) {
  ASSERT_EQ(scans_->size(), 3u);
  write(dir_.path(), 3);
  EXPECT_TRUE(isKittiSequenceDirectory(dir_.path()));
  EXPECT_EQ(detectStreamFormat(dir_.path()), StreamFormat::kKittiOdometry);
  EXPECT_TRUE(
      readKittiVelodyneToCam0(dir_ / "calib.txt").isApprox(kittiLikeVelodyneToCam0(), 1e-15));
  EXPECT_EQ(readKittiTimes(dir_ / "times.txt"), (std::vector<double>{0.0, 0.1, 0.2}));

  const std::vector<mesher::Keyframe> read = keyframes(readKittiOdometry(dir_.path()));
  ASSERT_EQ(read.size(), 3u);
  for (std::size_t k = 0; k < read.size(); ++k) {
    const LidarScan& scan = (*scans_)[k];
    ASSERT_GT(scan.returns.size(), 50000u);
    EXPECT_EQ(read[k].id.value, k);
    EXPECT_EQ(fs::file_size(dir_ / KittiSequenceWriter::scanFileName(k)), 16 * scan.returns.size());
    EXPECT_TRUE(read[k].position_W_C.isApprox(scan.T_W_S.translation(), 1e-12)) << "scan " << k;
    EXPECT_TRUE(read[k].rotation_W_C.toRotationMatrix().isApprox(scan.T_W_S.linear(), 1e-12))
        << "scan " << k;
    ASSERT_EQ(read[k].observations.size(), scan.returns.size()) << "scan " << k;
    for (std::size_t i = 0; i < scan.returns.size(); i += 97) {
      const Eigen::Vector3d expected_W = scan.T_W_S * scan.returns[i].position_S.cast<double>();
      ASSERT_LT((read[k].observations[i].position_W - expected_W).norm(), 1e-9)
          << "scan " << k << " return " << i;
    }
  }
  // The reader's thinning works on the written sequence too.
  KittiOdometryOptions thin;
  thin.max_returns_per_scan = 1000;
  for (const mesher::Keyframe& keyframe : keyframes(readKittiOdometry(dir_.path(), thin))) {
    EXPECT_EQ(keyframe.observations.size(), 1000u);
  }
}

TEST_F(KittiSequenceWriterTest, FilesAre0644AndNoTemporaryFileIsLeft) {
  write(dir_.path(), 2);
  for (const fs::path& name : {fs::path("calib.txt"), fs::path("poses.txt"), fs::path("times.txt"),
                               KittiSequenceWriter::scanFileName(1)}) {
    EXPECT_EQ(fs::status(dir_ / name).permissions() & fs::perms::all,
              fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read |
                  fs::perms::others_read)
        << name;
  }
  for (const auto& entry : fs::recursive_directory_iterator(dir_.path())) {
    EXPECT_NE(entry.path().filename().string().front(), '.')
        << "temporary file left: " << entry.path();
  }
}

TEST_F(KittiSequenceWriterTest, RewritingAShorterSequenceDropsTheOldScans) {
  write(dir_.path(), 3);
  fs::copy_file(dir_ / "poses.txt", dir_ / "velodyne" / "notes.txt");  // not a scan: kept
  KittiSequenceWriter writer(dir_.path());
  EXPECT_FALSE(isKittiSequenceDirectory(dir_.path()))
      << "no calib.txt until the new sequence is complete";
  writer.addScan((*scans_)[2].returns, (*scans_)[2].T_W_S, 0.0);
  writer.finish();
  EXPECT_THROW(writer.finish(), std::logic_error);
  EXPECT_FALSE(fs::exists(dir_ / KittiSequenceWriter::scanFileName(1)));
  EXPECT_FALSE(fs::exists(dir_ / KittiSequenceWriter::scanFileName(2)));
  EXPECT_TRUE(fs::exists(dir_ / "velodyne" / "notes.txt"));
  const std::vector<mesher::Keyframe> read = keyframes(readKittiOdometry(dir_.path()));
  ASSERT_EQ(read.size(), 1u);
  EXPECT_EQ(read[0].observations.size(), (*scans_)[2].returns.size());
  EXPECT_TRUE(read[0].position_W_C.isApprox((*scans_)[2].T_W_S.translation(), 1e-12));
}

TEST_F(KittiSequenceWriterTest, FinishWithoutScansIsAnError) {
  KittiSequenceWriter writer(dir_.path());
  EXPECT_THROW(writer.finish(), std::logic_error);
  EXPECT_FALSE(isKittiSequenceDirectory(dir_.path()));
}

}  // namespace
}  // namespace terramesh::datasets
