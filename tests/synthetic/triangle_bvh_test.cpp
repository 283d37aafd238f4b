#include "datasets/triangle_bvh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <thread>

namespace terramesh::datasets {
namespace {

using mesher::TriangleMesh;

/// Möller-Trumbore, two-sided, written independently of the tree as an oracle.
std::optional<double> bruteRayTriangle(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-14) return std::nullopt;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) / det;
  if (u < 0 || u > 1) return std::nullopt;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = d.dot(q) / det;
  if (v < 0 || u + v > 1) return std::nullopt;
  const double t = e2.dot(q) / det;
  if (t < 0) return std::nullopt;
  return t;
}

struct BruteHit {
  double distance = std::numeric_limits<double>::infinity();
  std::uint32_t face = 0;
};

BruteHit bruteFirstHit(const TriangleMesh& mesh, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double max_distance) {
  BruteHit best;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& face = mesh.faces[f];
    const auto t = bruteRayTriangle(o, d, mesh.vertices[face[0]], mesh.vertices[face[1]], mesh.vertices[face[2]]);
    if (t && *t <= max_distance && *t < best.distance) best = {*t, static_cast<std::uint32_t>(f)};
  }
  return best;
}

/// Brute-force closest distance by dense barycentric sampling is too weak; use projection onto
/// the plane plus the three edges instead.
double bruteClosestDistance(const TriangleMesh& mesh, const Eigen::Vector3d& p) {
  auto segment = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    return (a + t * (b - a) - p).norm();
  };
  double best = std::numeric_limits<double>::infinity();
  for (const auto& face : mesh.faces) {
    const Eigen::Vector3d &a = mesh.vertices[face[0]], &b = mesh.vertices[face[1]], &c = mesh.vertices[face[2]];
    best = std::min({best, segment(a, b), segment(b, c), segment(c, a)});
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    const Eigen::Vector3d q = p - n.dot(p - a) * n;
    const bool inside = (b - a).cross(q - a).dot(n) >= 0 && (c - b).cross(q - b).dot(n) >= 0 &&
                        (a - c).cross(q - c).dot(n) >= 0;
    if (inside) best = std::min(best, (q - p).norm());
  }
  return best;
}

TriangleMesh randomSoup(int triangles, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> position(-10, 10), offset(-1.5, 1.5);
  TriangleMesh mesh;
  for (int i = 0; i < triangles; ++i) {
    const Eigen::Vector3d centre(position(rng), position(rng), position(rng));
    for (int k = 0; k < 3; ++k) mesh.vertices.push_back(centre + Eigen::Vector3d(offset(rng), offset(rng), offset(rng)));
    const auto base = static_cast<std::uint32_t>(3 * i);
    mesh.faces.push_back({base, base + 1, base + 2});
  }
  return mesh;
}

/// The surface of [-1, 1]^3, each face split into n x n squares, vertices shared, wound outwards.
TriangleMesh gridCube(int n) {
  TriangleMesh mesh;
  std::map<std::array<int, 3>, std::uint32_t> index;
  auto vertex = [&](const std::array<int, 3>& key) {
    const auto [it, inserted] = index.emplace(key, static_cast<std::uint32_t>(mesh.vertices.size()));
    if (inserted) mesh.vertices.emplace_back(2.0 * key[0] / n - 1, 2.0 * key[1] / n - 1, 2.0 * key[2] / n - 1);
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis) {
    for (const int side : {0, n}) {
      const int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          auto key = [&](int du, int dv) {
            std::array<int, 3> k{};
            k[static_cast<std::size_t>(axis)] = side;
            k[static_cast<std::size_t>(u_axis)] = i + du;
            k[static_cast<std::size_t>(v_axis)] = j + dv;
            return vertex(k);
          };
          const std::uint32_t a = key(0, 0), b = key(1, 0), c = key(1, 1), d = key(0, 1);
          if (side == n) {
            mesh.faces.push_back({a, b, c});
            mesh.faces.push_back({a, c, d});
          } else {
            mesh.faces.push_back({a, c, b});
            mesh.faces.push_back({a, d, c});
          }
        }
      }
    }
  }
  return mesh;
}

