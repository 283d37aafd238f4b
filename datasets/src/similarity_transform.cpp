#include "datasets/similarity_transform.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/input_error.h"

namespace terramesh::datasets {

mesher::TriangleMesh SimilarityTransform::apply(const mesher::TriangleMesh& mesh) const {
  mesher::TriangleMesh mapped = mesh;
  for (Eigen::Vector3d& v : mapped.vertices) v = apply(v);
  return mapped;
}

Eigen::Quaterniond SimilarityTransform::apply(const Eigen::Quaterniond& rotation_W_C) const {
  return Eigen::Quaterniond(rotation * rotation_W_C.toRotationMatrix()).normalized();
}

SimilarityTransform readSimilarityTransform(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string(), "", "cannot open file for reading");
  SimilarityTransform sim;
  bool have_s = false, have_r = false, have_t = false;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    std::string key;
    if (!(fields >> key)) continue;
    std::vector<double> values;
    for (std::string token; fields >> token;) {
      char* end = nullptr;
      const double value = std::strtod(token.c_str(), &end);
      if (*end != '\0' || !std::isfinite(value)) {
        if (key == "s" || key == "R" || key == "t") {
          throw InputError(path.string(), lineLocation(number), key + ": expected finite numbers, got \"" + token + "\"");
        }
        break;
      }
      values.push_back(value);
    }
    auto expect = [&](std::size_t count) {
      if (values.size() != count) {
        throw InputError(path.string(), lineLocation(number),
                         key + ": expected " + std::to_string(count) + " numbers, got " + std::to_string(values.size()));
      }
    };
    if (key == "s") {
      expect(1);
      if (!(values[0] > 0)) throw InputError(path.string(), lineLocation(number), "s: the scale must be positive");
      sim.scale = values[0];
      have_s = true;
    } else if (key == "R") {
      expect(9);
      for (int i = 0; i < 9; ++i) sim.rotation(i / 3, i % 3) = values[static_cast<std::size_t>(i)];
      const double error = (sim.rotation.transpose() * sim.rotation - Eigen::Matrix3d::Identity()).norm();
      if (error > 1e-3 || sim.rotation.determinant() < 0) {
        throw InputError(path.string(), lineLocation(number), "R: expected a rotation matrix (orthonormal, det +1)");
      }
      have_r = true;
    } else if (key == "t") {
      expect(3);
      sim.translation = Eigen::Vector3d(values[0], values[1], values[2]);
      have_t = true;
    }
  }
  if (!have_s || !have_r || !have_t) {
    throw InputError(path.string(), "", std::string("missing ") + (!have_s ? "s" : !have_r ? "R" : "t") +
                                            " (expected lines \"s\", \"R\" and \"t\")");
  }
  return sim;
}

}  // namespace terramesh::datasets
