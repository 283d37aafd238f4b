#include "compare_report.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/atomic_file.h"
#include "common/plan_frame.h"

namespace terramesh::cli {

namespace {

std::string fixed(double value, int digits) {
  if (std::isnan(value)) return "nan";
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", digits, value);
  return text;
}

/// Markdown cell: "-" when not measured.
std::string cell(bool measured, double value, int digits) { return measured ? fixed(value, digits) : "-"; }

double mb(std::uintmax_t bytes) { return static_cast<double>(bytes) / 1e6; }

/// The reports' accuracy and completeness threshold.
constexpr std::size_t k25cm = evaluation::DistanceStats::kWithin25cm;

}  // namespace

void writeCompareCsv(const std::filesystem::path& path, const std::vector<CompareRow>& rows) {
  std::ostringstream csv;
  csv << "map,slug,kind,built,build_s,to_surface_s,peak_rss_mb,extra_peak_mb,size_mb,faces,measured_faces,"
         "depth_coverage,depth_median_m,accuracy_median_m,accuracy_within_0.25m,completeness_median_m,"
         "completeness_within_0.25m,non_manifold_edges,non_manifold_vertices,boundary_edges,boundary_loops,"
         "components,genus,orientation_errors,traversability_precision,traversability_recall,traversability_f1,"
         "traversability_coverage,traversability_unknown_fraction,plan_pairs,plan_solved,plan_no_start_or_goal,"
         "plan_unreachable,plan_mean_length_m,plan_mean_cost,plan_length_ratio,plan_truth_checked,plan_truth_valid,"
         "walkable_faces,walkable_area_m2,walkable_components,largest_component_m2\n";
  const char* kinds[] = {"mesh", "voxels", "points"};
  for (const CompareRow& r : rows) {
    const auto& g = r.geometry;
    const auto& m = r.manifold;
    const auto& t = r.traversability;
    const auto& p = r.planning;
    const double nan = std::nan("");
    csv << '"' << r.spec.name << "\"," << r.spec.slug << ',' << kinds[static_cast<int>(r.spec.kind)] << ','
        << (r.built.ok ? 1 : 0) << ',' << fixed(r.built.build_s, 4) << ',' << fixed(r.built.to_surface_s, 4) << ','
        << fixed(r.built.peak_rss_mb, 1) << ',' << fixed(r.built.extra_peak_mb, 1) << ','
        << fixed(mb(r.built.size_bytes), 3) << ',' << r.built.surface.faces.size() << ','
        << (r.has_geometry ? g.measured_faces : 0) << ',';
    if (r.has_geometry) {
      csv << fixed(g.depth.coverage(), 4) << ',' << fixed(g.depth.median_abs_m, 4) << ','
          << fixed(g.accuracy.median_m, 4) << ',' << fixed(g.accuracy.within[k25cm], 4) << ','
          << fixed(g.completeness.median_m, 4) << ',' << fixed(g.completeness.within[k25cm], 4)
          << ',';
    } else {
      csv << "nan,nan,nan,nan,nan,nan,";
    }
    csv << m.non_manifold_edges << ',' << m.non_manifold_vertices << ',' << m.boundary_edges << ','
        << m.boundary_loops << ',' << m.components << ',' << m.genus << ',' << m.orientation_errors << ',';
    csv << fixed(r.has_traversability ? t.precision : nan, 4) << ',' << fixed(r.has_traversability ? t.recall : nan, 4)
        << ',' << fixed(r.has_traversability ? t.f1 : nan, 4) << ','
        << fixed(r.has_traversability ? t.coverage : nan, 4) << ','
        << fixed(r.has_traversability ? t.unknown_fraction : nan, 4) << ',';
    csv << p.pairs << ',' << p.solved << ',' << p.no_start_or_goal << ',' << p.unreachable << ','
        << fixed(r.has_planning ? p.mean_length_m : nan, 3) << ',' << fixed(r.has_planning ? p.mean_cost : nan, 3) << ','
        << fixed(r.has_planning ? p.mean_length_ratio : nan, 4) << ',' << p.truth_checked << ',' << p.truth_valid << ','
        << p.walkable_faces << ',' << fixed(p.walkable_area_m2, 2) << ',' << p.walkable_components << ','
        << fixed(p.largest_component_m2, 2) << '\n';
  }
  writeFileAtomically(path, csv.str());
}

void writeTopView(const std::filesystem::path& path, const mesher::TriangleMesh& mesh,
                  const std::vector<traversability::FaceLayers>* layers, const Eigen::Vector3d& up_W,
                  std::size_t max_faces) {
  const Eigen::Vector3d up = up_W.normalized();
  const geometry::PlanFrame frame = geometry::planFrame(up, geometry::exportFrameRule());
  const Eigen::Vector3d& x = frame.e1;
  const Eigen::Vector3d& y = frame.e2;
  const bool flags = mesh.is_steiner.size() == mesh.vertices.size();
  std::vector<std::size_t> chosen;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& t = mesh.faces[f];
    const Eigen::Vector3d n = (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    if (n.dot(up) > 0) chosen.push_back(f);
  }
  const std::size_t step = chosen.size() > max_faces ? (chosen.size() + max_faces - 1) / max_faces : 1;
  std::ostringstream csv;
  csv << "x0,y0,x1,y1,x2,y2,height,class\n";
  char line[256];
  for (std::size_t i = 0; i < chosen.size(); i += step) {
    const std::size_t f = chosen[i];
    const auto& t = mesh.faces[f];
    int cls = 3;
    if (layers) {
      cls = static_cast<int>((*layers)[f].face_class);
    } else if (flags && (mesh.is_steiner[t[0]] || mesh.is_steiner[t[1]] || mesh.is_steiner[t[2]])) {
      cls = 4;
    }
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    const Eigen::Vector3d& b = mesh.vertices[t[1]];
    const Eigen::Vector3d& c = mesh.vertices[t[2]];
    std::snprintf(line, sizeof(line), "%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%d\n", a.dot(x), a.dot(y), b.dot(x), b.dot(y),
                  c.dot(x), c.dot(y), (a + b + c).dot(up) / 3.0, cls);
    csv << line;
  }
  writeFileAtomically(path, csv.str());
}

void writePairsCsv(const std::filesystem::path& path, const std::vector<evaluation::ComparePair>& pairs,
                   const std::vector<CompareRow>& rows) {
  std::ostringstream csv;
  csv.precision(10);
  csv << "pair,start_x,start_y,start_z,goal_x,goal_y,goal_z,straight_m,truth_length_m";
  for (const CompareRow& r : rows) {
    if (r.has_planning) csv << ',' << r.spec.slug << ',' << r.spec.slug << "_truth";
  }
  csv << '\n';
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const evaluation::ComparePair& p = pairs[i];
    csv << i << ',' << p.start_W.x() << ',' << p.start_W.y() << ',' << p.start_W.z() << ',' << p.goal_W.x() << ','
        << p.goal_W.y() << ',' << p.goal_W.z() << ',' << (p.goal_W - p.start_W).norm() << ',' << p.truth_length_m;
    for (const CompareRow& r : rows) {
      if (!r.has_planning) continue;
      const bool known = i < r.planning.statuses.size();
      csv << ',' << (known ? r.planning.statuses[i] : "") << ",\"" << (known ? r.planning.truth_reasons[i] : "") << '"';
    }
    csv << '\n';
  }
  writeFileAtomically(path, csv.str());
}

