// Driven-ground samples (PointKind::kDrivenGround) in the mesher: one view inserts them, a re-sent
// keyframe moves them, removing their keyframe removes them, the surface counts them per face,
// and checkpoints and PLY files keep the kind; their undersides (PointKind::kDrivenUnderside) trace no ray.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "common/input_error.h"
#include "mesher/checkpoint.h"
#include "mesher/mesh_io.h"
#include "mesher/mesher.h"
#include "test_support/analytic_scenes.h"
#include "test_support/temp_dir.h"

namespace terramesh::mesher {
namespace {

constexpr std::uint64_t kDrivenBit = std::uint64_t{1} << 63;
constexpr double kCameraHeight = 3.0;  // planeScene's cameras are 3 m above z = 0

PointId sampleId(std::uint64_t keyframe, std::uint64_t index) { return PointId{kDrivenBit | keyframe << 6 | index}; }

/// Five samples on z = 0 under the camera (centre and four corners of a 1 m square), shifted by `offset`.
std::vector<PointObservation> samplesUnder(const Keyframe& keyframe, const Eigen::Vector3d& offset = Eigen::Vector3d::Zero()) {
  const Eigen::Vector3d centre = keyframe.position_W_C - Eigen::Vector3d(0, 0, kCameraHeight) + offset;
  const Eigen::Vector3d corners[] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, -0.5, 0}, {-0.5, 0.5, 0}, {-0.5, -0.5, 0}};
  std::vector<PointObservation> samples;
  for (std::uint64_t i = 0; i < 5; ++i) {
    samples.push_back({sampleId(keyframe.id.value, i), centre + corners[i], PointKind::kDrivenGround});
  }
  return samples;
}

Keyframe withSamples(Keyframe keyframe, const Eigen::Vector3d& offset = Eigen::Vector3d::Zero()) {
  const std::vector<PointObservation> samples = samplesUnder(keyframe, offset);
  keyframe.observations.insert(keyframe.observations.end(), samples.begin(), samples.end());
  return keyframe;
}

MesherConfig planeConfig() {
  MesherConfig config = MesherConfig::forMode(MesherMode::kProposed);
  config.steiner_step_m = 4.0;
  return config;
}

std::vector<Keyframe> planeKeyframes() { return test::planeScene(test::SceneOptions{}).keyframes; }

void expectHealthy(const Mesher& mesher, const std::string& where) {
  const InvariantReport report = mesher.checkInvariants();
  EXPECT_TRUE(report.ok()) << where << ": " << report.summary();
  const MeshTopology topology = analyzeTopology(mesher.extractMesh());
  EXPECT_TRUE(topology.isClosedManifold()) << where;
}

/// Positions of the mesh's vertices by key value (point keys only).
std::unordered_map<std::uint64_t, Eigen::Vector3d> pointVertices(const TriangleMesh& mesh) {
  std::unordered_map<std::uint64_t, Eigen::Vector3d> positions;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!mesh.vertex_keys[v].steiner) positions[mesh.vertex_keys[v].value] = mesh.vertices[v];
  }
  return positions;
}

TEST(DrivenGroundTest, OneViewInsertsASampleWhileASlamPointWaitsForMinViews) {
  MesherConfig config = planeConfig();
  config.min_views = 2;
  Mesher mesher(config);
  Keyframe keyframe = planeKeyframes().front();
  keyframe.observations = {{PointId{1}, keyframe.position_W_C + Eigen::Vector3d(5, 0, -3), PointKind::kSlam}};
  const UpdateStats stats = mesher.integrateKeyframe(withSamples(keyframe));
  EXPECT_EQ(mesher.size().inserted_points, 5u);
  EXPECT_EQ(stats.points_waiting, 1u);
  expectHealthy(mesher, "one keyframe");
}

TEST(DrivenGroundTest, FacesCountTheirDrivenVerticesAndTheMeshFlagsThem) {
  Mesher mesher(planeConfig());
  for (const Keyframe& keyframe : planeKeyframes()) mesher.integrateKeyframe(withSamples(keyframe));
  expectHealthy(mesher, "whole scene");
  std::size_t driven_faces = 0;
  for (const SurfaceFace& face : mesher.surfaceFaces()) {
    int expected = 0;
    for (const VertexKey& key : face.vertices) expected += !key.steiner && (key.value & kDrivenBit) != 0;
    EXPECT_EQ(face.driven_vertices, expected);
    driven_faces += face.driven_vertices > 0;
  }
  EXPECT_GT(driven_faces, 20u);
  const TriangleMesh mesh = mesher.extractMesh();
  ASSERT_EQ(mesh.driven_kind.size(), mesh.vertices.size());
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const bool driven = !mesh.vertex_keys[v].steiner && (mesh.vertex_keys[v].value & kDrivenBit) != 0;
    EXPECT_EQ(mesh.driven_kind[v] != 0, driven);
    if (driven) EXPECT_NEAR(mesh.vertices[v].z(), 0.0, 1e-12);
  }
}

