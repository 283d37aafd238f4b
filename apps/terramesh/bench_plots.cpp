#include <filesystem>

#include "bench_report.h"
#include "line_plot.h"

namespace terramesh::cli {
namespace {

PlotSeries seriesOf(const std::string& label, const BenchRun& run, const char* column) {
  PlotSeries series;
  series.label = label;
  for (std::size_t i = 0; i < run.keyframes.size(); ++i) {
    series.x.push_back(static_cast<double>(i));
    series.y.push_back(1e3 * run.keyframes[i].at(column));
  }
  return series;
}

}  // namespace

std::vector<std::filesystem::path> writeBenchPlots(const std::filesystem::path& dir,
                                                   const BenchContext& context,
                                                   const std::vector<BenchRun>& runs) {
  std::filesystem::create_directories(dir);
  std::vector<std::filesystem::path> written;
  const std::string stream = std::filesystem::path(context.stream_name).filename().string();

  LinePlot total;
  total.title = "Time per keyframe, all modes (" + stream + ")";
  total.x_label = "keyframe";
  total.y_label = "update time (ms)";
  total.log_y = true;
  for (const BenchRun& run : runs) total.series.push_back(seriesOf(run.mode, run, "time_total_s"));
  written.push_back(dir / "time_per_keyframe.png");
  writeLinePlotPng(written.back(), total);

  static const std::pair<const char*, const char*> kSteps[] = {
      {"time_steiner_s", "Steiner"}, {"time_shrink_s", "shrink"}, {"time_insertion_s", "insertion"},
      {"time_ray_tracing_s", "ray tracing"}, {"time_grow_s", "grow"}, {"time_total_s", "total"}};
  for (const BenchRun& run : runs) {
    LinePlot steps;
    steps.title = "Time per step and keyframe, " + run.mode + " (" + stream + ")";
    steps.x_label = "keyframe";
    steps.y_label = "time (ms)";
    for (const auto& [column, label] : kSteps) steps.series.push_back(seriesOf(label, run, column));
    written.push_back(dir / ("steps_" + run.mode + ".png"));
    writeLinePlotPng(written.back(), steps);
  }
  return written;
}

}  // namespace terramesh::cli