namespace {

/// One map's row of the report's table.
void tableRow(std::ostringstream& md, const CompareRow& r) {
  if (!r.built.ok) {
    md << "| " << r.spec.name << " | failed: " << r.built.error << " ||||||||||||||||||||\n";
    return;
  }
  const auto& g = r.geometry;
  const auto& m = r.manifold;
  md << "| " << r.spec.name << " | " << fixed(r.built.build_s + r.built.to_surface_s, 2) << " | "
     << fixed(r.built.peak_rss_mb, 0) << " | " << fixed(r.built.extra_peak_mb, 0) << " | "
     << fixed(mb(r.built.size_bytes), 2) << " | " << r.built.surface.faces.size() << " | "
     << cell(r.has_geometry, g.accuracy.median_m, 3) << " | " << cell(r.has_geometry, g.accuracy.within[k25cm], 3)
     << " | " << cell(r.has_geometry, g.completeness.median_m, 3) << " | "
     << cell(r.has_geometry, g.completeness.within[k25cm], 3) << " | "
     << cell(r.has_geometry, g.depth.coverage(), 3)
     << " | " << m.non_manifold_edges << " / " << m.non_manifold_vertices << " | " << m.boundary_loops << " | "
     << m.components << " | " << m.genus << " | " << cell(r.has_traversability, r.traversability.f1, 3) << " | "
     << cell(r.has_traversability, r.traversability.coverage, 3) << " | ";
  if (r.has_planning) {
    const PlanningOutcome& p = r.planning;
    md << p.solved << "/" << p.pairs << " | " << fixed(p.mean_length_m, 2) << " | " << fixed(p.mean_cost, 2) << " | "
       << fixed(p.mean_length_ratio, 3) << " | ";
    if (p.truth_checked > 0) md << p.truth_valid << "/" << p.truth_checked << " |\n";
    else md << "- |\n";
  } else {
    md << "- | - | - | - | - |\n";
  }
}

}  // namespace

