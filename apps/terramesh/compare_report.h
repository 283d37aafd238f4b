#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "compare_maps.h"
#include "compare_planning.h"
#include "evaluation/geometry_truth.h"
#include "evaluation/manifoldness.h"
#include "evaluation/traversability_score.h"
#include "evaluation/truth_pairs.h"
#include "traversability/layered_mesh.h"

namespace terramesh::cli {

/// One row of the comparison: a map and everything measured on it.
struct CompareRow {
  MapSpec spec;
  BuiltMap built;
  double measure_s = 0;  ///< time spent measuring (not part of the build)
  evaluation::Manifoldness manifold;
  bool has_geometry = false;
  evaluation::GeometryScores geometry;
  bool has_traversability = false;
  evaluation::TraversabilityScore traversability;
  bool has_planning = false;
  PlanningOutcome planning;
};

/// What the run was, for the report's header.
struct CompareSetup {
  std::string command;       ///< the command line
  std::string input;
  std::string truth;         ///< what the geometry was compared with
  std::string robot;         ///< profile name, or empty
  std::string pairs;         ///< how the start-goal pairs were drawn
  std::size_t keyframes = 0;
  double metres_per_unit = 1;
};

/// compare.csv: one line per row, every measure (NaN or empty where not measured).
void writeCompareCsv(const std::filesystem::path& path, const std::vector<CompareRow>& rows);

/// A top view of one map for the figure script: the upward-facing faces (normal within 90 deg of
/// up) projected onto the plan (x = world x, or y when x is within 30 deg of up, made
/// perpendicular to up; y = up x x), one line per face: x0,y0,x1,y1,x2,y2,height,class (class
/// 0 free, 1 lethal, 2 unknown from `map`'s layers; 3 measured, 4 Steiner/unsupported without
/// layers). At most `max_faces` faces (every k-th beyond that).
void writeTopView(const std::filesystem::path& path, const mesher::TriangleMesh& mesh,
                  const std::vector<traversability::FaceLayers>* layers, const Eigen::Vector3d& up_W,
                  std::size_t max_faces = 400000);

/// pairs.csv: one line per pair (start, goal, truth length) with every map's status.
void writePairsCsv(const std::filesystem::path& path, const std::vector<evaluation::ComparePair>& pairs,
                   const std::vector<CompareRow>& rows);

/// report.md: the setup, the table, each map's parameters, the figures and how the columns
/// are measured.
std::string compareMarkdown(const CompareSetup& setup, const std::vector<CompareRow>& rows, bool figures_drawn);

}  // namespace terramesh::cli