TEST(DrivenGroundTest, ResentKeyframeMovesItsSamplesAndRemovingItRemovesThem) {
  const std::vector<Keyframe> keyframes = planeKeyframes();
  Mesher mesher(planeConfig());
  for (const Keyframe& keyframe : keyframes) mesher.integrateKeyframe(withSamples(keyframe));
  const Keyframe& moved = keyframes[12];
  const Eigen::Vector3d correction(0.2, 0.4, 0.05);
  Keyframe corrected = moved;
  corrected.position_W_C += correction;
  mesher.integrateKeyframe(withSamples(corrected, Eigen::Vector3d::Zero()));
  expectHealthy(mesher, "after the correction");
  const auto positions = pointVertices(mesher.extractMesh());
  std::size_t on_surface = 0;
  for (const PointObservation& sample : samplesUnder(corrected)) {
    const auto it = positions.find(sample.point.value);
    if (it == positions.end()) continue;
    ++on_surface;
    EXPECT_EQ(it->second, sample.position_W) << "sample " << sample.point.value;
  }
  EXPECT_GE(on_surface, 3u);

  const std::size_t points_before = mesher.size().points;
  mesher.removeKeyframe(moved.id);
  expectHealthy(mesher, "after the removal");
  const auto after = pointVertices(mesher.extractMesh());
  for (std::uint64_t i = 0; i < 5; ++i) EXPECT_EQ(after.count(sampleId(moved.id.value, i).value), 0u);
  // Its samples and the SLAM points only it observed are gone; at least the five samples.
  EXPECT_LE(mesher.size().points + 5, points_before);
}

TEST(DrivenGroundTest, AnotherKindForAKnownPointIsRefusedBeforeAnythingChanges) {
  Mesher mesher(planeConfig());
  const std::vector<Keyframe> keyframes = planeKeyframes();
  mesher.integrateKeyframe(withSamples(keyframes[0]));
  const std::uint64_t revision = mesher.revision();
  Keyframe wrong = keyframes[1];
  wrong.observations.push_back({sampleId(keyframes[0].id.value, 0), Eigen::Vector3d(0, 0, 0), PointKind::kSlam});
  EXPECT_THROW(mesher.integrateKeyframe(wrong), std::invalid_argument);
  EXPECT_EQ(mesher.revision(), revision);
  EXPECT_EQ(mesher.size().keyframes, 1u);
}

TEST(DrivenGroundTest, CheckpointKeepsTheKind) {
  const std::vector<Keyframe> keyframes = planeKeyframes();
  Mesher mesher(planeConfig());
  for (std::size_t k = 0; k < 16; ++k) mesher.integrateKeyframe(withSamples(keyframes[k]));
  std::stringstream bytes;
  saveCheckpoint(mesher, bytes, "");
  LoadedCheckpoint loaded = loadCheckpoint(bytes, "memory");
  Mesher& resumed = loaded.mesher;
  EXPECT_EQ(resumed.extractMesh().driven_kind, mesher.extractMesh().driven_kind);
  // The kind came back: re-observing a sample as a SLAM point is still refused.
  Keyframe wrong = keyframes[16];
  wrong.observations.push_back({sampleId(keyframes[3].id.value, 1), Eigen::Vector3d(0, 0, 0), PointKind::kSlam});
  EXPECT_THROW(resumed.integrateKeyframe(wrong), std::invalid_argument);
  // Both continue alike: single-view samples of the next keyframes are inserted in both.
  for (std::size_t k = 16; k < keyframes.size(); ++k) {
    const UpdateStats a = mesher.integrateKeyframe(withSamples(keyframes[k]));
    const UpdateStats b = resumed.integrateKeyframe(withSamples(keyframes[k]));
    EXPECT_EQ(a.new_points, b.new_points) << "keyframe " << k;
  }
  const TriangleMesh expected = mesher.extractMesh();
  const TriangleMesh actual = resumed.extractMesh();
  EXPECT_EQ(actual.vertices, expected.vertices);
  EXPECT_EQ(actual.faces, expected.faces);
  EXPECT_EQ(actual.driven_kind, expected.driven_kind);
  std::vector<std::uint8_t> counts_a, counts_b;
  for (const SurfaceFace& face : mesher.surfaceFaces()) counts_a.push_back(face.driven_vertices);
  for (const SurfaceFace& face : resumed.surfaceFaces()) counts_b.push_back(face.driven_vertices);
  EXPECT_EQ(counts_a, counts_b);
  EXPECT_GT(std::count_if(counts_a.begin(), counts_a.end(), [](std::uint8_t c) { return c > 0; }), 0);
}

