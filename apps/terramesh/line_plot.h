#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace terramesh::cli {

/// One line of a plot: point i is (x[i], y[i]). Points with a NaN or infinite coordinate are
/// skipped and break the line; a point with no drawable neighbour is drawn as a dot.
struct PlotSeries {
  std::string label;  ///< Legend text; series with an empty label get no legend entry.
  std::vector<double> x;
  std::vector<double> y;
};

/// A line plot: the series are drawn in order over a grid, in the colours of `plotSeriesColor`.
/// The x axis spans the data, rounded out to tick values where that adds at most 5 % of the range.
struct LinePlot {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::vector<PlotSeries> series;
  bool log_y = false;  ///< log10 y axis with a tick per decade (all drawn y must be > 0).
  /// Fixed ends of the y axis; an end left empty comes from the data, rounded out to a tick (a
  /// decade on a log axis; a linear maximum on a tick gets one more step of room). Points outside
  /// the range are clipped.
  std::optional<double> y_min;
  std::optional<double> y_max;
};

/// An 8-bit sRGB colour.
struct Rgb {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;
};

/// Colour of series `index`: the Okabe-Ito palette (distinguishable with the common forms of
/// colour blindness), yellow last because it is faint on white; it repeats after 8 series.
Rgb plotSeriesColor(std::size_t index);

/// Ticks of one axis: the axis runs from `lo` to `hi`; `major` holds the labelled tick values in
/// increasing order, `labels` their text, `minor` unlabelled ticks (log axes only). On a log axis
/// all values, `lo` and `hi` included, are plain values, not exponents.
struct AxisTicks {
  double lo = 0.0;
  double hi = 1.0;
  std::vector<double> major;
  std::vector<std::string> labels;
  std::vector<double> minor;
};

/// Linear axis ticks on the smallest 1-2-5 step that makes at most max(`max_ticks`, 3) ticks.
/// With `expand` the ends are rounded out to multiples of the step, after widening a range
/// narrower than 1e-7 of its magnitude to +-10 % around its value (+-1 around 0); without, the
/// axis is [lo, hi] and only the ticks inside are kept.
/// @throw std::invalid_argument if lo or hi is not finite, lo > hi, or lo == hi without `expand`.
AxisTicks linearAxisTicks(double lo, double hi, int max_ticks, bool expand);

/// log10 axis ticks: one per decade, or per 2, 5, 10, ... decades to stay within `max_ticks`;
/// minor ticks at 2..9 times each decade on axes of up to 8 decades, else at the unlabelled
/// decades. An axis with fewer than two decades in view labels the 1-2-5 multiples instead. With
/// `expand` the ends are rounded out to decades (a decade either side of a constant power of 10).
/// @throw std::invalid_argument if lo or hi is not finite and > 0, lo > hi, or lo == hi without
///        `expand`.
AxisTicks log10AxisTicks(double lo, double hi, int max_ticks, bool expand);

/// Text of a tick at `value` on an axis whose ticks are `step` apart: fixed notation with as many
/// decimals as the step needs ("250", "0.002", "-1.5"), or "<mantissa>e<exponent>" for values
/// below 1e-3 or from 1e5 on ("1e-4", "2.5e6"). A value within 1e-9 steps of zero prints as "0".
std::string formatTickValue(double value, double step);

/// Renders the plot and writes it atomically (terramesh::writeFileAtomically) as an 8-bit RGB
/// PNG: white background, title, axis labels, tick labels on 'nice' values, light grey grid,
/// 2-px anti-aliased lines and a legend placed in the corner of the plot area that hides the
/// least data. Text uses a built-in 5x7 ASCII bitmap font scaled with the image (2x at the
/// default size); of the other characters only the micro sign is drawn, the rest show as '?'.
/// Cost: O(width * height * series + points).
/// Thread-safe: no shared state.
/// @throw std::invalid_argument for a series with x.size() != y.size(), a finite y <= 0 on a log
///        axis, a y range whose ends are not finite (or not > 0 on a log axis) or not increasing,
///        or an image size outside [200, 16384] x [150, 16384]; nothing is written then.
/// @throw std::runtime_error if the PNG cannot be encoded or the file cannot be written (e.g. its
///        directory does not exist); no partial file is left behind.
void writeLinePlotPng(const std::filesystem::path& path, const LinePlot& plot, int width_px = 1200,
                      int height_px = 700);

}  // namespace terramesh::cli
