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

void addInputOptions(CLI::App& app, InputOptions& options) {
  app.add_option("--input-format", options.input_format, "how to read the input: " + datasets::streamFormatNames())
      ->option_text("FMT");
  app.add_option("--image-list", options.image_list,
                 "Bundler input: the image list (default: list_r000.out, list.txt... found beside the .out file, "
                 "else none: meshing needs no image names)")
      ->option_text("FILE");
  app.add_option("--poses", options.poses,
                 "KITTI input: cam0 poses (KITTI or TUM format; default: found beside the sequence)")
      ->option_text("FILE");
  app.add_option("--frames", options.frames, "KITTI input: frames A to B (inclusive), every S-th")
      ->option_text("A[:B[:S]]");
  app.add_option("--max-returns-per-scan", options.max_returns_per_scan,
                 "KITTI input: keep N returns per scan, a seeded uniform subset (0: all)")
      ->option_text("N")
      ->check(nonNegativeNumber());
  app.add_option("--max-range-m", options.max_range_m, "KITTI input: drop returns farther than D from the sensor")
      ->option_text("D");
}

datasets::StreamReadOptions streamReadOptionsFrom(const InputOptions& values) {
  datasets::StreamReadOptions options;
  const auto format = datasets::parseStreamFormat(values.input_format);
  if (!format) throw UsageError("--input-format must be one of " + datasets::streamFormatNames());
  options.format = *format;
  if (values.image_list) options.bundler_image_list = *values.image_list;
  datasets::KittiOdometryOptions& kitti = options.kitti;
  if (values.poses) kitti.poses_path = *values.poses;
  if (values.frames) parseFrames(*values.frames, kitti);
  kitti.max_returns_per_scan = values.max_returns_per_scan;
  if (values.max_range_m) kitti.max_range_m = *values.max_range_m;
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