TEST(TriangleBvhTest, RandomRaysMatchBruteForce) {
  const TriangleMesh mesh = randomSoup(3000, 11);
  const TriangleBvh bvh(mesh);
  EXPECT_EQ(bvh.faceCount(), 3000u);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> position(-14, 14);
  std::normal_distribution<double> normal;
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d origin(position(rng), position(rng), position(rng));
    const Eigen::Vector3d direction = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    const double max_distance = i % 3 == 0 ? 8.0 : std::numeric_limits<double>::infinity();
    const BruteHit expected = bruteFirstHit(mesh, origin, direction, max_distance);
    const std::optional<RayHit> hit = bvh.firstHit(origin, 3.0 * direction, max_distance);
    ASSERT_EQ(hit.has_value(), std::isfinite(expected.distance)) << "ray " << i;
    if (!hit) continue;
    ++hits;
    EXPECT_NEAR(hit->distance, expected.distance, 1e-9) << "ray " << i;
    EXPECT_EQ(hit->face, expected.face) << "ray " << i;
    EXPECT_NEAR((hit->point - (origin + expected.distance * direction)).norm(), 0.0, 1e-9);
    // The segment to just short of the first hit is free; to beyond it, occluded.
    EXPECT_FALSE(bvh.segmentOccluded(origin, origin + 0.999 * hit->distance * direction, 1e-6));
    EXPECT_TRUE(bvh.segmentOccluded(origin, origin + (hit->distance + 0.01) * direction, 1e-6));
  }
  EXPECT_GT(hits, 500);
}

TEST(TriangleBvhTest, ClosestPointMatchesBruteForce) {
  const TriangleMesh mesh = randomSoup(800, 3);
  const TriangleBvh bvh(mesh);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> position(-15, 15);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d query(position(rng), position(rng), position(rng));
    const SurfacePoint closest = bvh.closestPoint(query);
    EXPECT_NEAR(closest.distance, bruteClosestDistance(mesh, query), 1e-9) << "query " << i;
    EXPECT_NEAR((closest.point - query).norm(), closest.distance, 1e-12);
    const auto& face = mesh.faces[closest.face];
    const TriangleMesh single{{mesh.vertices[face[0]], mesh.vertices[face[1]], mesh.vertices[face[2]]}, {{0, 1, 2}}, {}, {}};
    EXPECT_NEAR(bruteClosestDistance(single, query), closest.distance, 1e-9) << "the reported face holds the point";
  }
}

TEST(TriangleBvhTest, FacesWithinMatchBruteForce) {
  const TriangleMesh mesh = randomSoup(800, 4);
  const TriangleBvh bvh(mesh);
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> position(-15, 15);
  std::uniform_real_distribution<double> radius(0.0, 6.0);
  std::size_t found = 0;
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d centre(position(rng), position(rng), position(rng));
    const double r = radius(rng);
    std::vector<std::uint32_t> expected;
    for (std::uint32_t f = 0; f < mesh.faces.size(); ++f) {
      const auto& face = mesh.faces[f];
      const TriangleMesh single{{mesh.vertices[face[0]], mesh.vertices[face[1]], mesh.vertices[face[2]]}, {{0, 1, 2}}, {}, {}};
      if (bruteClosestDistance(single, centre) <= r) expected.push_back(f);
    }
    EXPECT_EQ(bvh.facesWithin(centre, r), expected) << "query " << i;
    found += expected.size();
  }
  EXPECT_GT(found, 300u);  // the queries do reach faces
  EXPECT_TRUE(bvh.facesWithin({0, 0, 0}, -1.0).empty());
  EXPECT_TRUE(TriangleBvh(TriangleMesh{}).facesWithin({0, 0, 0}, 1.0).empty());
  EXPECT_THROW(bvh.facesWithin({NAN, 0, 0}, 1.0), std::invalid_argument);
  EXPECT_THROW(bvh.facesWithin({0, 0, 0}, INFINITY), std::invalid_argument);
}