/// `keyframe` with its samples and their undersides, `depth` below each (ids: index + 32).
Keyframe withUndersides(Keyframe keyframe, double depth) {
  const std::vector<PointObservation> samples = samplesUnder(keyframe);
  for (PointObservation sample : samples) {
    keyframe.observations.push_back(sample);
    sample.point.value += 32;
    sample.position_W.z() -= depth;
    sample.kind = PointKind::kDrivenUnderside;
    keyframe.observations.push_back(sample);
  }
  return keyframe;
}

TEST(DrivenGroundTest, UndersidesGoInWithOneViewTraceNoRayAndComeBackFromACheckpoint) {
  const std::vector<Keyframe> keyframes = planeKeyframes();
  Mesher plain(planeConfig()), with(planeConfig());
  for (std::size_t k = 0; k < 16; ++k) {
    plain.integrateKeyframe(withSamples(keyframes[k]));
    with.integrateKeyframe(withUndersides(keyframes[k], 0.1));
  }
  expectHealthy(with, "with undersides");  // checkInvariants: every point has the rays it calls for
  // One vertex per underside, and not one ray more: they carve nothing.
  EXPECT_EQ(with.size().inserted_points, plain.size().inserted_points + 16 * 5);
  EXPECT_EQ(with.size().rays, plain.size().rays);
  // Undersides are not driven ground: faces do not count them.
  for (const SurfaceFace& face : with.surfaceFaces()) {
    int expected = 0;
    for (const VertexKey& key : face.vertices) expected += !key.steiner && (key.value & kDrivenBit) != 0 && (key.value & 63) < 32;
    EXPECT_EQ(face.driven_vertices, expected);
  }

  std::stringstream bytes;
  saveCheckpoint(with, bytes, "");
  LoadedCheckpoint loaded = loadCheckpoint(bytes, "memory");
  for (std::size_t k = 16; k < keyframes.size(); ++k) {
    with.integrateKeyframe(withUndersides(keyframes[k], 0.1));
    loaded.mesher.integrateKeyframe(withUndersides(keyframes[k], 0.1));
  }
  expectHealthy(loaded.mesher, "resumed");
  EXPECT_EQ(loaded.mesher.size().rays, with.size().rays);
  EXPECT_EQ(loaded.mesher.extractMesh().vertices, with.extractMesh().vertices);
  EXPECT_EQ(loaded.mesher.extractMesh().faces, with.extractMesh().faces);
  // Removing their keyframe removes them with the samples.
  const std::size_t points_before = with.size().points;
  with.removeKeyframe(keyframes[12].id);
  expectHealthy(with, "after the removal");
  EXPECT_LE(with.size().points + 10, points_before);
}

std::string plyHeader(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string header, line;
  while (std::getline(in, line) && line != "end_header") header += line + "\n";
  return header;
}

TEST(DrivenGroundTest, PlyWritesTheDrivenFlagOnlyWhenSomeVertexIsDrivenAndReadsItBack) {
  const test::TempDir dir;
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  mesh.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  mesh.is_steiner = {0, 0, 1, 0};
  mesh.driven_kind = {1, 0, 0, 2};  // a driven-ground sample and the underside under one
  writePly(dir / "driven.ply", mesh);
  EXPECT_NE(plyHeader(dir / "driven.ply").find("property uchar driven"), std::string::npos);
  const TriangleMesh back = readMesh(dir / "driven.ply");
  EXPECT_EQ(back.driven_kind, mesh.driven_kind);
  EXPECT_EQ(back.is_steiner, mesh.is_steiner);

  mesh.driven_kind = {0, 0, 0, 0};
  writePly(dir / "plain.ply", mesh);
  mesh.driven_kind.clear();
  writePly(dir / "unflagged.ply", mesh);
  EXPECT_EQ(plyHeader(dir / "plain.ply").find("driven"), std::string::npos);
  std::ifstream a(dir / "plain.ply", std::ios::binary), b(dir / "unflagged.ply", std::ios::binary);
  const std::string bytes_a((std::istreambuf_iterator<char>(a)), std::istreambuf_iterator<char>());
  const std::string bytes_b((std::istreambuf_iterator<char>(b)), std::istreambuf_iterator<char>());
  EXPECT_EQ(bytes_a, bytes_b);
  EXPECT_TRUE(readMesh(dir / "plain.ply").driven_kind.empty());
}

TEST(DrivenGroundTest, PlyWithADrivenValueNoPointKindHasIsAnInputError) {
  const test::TempDir dir;
  std::ofstream(dir / "bad.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                    "property float z\nproperty uchar driven\nelement face 1\n"
                                    "property list uchar int vertex_indices\nend_header\n"
                                    "0 0 0 1\n1 0 0 2\n0 1 0 3\n3 0 1 2\n";
  try {
    readMesh(dir / "bad.ply");
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.where(), "vertex 2");
    EXPECT_NE(error.problem().find("expected 0, 1 driven ground or 2 its underside"), std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace terramesh::mesher