std::string compareMarkdown(const CompareSetup& setup, const std::vector<CompareRow>& rows, bool figures_drawn) {
  std::ostringstream md;
  md << "# terramesh compare\n\n"
     << "```\n" << setup.command << "\n```\n\n"
     << "- input: `" << setup.input << "` (" << setup.keyframes << " keyframe events, " << fixed(setup.metres_per_unit, 4)
     << " m per map unit)\n"
     << "- geometry truth: " << (setup.truth.empty() ? "none (accuracy columns not measured)" : setup.truth) << '\n'
     << "- robot: " << (setup.robot.empty() ? "none (traversability and planning not measured)" : setup.robot) << '\n'
     << "- start-goal pairs: " << (setup.pairs.empty() ? "none" : setup.pairs) << "\n\n";
  md << "| map | build (s) | peak RSS (MB) | extra peak (MB) | size (MB) | faces | accuracy median (m) | accuracy <= 0.25 m "
        "| completeness median (m) | completeness <= 0.25 m | depth coverage | non-manifold edges / vertices | "
        "boundary loops | components | genus | traversability F1 | traversable covered | plan solved | plan length (m) | "
        "plan cost | length / truth | valid on truth |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const CompareRow& r : rows) tableRow(md, r);
  md << "\nBuild time: the method's own work (mesher: every update and the final extraction; OctoMap: the "
        "insertions, plus turning the .bt into a voxel-face surface; PCL: selecting the points, normals and the "
        "reconstruction). Peak RSS: `ru_maxrss` of the child process (fork + wait4) that built the map alone; extra "
        "peak: above the resident set it inherited at the fork (the loaded stream). Size: the method's own file "
        "(mesher: binary PLY, float64 vertices + Steiner flag; OctoMap: .bt; PCL: pcl::io::savePLYFileBinary, "
        "float32). Accuracy, completeness and depth coverage: the measures of `terramesh eval` on the measured "
        "faces (faces touching a Steiner vertex, or a PCL vertex unsupported by the points, left out). Manifoldness "
        "over the whole surface. Traversability: our layers on every surface (`computeForMesh`), area-weighted F1 "
        "of free vs. the generator's per-robot labels (`traverse-eval`), and the share of the truly traversable "
        "area with a known map face within 0.5 m. Planning: graph A* (`planOnFaceGraph`) on the same pairs; length "
        "and cost are means over solved pairs (cost: metres weighted by 1 + 4 x face cost); length / truth is the "
        "mean over solved pairs of the path length over the shortest traversable length on the truth; valid on "
        "truth: solved paths drivable on the labelled truth (planner_demo's ground-truth check).\n\n";
  bool any_planning = false;
  for (const CompareRow& r : rows) any_planning = any_planning || r.has_planning;
  if (any_planning) {
    md << "## Planning, per map\n\n";
    for (const CompareRow& r : rows) {
      if (r.has_planning) md << "- **" << r.spec.name << "**: " << r.planning.summary() << '\n';
    }
    md << "\nPer pair: `pairs.csv`.\n\n";
  }
  md << "## Parameters\n\n";
  for (const CompareRow& r : rows) {
    md << "- **" << r.spec.name << "**: " << (r.built.ok ? r.built.parameters : r.built.error) << " (`"
       << r.built.native_file.filename().string() << "`)\n";
  }
  md << "\n## Figures\n\n";
  if (figures_drawn) {
    md << "![accuracy vs build time](accuracy_vs_build_time.png)\n\n![top views](top_views.png)\n";
  } else {
    md << "Not drawn here; run `python3 scripts/figures/compare_figures.py OUTDIR` (matplotlib) on this folder.\n";
  }
  return md.str();
}

}  // namespace terramesh::cli