TEST(TriangleBvhTest, DoublePrecisionFarFromTheOrigin) {
  // Embree stores floats (0.5 mm steps at 1e4 m); the answers are refined in double on the faces
  // it reports, so they match the double-precision oracle to 1e-9 m even here.
  TriangleMesh mesh = randomSoup(1500, 21);
  const Eigen::Vector3d offset(1.0e4, -2.0e4, 3.0e3);
  for (Eigen::Vector3d& v : mesh.vertices) v += offset;
  const TriangleBvh bvh(mesh);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> position(-14, 14);
  std::normal_distribution<double> normal;
  int hits = 0;
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d origin = offset + Eigen::Vector3d(position(rng), position(rng), position(rng));
    const Eigen::Vector3d direction = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    const BruteHit expected = bruteFirstHit(mesh, origin, direction, 30.0);
    const std::optional<RayHit> hit = bvh.firstHit(origin, direction, 30.0);
    ASSERT_EQ(hit.has_value(), std::isfinite(expected.distance)) << "ray " << i;
    if (hit) {
      ++hits;
      EXPECT_NEAR(hit->distance, expected.distance, 1e-9) << "ray " << i;
      EXPECT_EQ(hit->face, expected.face) << "ray " << i;
    }
    EXPECT_NEAR(bvh.closestPoint(origin).distance, bruteClosestDistance(mesh, origin), 1e-9) << "query " << i;
  }
  EXPECT_GT(hits, 200);
}

TEST(TriangleBvhTest, ClosedCubeIsWatertightThroughVerticesAndEdges) {
  const int n = 6;
  const TriangleMesh cube = gridCube(n);
  const TriangleBvh bvh(cube);
  // Rays from inside aimed exactly at every vertex and every edge midpoint of the tessellation.
  const Eigen::Vector3d origins[] = {{0, 0, 0}, {0.1, -0.3, 0.2}, {1.0 / 3, 1.0 / 3, -1.0 / 3}};
  int rays = 0;
  for (const Eigen::Vector3d& origin : origins) {
    for (const auto& face : cube.faces) {
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d& a = cube.vertices[face[static_cast<std::size_t>(k)]];
        const Eigen::Vector3d& b = cube.vertices[face[static_cast<std::size_t>((k + 1) % 3)]];
        for (const Eigen::Vector3d& target : {a, Eigen::Vector3d((a + b) / 2)}) {
          const std::optional<RayHit> hit = bvh.firstHit(origin, target - origin);
          ASSERT_TRUE(hit.has_value()) << "ray leaked through a seam towards " << target.transpose();
          EXPECT_NEAR(hit->distance, (target - origin).norm(), 1e-12);
          ++rays;
        }
      }
    }
  }
  EXPECT_GT(rays, 2000);
}

TEST(TriangleBvhTest, AnalyticDistancesToCubeAndPlane) {
  const TriangleBvh bvh(gridCube(4));
  std::mt19937 rng(1);
  std::normal_distribution<double> normal;
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d d = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    const double expected = 1.0 / d.cwiseAbs().maxCoeff();  // from the centre to the surface of [-1, 1]^3
    const auto hit = bvh.firstHit(Eigen::Vector3d::Zero(), d);
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->distance, expected, 1e-12);
    // Outside points: distance to the box; inside points: distance to the nearest face.
    const Eigen::Vector3d outside = 3.0 * d;
    EXPECT_NEAR(bvh.closestPoint(outside).distance,
                (outside.cwiseAbs() - Eigen::Vector3d::Ones()).cwiseMax(0.0).norm(), 1e-12);
    const Eigen::Vector3d inside = 0.5 * d;
    EXPECT_NEAR(bvh.closestPoint(inside).distance, 1.0 - inside.cwiseAbs().maxCoeff(), 1e-12);
  }
  // A plane z = 0 seen from 2 m up at 30 degrees of depression: 4 m along the ray.
  TriangleMesh plane;
  plane.vertices = {{-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0}};
  plane.faces = {{0, 1, 2}, {0, 2, 3}};
  const TriangleBvh ground(plane);
  const auto hit = ground.firstHit({0, 0, 2}, {std::cos(M_PI / 6), 0, -std::sin(M_PI / 6)});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->distance, 4.0, 1e-12);
  EXPECT_FALSE(ground.firstHit({0, 0, 2}, {1, 0, -0.5}, 3.0).has_value()) << "beyond max_distance";
  EXPECT_FALSE(ground.firstHit({0, 0, 2}, {0, 0, 1}).has_value()) << "pointing away";
  EXPECT_TRUE(ground.firstHit({0, 0, -2}, {0, 0, 1}).has_value()) << "faces are hit from both sides";
}

