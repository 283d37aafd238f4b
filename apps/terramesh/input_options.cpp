#include "input_options.h"

#include <limits>

namespace terramesh::cli {
namespace {

/// "A", "A:B" or "A:B:STEP" into the KITTI frame range.
void parseFrames(const std::string& text, datasets::KittiOdometryOptions& kitti) {
  const auto fields = parseColonIntegers(text, "--frames", "FIRST[:LAST[:STEP]]", 3);
  for (const auto& field : fields) {
    if (!field) throw UsageError("--frames expects FIRST[:LAST[:STEP]] with no empty field, got \"" + text + "\"");
  }
  kitti.first_frame = *fields[0];
  kitti.last_frame = fields.size() > 1 ? *fields[1] : std::numeric_limits<std::size_t>::max();
  if (fields.size() > 2) kitti.frame_step = *fields[2];
}

}  // namespace

void declareInputOptions(ArgParser& parser) {
  parser
      .option("--input-format", "FMT", "how to read the input: " + datasets::streamFormatNames(), "auto")
      .option("--image-list", "FILE",
              "Bundler input: the image list (default: list_r000.out, list.txt... found beside "
              "the .out file, else none: meshing needs no image names)")
      .option("--poses", "FILE", "KITTI input: cam0 poses (KITTI or TUM format; default: found beside the sequence)")
      .option("--frames", "A[:B[:S]]", "KITTI input: frames A to B (inclusive), every S-th")
      .option("--max-returns-per-scan", "N", "KITTI input: keep N returns per scan, a seeded uniform subset (0: all)", "0")
      .option("--max-range-m", "D", "KITTI input: drop returns farther than D from the sensor");
}

datasets::StreamReadOptions streamReadOptionsFromArgs(const ArgParser& parser) {
  datasets::StreamReadOptions options;
  const auto format = datasets::parseStreamFormat(parser.get("--input-format"));
  if (!format) throw UsageError("--input-format must be one of " + datasets::streamFormatNames());
  options.format = *format;
  if (parser.has("--image-list")) options.bundler_image_list = parser.get("--image-list");
  datasets::KittiOdometryOptions& kitti = options.kitti;
  if (parser.has("--poses")) kitti.poses_path = parser.get("--poses");
  if (parser.has("--frames")) parseFrames(parser.get("--frames"), kitti);
  const long returns = parser.getInt("--max-returns-per-scan");
  if (returns < 0) throw UsageError("--max-returns-per-scan must be >= 0");
  kitti.max_returns_per_scan = static_cast<std::size_t>(returns);
  if (parser.has("--max-range-m")) kitti.max_range_m = parser.getDouble("--max-range-m");
  const std::vector<std::string> problems = kitti.problems();
  if (!problems.empty()) {
    std::string message = "invalid KITTI input options:";
    for (const std::string& problem : problems) message += " " + problem + ";";
    message.pop_back();
    throw UsageError(message);
  }
  return options;
}

}  // namespace terramesh::cli