TEST(TriangleBvhTest, SegmentToleranceIgnoresTheSurfaceAtTheEnds) {
  TriangleMesh plane;
  plane.vertices = {{-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}};
  plane.faces = {{0, 1, 2}, {0, 2, 3}};
  const TriangleBvh bvh(plane);
  EXPECT_FALSE(bvh.segmentOccluded({0, 0, 5}, {3, 1, 0}, 1e-3)) << "the end point lies on the surface";
  EXPECT_TRUE(bvh.segmentOccluded({0, 0, 5}, {3, 1, -1}, 1e-3));
  EXPECT_FALSE(bvh.segmentOccluded({0, 0, 5}, {0, 0, 5.0001}, 1e-3)) << "shorter than twice the tolerance";
}

TEST(TriangleBvhTest, TiesGoToTheLowestFaceIndex) {
  TriangleMesh mesh;
  mesh.vertices = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  mesh.faces = {{0, 1, 2}, {1, 2, 0}, {0, 2, 1}};
  const TriangleBvh bvh(mesh);
  EXPECT_EQ(bvh.firstHit({0, 0, 1}, {0, 0, -1})->face, 0u);
  EXPECT_EQ(bvh.closestPoint({0.1, 0.1, 3}).face, 0u);
}

TEST(TriangleBvhTest, DegenerateAndBadInput) {
  const TriangleBvh empty{TriangleMesh{}};
  EXPECT_EQ(empty.faceCount(), 0u);
  EXPECT_FALSE(empty.firstHit({0, 0, 0}, {1, 0, 0}).has_value());
  EXPECT_FALSE(empty.segmentOccluded({0, 0, 0}, {1, 0, 0}, 0.0));
  EXPECT_THROW(empty.closestPoint({0, 0, 0}), std::logic_error);

  TriangleMesh sliver;  // collinear: never hit by rays, still has a closest point
  sliver.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  sliver.faces = {{0, 1, 2}};
  const TriangleBvh line(sliver);
  EXPECT_FALSE(line.firstHit({1, 0, 1}, {0, 0, -1}).has_value());
  EXPECT_NEAR(line.closestPoint({1.5, 2, 0}).distance, 2.0, 1e-12);
  EXPECT_NEAR(line.closestPoint({3, 0, 0}).distance, 1.0, 1e-12);

  EXPECT_THROW(line.firstHit({0, 0, 0}, {0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(line.firstHit({NAN, 0, 0}, {1, 0, 0}), std::invalid_argument);
  EXPECT_THROW(line.segmentOccluded({0, 0, 0}, {1, 0, 0}, -1.0), std::invalid_argument);
  EXPECT_THROW(line.closestPoint({INFINITY, 0, 0}), std::invalid_argument);
  TriangleMesh bad = sliver;
  bad.faces = {{0, 1, 7}};
  EXPECT_THROW(TriangleBvh{bad}, std::invalid_argument);
  bad = sliver;
  bad.vertices[1].x() = NAN;
  EXPECT_THROW(TriangleBvh{bad}, std::invalid_argument);
}

TEST(TriangleBvhTest, ConcurrentQueriesAgreeWithSequentialOnes) {
  const TriangleMesh mesh = randomSoup(5000, 2);
  const TriangleBvh bvh(mesh);
  std::vector<Eigen::Vector3d> directions;
  std::mt19937 rng(4);
  std::normal_distribution<double> normal;
  for (int i = 0; i < 4000; ++i) directions.emplace_back(normal(rng), normal(rng), normal(rng));
  auto run = [&](std::size_t begin, std::size_t end, std::vector<double>& out) {
    for (std::size_t i = begin; i < end; ++i) {
      const auto hit = bvh.firstHit(Eigen::Vector3d::Zero(), directions[i]);
      out[i] = (hit ? hit->distance : -1.0) + bvh.closestPoint(directions[i] * 5).distance;
    }
  };
  std::vector<double> sequential(directions.size()), parallel(directions.size());
  run(0, directions.size(), sequential);
  std::thread first([&] { run(0, directions.size() / 2, parallel); });
  std::thread second([&] { run(directions.size() / 2, directions.size(), parallel); });
  first.join();
  second.join();
  EXPECT_EQ(sequential, parallel);
}

TEST(TriangleBvhTest, MoveKeepsTheTreeAndBoundsCoverTheMesh) {
  TriangleBvh bvh(gridCube(2));
  TriangleBvh moved = std::move(bvh);
  EXPECT_TRUE(moved.firstHit({0, 0, 0}, {0, 0, 1}).has_value());
  EXPECT_TRUE(moved.bounds().isApprox(Eigen::AlignedBox3d(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1))));
}

}  // namespace
}  // namespace terramesh::datasets
