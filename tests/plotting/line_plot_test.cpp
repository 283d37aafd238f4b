#include "line_plot.h"

#include <gtest/gtest.h>
#include <png.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>

#include "test_support/temp_dir.h"

namespace terramesh::cli {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr Rgb kLegendBorder{190, 190, 190};

/// A PNG read back with libpng's simplified API, as 8-bit RGB.
struct Png {
  int width = 0;
  int height = 0;
  png_uint_32 file_format = 0;  ///< PNG_FORMAT_* of the file itself.
  std::vector<std::uint8_t> rgb;

  Rgb at(int x, int y) const {
    const std::uint8_t* p = rgb.data() + 3 * (std::size_t(y) * width + x);
    return {p[0], p[1], p[2]};
  }
};

Png readPng(const std::filesystem::path& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) {
    throw std::runtime_error("cannot read " + path.string() + ": " + image.message);
  }
  Png png;
  png.width = static_cast<int>(image.width);
  png.height = static_cast<int>(image.height);
  png.file_format = image.format;
  image.format = PNG_FORMAT_RGB;
  png.rgb.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, png.rgb.data(), 0, nullptr)) {
    throw std::runtime_error("cannot decode " + path.string() + ": " + image.message);
  }
  return png;
}

bool sameColor(Rgb a, Rgb b) { return a.r == b.r && a.g == b.g && a.b == b.b; }

bool isDark(Rgb c) { return std::max({c.r, c.g, c.b}) < 100; }

/// The plot frame, found as the outermost rows and columns holding a long unbroken run of dark
/// pixels (text never does).
struct Frame {
  int left = -1;
  int top = -1;
  int right = -1;
  int bottom = -1;

  double columnOf(double fraction) const { return left + fraction * (right - left); }
  double rowOf(double fraction) const { return bottom - fraction * (bottom - top); }
};

/// The pixel at position `i` along row (`horizontal`) or column `index`.
Rgb along(const Png& png, int index, int i, bool horizontal) {
  return horizontal ? png.at(i, index) : png.at(index, i);
}

int longestDarkRun(const Png& png, int index, bool horizontal) {
  int run = 0;
  int longest = 0;
  for (int i = 0; i < (horizontal ? png.width : png.height); ++i) {
    run = isDark(along(png, index, i, horizontal)) ? run + 1 : 0;
    longest = std::max(longest, run);
  }
  return longest;
}

Frame findFrame(const Png& png) {
  Frame frame;
  for (int y = 0; y < png.height; ++y) {
    if (longestDarkRun(png, y, true) <= png.width / 2) continue;
    if (frame.top < 0) frame.top = y;
    frame.bottom = y;
  }
  for (int x = 0; x < png.width; ++x) {
    if (longestDarkRun(png, x, false) <= png.height / 2) continue;
    if (frame.left < 0) frame.left = x;
    frame.right = x;
  }
  return frame;
}

/// Positions strictly inside the frame along row (`horizontal`) or column `index` whose pixel has
/// exactly `color`.
std::vector<int> positionsWithColor(const Png& png, const Frame& frame, int index, bool horizontal,
                                    Rgb color) {
  std::vector<int> positions;
  const int first = horizontal ? frame.left : frame.top;
  const int last = horizontal ? frame.right : frame.bottom;
  for (int i = first + 1; i < last; ++i) {
    if (sameColor(along(png, index, i, horizontal), color)) positions.push_back(i);
  }
  return positions;
}

std::vector<int> rowsWithColor(const Png& png, const Frame& frame, int x, Rgb color) {
  return positionsWithColor(png, frame, x, false, color);
}

std::vector<int> columnsWithColor(const Png& png, const Frame& frame, int y, Rgb color) {
  return positionsWithColor(png, frame, y, true, color);
}

double mean(const std::vector<int>& values) {
  double sum = 0.0;
  for (int v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

std::size_t countColor(const Png& png, Rgb color) {
  std::size_t count = 0;
  for (int y = 0; y < png.height; ++y) {
    for (int x = 0; x < png.width; ++x) count += sameColor(png.at(x, y), color) ? 1 : 0;
  }
  return count;
}

PlotSeries constantSeries(const std::string& label, double y, double x_max = 10.0) {
  PlotSeries series;
  series.label = label;
  for (int i = 0; i <= 100; ++i) {
    series.x.push_back(x_max * i / 100.0);
    series.y.push_back(y);
  }
  return series;
}

LinePlot titledPlot() {
  LinePlot plot;
  plot.title = "Time per keyframe";
  plot.x_label = "keyframe";
  plot.y_label = "time (ms)";
  return plot;
}

class LinePlotTest : public ::testing::Test {
 protected:
  /// Writes `plot` at the default size into the temp dir and reads it back.
  Png render(const LinePlot& plot, const std::string& name = "plot.png") {
    writeLinePlotPng(dir_ / name, plot);
    return readPng(dir_ / name);
  }

  test::TempDir dir_;
};

TEST_F(LinePlotTest, WritesEightBitRgbPngOfTheRequestedSize) {
  LinePlot plot = titledPlot();
  plot.series.push_back(constantSeries("a", 1.0));
  const Png png = render(plot, "default.png");
  EXPECT_EQ(png.width, 1200);
  EXPECT_EQ(png.height, 700);
  EXPECT_EQ(png.file_format, png_uint_32(PNG_FORMAT_RGB));

  writeLinePlotPng(dir_ / "small.png", plot, 640, 480);
  const Png small = readPng(dir_ / "small.png");
  EXPECT_EQ(small.width, 640);
  EXPECT_EQ(small.height, 480);
}

TEST_F(LinePlotTest, BackgroundIsWhite) {
  LinePlot plot = titledPlot();
  plot.series.push_back(constantSeries("a", 3.0));
  const Png png = render(plot);
  const Rgb white{255, 255, 255};
  for (const auto& [x, y] :
       {std::pair{0, 0}, std::pair{png.width - 1, 0}, std::pair{0, png.height - 1},
        std::pair{png.width - 1, png.height - 1}}) {
    EXPECT_TRUE(sameColor(png.at(x, y), white)) << x << "," << y;
  }
  EXPECT_GT(countColor(png, white), std::size_t(png.width) * png.height * 8 / 10);
}

TEST_F(LinePlotTest, HorizontalLineLiesAtItsValueOnAFixedAxis) {
  LinePlot plot = titledPlot();
  plot.series.push_back(constantSeries("five", 5.0));
  plot.y_min = 0.0;
  plot.y_max = 10.0;
  const Png png = render(plot);
  const Frame frame = findFrame(png);
  ASSERT_GT(frame.right - frame.left, png.width / 2);
  ASSERT_GT(frame.bottom - frame.top, png.height / 2);

  const Rgb color = plotSeriesColor(0);
  for (const double fraction : {0.1, 0.5, 0.9}) {
    const int x = static_cast<int>(std::lround(frame.columnOf(fraction)));
    const std::vector<int> rows = rowsWithColor(png, frame, x, color);
    ASSERT_FALSE(rows.empty()) << "no line at column " << x;
    EXPECT_NEAR(mean(rows), frame.rowOf(0.5), 2.0) << "column " << x;
    EXPECT_LE(rows.back() - rows.front(), 3) << "line too thick or smeared";
  }
}

TEST_F(LinePlotTest, VerticalLineLiesAtItsValueOnADataAxis) {
  LinePlot plot;
  PlotSeries vertical{"x = 2", {2.0, 2.0}, {1.0, 9.0}};
  PlotSeries base{"base", {0.0, 10.0}, {0.0, 10.0}};
  plot.series = {vertical, base};
  plot.y_min = 0.0;
  plot.y_max = 10.0;
  const Png png = render(plot);
  const Frame frame = findFrame(png);
  // The x data spans [0, 10], whose ends are tick values, so the x axis does too.
  const int y = static_cast<int>(std::lround(frame.rowOf(0.5)));
  const std::vector<int> columns = columnsWithColor(png, frame, y, plotSeriesColor(0));
  ASSERT_FALSE(columns.empty());
  EXPECT_NEAR(mean(columns), frame.columnOf(0.2), 2.0);
  // And the diagonal crosses the middle of the plot.
  const std::vector<int> diagonal = columnsWithColor(png, frame, y, plotSeriesColor(1));
  ASSERT_FALSE(diagonal.empty());
  EXPECT_NEAR(mean(diagonal), frame.columnOf(0.5), 2.0);
}

TEST_F(LinePlotTest, LogAxisSpacesDecadesEvenly) {
  LinePlot plot = titledPlot();
  plot.log_y = true;
  plot.y_min = 1e-4;
  plot.y_max = 1.0;
  for (const double y : {1e-3, 1e-2, 1e-1}) plot.series.push_back(constantSeries("", y));
  const Png png = render(plot);
  const Frame frame = findFrame(png);
  const int x = static_cast<int>(std::lround(frame.columnOf(0.5)));
  std::vector<double> rows;
  for (std::size_t i = 0; i < 3; ++i) {
    const std::vector<int> hits = rowsWithColor(png, frame, x, plotSeriesColor(i));
    ASSERT_FALSE(hits.empty()) << "series " << i;
    rows.push_back(mean(hits));
  }
  const double quarter = (frame.bottom - frame.top) / 4.0;
  EXPECT_NEAR(rows[0], frame.rowOf(0.25), 2.0);
  EXPECT_NEAR(rows[1], frame.rowOf(0.50), 2.0);
  EXPECT_NEAR(rows[2], frame.rowOf(0.75), 2.0);
  EXPECT_NEAR(rows[0] - rows[1], quarter, 2.0);
  EXPECT_NEAR(rows[1] - rows[2], quarter, 2.0);
}

TEST_F(LinePlotTest, AutomaticLogAxisIsRoundedOutToDecades) {
  LinePlot plot;
  plot.log_y = true;
  plot.series.push_back(constantSeries("", 1.0));
  plot.series.push_back(constantSeries("", 10.0));
  plot.series.push_back(constantSeries("", 31.6227766));  // 10^1.5
  plot.series.push_back(constantSeries("", 1000.0));
  const Png png = render(plot);
  const Frame frame = findFrame(png);
  const int x = static_cast<int>(std::lround(frame.columnOf(0.5)));
  const std::vector<int> ten = rowsWithColor(png, frame, x, plotSeriesColor(1));
  const std::vector<int> mid = rowsWithColor(png, frame, x, plotSeriesColor(2));
  ASSERT_FALSE(ten.empty());
  ASSERT_FALSE(mid.empty());
  EXPECT_NEAR(mean(ten), frame.rowOf(1.0 / 3.0), 2.0);
  EXPECT_NEAR(mean(mid), frame.rowOf(0.5), 2.0);
}

TEST_F(LinePlotTest, NonFiniteValuesBreakTheLine) {
  LinePlot plot;
  PlotSeries series;
  for (int i = 0; i <= 10; ++i) {
    series.x.push_back(i);
    series.y.push_back(i == 5 ? kNaN : i == 8 ? kInf : 5.0);
  }
  plot.series.push_back(series);
  plot.y_min = 0.0;
  plot.y_max = 10.0;
  const Png png = render(plot);
  const Frame frame = findFrame(png);
  const Rgb color = plotSeriesColor(0);
  const auto column = [&frame](double x) {
    return static_cast<int>(std::lround(frame.columnOf(x / 10.0)));
  };
  EXPECT_FALSE(rowsWithColor(png, frame, column(2.5), color).empty());
  EXPECT_TRUE(rowsWithColor(png, frame, column(4.5), color).empty());
  EXPECT_TRUE(rowsWithColor(png, frame, column(5.0), color).empty());
  EXPECT_TRUE(rowsWithColor(png, frame, column(5.5), color).empty());
  EXPECT_FALSE(rowsWithColor(png, frame, column(6.5), color).empty());
  EXPECT_TRUE(rowsWithColor(png, frame, column(7.5), color).empty());
  EXPECT_TRUE(rowsWithColor(png, frame, column(8.5), color).empty());
  // The point at x = 10 has no drawable neighbour: it is a dot.
  EXPECT_FALSE(rowsWithColor(png, frame, column(10.0) - 2, color).empty());
}

TEST_F(LinePlotTest, SinglePointIsDrawnAsADotAtItsPlace) {
  LinePlot plot;
  plot.series.push_back({"one", {3.0}, {7.0}});
  plot.y_min = 0.0;
  plot.y_max = 10.0;
  const Png png = render(plot);
  const Frame frame = findFrame(png);
  // A constant x range is centred on the value.
  const int x = static_cast<int>(std::lround(frame.columnOf(0.5)));
  const std::vector<int> rows = rowsWithColor(png, frame, x, plotSeriesColor(0));
  ASSERT_FALSE(rows.empty());
  EXPECT_NEAR(mean(rows), frame.rowOf(0.7), 2.0);
  EXPECT_GE(rows.size(), 3u);
}

TEST_F(LinePlotTest, DegenerateInputsStillMakeAPlot) {
  const auto render = [this](const LinePlot& plot, const std::string& name) {
    SCOPED_TRACE(name);
    const auto path = dir_ / (name + ".png");
    ASSERT_NO_THROW(writeLinePlotPng(path, plot, 800, 500));
    const Png png = readPng(path);
    EXPECT_EQ(png.width, 800);
    EXPECT_EQ(png.height, 500);
    const Frame frame = findFrame(png);
    EXPECT_GT(frame.right - frame.left, 200);
    EXPECT_GT(frame.bottom - frame.top, 200);
  };
  LinePlot plot;
  render(plot, "no_series");
  plot.series.push_back({"empty", {}, {}});
  render(plot, "empty_series");
  plot.series.push_back({"all nan", {kNaN, 1.0, kInf}, {1.0, kNaN, 2.0}});
  render(plot, "all_nan");
  plot.log_y = true;
  render(plot, "all_nan_log");
  plot.series.push_back({"constant", {0.0, 1.0, 2.0}, {4.0, 4.0, 4.0}});
  render(plot, "constant_log");
  plot.log_y = false;
  render(plot, "constant");
  plot.series.back().y = {0.0, 0.0, 0.0};
  render(plot, "zero");
  plot.series.back().y = {-1e300, 1e300, 0.0};
  render(plot, "huge");
  plot.series.back().y = {-1.7e308, 1.7e308, 0.0};
  render(plot, "near_overflow");
  plot.series.back().y = {3e-300, 3e-300, 3e-300};
  render(plot, "tiny_constant");
  plot.series.back().y = {1.0, 1.0 + 1e-15, 1.0};
  render(plot, "nearly_constant");
  plot.series.back().y = {-5e-5, 2e-4, 1e-4};
  render(plot, "small");
  plot.y_min = 1.0;  // above all data
  render(plot, "data_below_y_min");
  plot.y_min.reset();
  plot.y_max = -1.0;  // below all data
  render(plot, "data_above_y_max");
  plot.y_max.reset();
  plot.log_y = true;
  plot.series.back().y = {1e-300, 1e300, 1.0};
  render(plot, "six_hundred_decades");
  plot.series.back().y = {2.0, 3.0, 2.5};
  plot.y_min = 2.0;
  plot.y_max = 3.0;
  render(plot, "log_within_a_decade");
  plot.series.back().label = std::string(300, 'w') + "\xc2\xb5s \xe2\x82\xac";
  plot.title = std::string(200, 'T');
  render(plot, "long_texts");
}

TEST_F(LinePlotTest, ThousandsOfPointsPerSeries) {
  LinePlot plot = titledPlot();
  std::mt19937 random(42);
  std::lognormal_distribution<double> time(0.0, 0.5);
  for (int s = 0; s < 6; ++s) {
    PlotSeries series;
    series.label = "mode " + std::to_string(s);
    for (int i = 0; i < 20000; ++i) {
      series.x.push_back(i);
      series.y.push_back((s + 1) * time(random));
    }
    plot.series.push_back(std::move(series));
  }
  plot.log_y = true;
  const auto start = std::chrono::steady_clock::now();
  writeLinePlotPng(dir_ / "plot.png", plot);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 10.0);
  const Png png = readPng(dir_ / "plot.png");
  EXPECT_GT(countColor(png, plotSeriesColor(5)), 1000u);
}

TEST_F(LinePlotTest, LegendSitsInTheCornerThatHidesTheLeastData) {
  LinePlot plot;
  plot.series.push_back({"rising", {0.0, 10.0}, {0.0, 10.0}});
  plot.y_min = 0.0;
  plot.y_max = 10.0;
  const Png png = render(plot, "rising.png");
  const Frame frame = findFrame(png);
  int x_min = png.width;
  int y_min = png.height;
  for (int y = 0; y < png.height; ++y) {
    for (int x = 0; x < png.width; ++x) {
      if (!sameColor(png.at(x, y), kLegendBorder)) continue;
      x_min = std::min(x_min, x);
      y_min = std::min(y_min, y);
    }
  }
  // The line runs from bottom left to top right: top left is free.
  EXPECT_LT(x_min, frame.columnOf(0.1));
  EXPECT_LT(y_min, frame.rowOf(0.9));

  plot.series.front().label.clear();
  EXPECT_EQ(countColor(render(plot, "unlabelled.png"), kLegendBorder), 0u);
}

TEST_F(LinePlotTest, InvalidInputThrowsAndWritesNothing) {
  const auto path = dir_ / "plot.png";
  const auto expectRejected = [&path](const LinePlot& plot, int width = 1200, int height = 700) {
    EXPECT_THROW(writeLinePlotPng(path, plot, width, height), std::invalid_argument);
    EXPECT_FALSE(std::filesystem::exists(path));
  };
  LinePlot plot;
  plot.series.push_back({"mismatched", {1.0, 2.0}, {1.0}});
  expectRejected(plot);
  plot.series.front() = {"zero on log", {1.0, 2.0}, {1.0, 0.0}};
  plot.log_y = true;
  expectRejected(plot);
  plot.series.front().y = {1.0, -3.0};
  expectRejected(plot);
  plot.series.front().y = {1.0, 2.0};
  plot.y_min = 0.0;
  expectRejected(plot);
  plot.log_y = false;
  plot.y_min = 5.0;
  plot.y_max = 5.0;
  expectRejected(plot);
  plot.y_max = kNaN;
  expectRejected(plot);
  plot.y_min.reset();
  plot.y_max.reset();
  expectRejected(plot, 100, 700);
  expectRejected(plot, 1200, 100);
  expectRejected(plot, 20000, 700);
  EXPECT_TRUE(std::filesystem::is_empty(dir_.path()));
}

TEST_F(LinePlotTest, MissingDirectoryThrowsAndCreatesNothing) {
  LinePlot plot = titledPlot();
  plot.series.push_back(constantSeries("a", 1.0));
  const auto path = dir_ / "missing" / "plot.png";
  EXPECT_THROW(writeLinePlotPng(path, plot), std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "missing"));
  EXPECT_TRUE(std::filesystem::is_empty(dir_.path()));
}

TEST_F(LinePlotTest, ReplacesAnExistingFileWhole) {
  const auto path = dir_ / "plot.png";
  std::ofstream(path) << "not a png";
  LinePlot plot = titledPlot();
  plot.series.push_back(constantSeries("a", 1.0));
  writeLinePlotPng(path, plot);
  EXPECT_EQ(readPng(path).width, 1200);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir_.path()),
                          std::filesystem::directory_iterator()),
            1);
}

TEST(PlotPaletteTest, EightDistinctColoursThenRepeats) {
  std::set<std::tuple<int, int, int>> colours;
  for (std::size_t i = 0; i < 8; ++i) {
    const Rgb c = plotSeriesColor(i);
    colours.insert({c.r, c.g, c.b});
    EXPECT_TRUE(sameColor(plotSeriesColor(i + 8), c));
  }
  EXPECT_EQ(colours.size(), 8u);
}

/// Whether `step` is 1, 2 or 5 times a power of ten.
bool isNiceStep(double step) {
  const double exponent = std::floor(std::log10(step) + 1e-9);
  const double mantissa = step / std::pow(10.0, exponent);
  return std::abs(mantissa - 1.0) < 1e-9 || std::abs(mantissa - 2.0) < 1e-9 ||
         std::abs(mantissa - 5.0) < 1e-9;
}

TEST(AxisTicksTest, LinearTicksAreNiceAndCoverTheData) {
  const AxisTicks ticks = linearAxisTicks(0.3, 12.2, 8, true);
  EXPECT_DOUBLE_EQ(ticks.lo, 0.0);
  EXPECT_DOUBLE_EQ(ticks.hi, 14.0);
  EXPECT_EQ(ticks.labels, (std::vector<std::string>{"0", "2", "4", "6", "8", "10", "12", "14"}));

  std::mt19937 random(7);
  std::uniform_real_distribution<double> exponent(-12.0, 12.0);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    const double scale = std::pow(10.0, exponent(random));
    const double a = unit(random) * scale;
    const double b = a + std::abs(unit(random)) * scale + scale * 1e-6;
    const int max_ticks = 3 + trial % 8;
    const AxisTicks t = linearAxisTicks(a, b, max_ticks, true);
    SCOPED_TRACE(::testing::Message() << a << " .. " << b << " max " << max_ticks);
    ASSERT_GE(t.major.size(), 2u);
    ASSERT_LE(t.major.size(), std::size_t(max_ticks));
    ASSERT_EQ(t.major.size(), t.labels.size());
    EXPECT_LE(t.lo, a);
    EXPECT_GE(t.hi, b);
    EXPECT_DOUBLE_EQ(t.major.front(), t.lo);
    EXPECT_DOUBLE_EQ(t.major.back(), t.hi);
    const double step = t.major[1] - t.major[0];
    EXPECT_TRUE(isNiceStep(step)) << step;
    // Distinct labels: the format keeps enough digits.
    EXPECT_EQ(std::set<std::string>(t.labels.begin(), t.labels.end()).size(), t.labels.size());
  }
}

TEST(AxisTicksTest, FixedLinearRangeKeepsItsEnds) {
  const AxisTicks ticks = linearAxisTicks(0.5, 7.3, 8, false);
  EXPECT_DOUBLE_EQ(ticks.lo, 0.5);
  EXPECT_DOUBLE_EQ(ticks.hi, 7.3);
  EXPECT_EQ(ticks.labels, (std::vector<std::string>{"1", "2", "3", "4", "5", "6", "7"}));
}

TEST(AxisTicksTest, ConstantRangeIsWidened) {
  AxisTicks ticks = linearAxisTicks(5.0, 5.0, 8, true);
  EXPECT_LT(ticks.lo, 5.0);
  EXPECT_GT(ticks.hi, 5.0);
  EXPECT_LE(ticks.hi - ticks.lo, 2.0);
  ticks = linearAxisTicks(0.0, 0.0, 8, true);
  EXPECT_DOUBLE_EQ(ticks.lo, -1.0);
  EXPECT_DOUBLE_EQ(ticks.hi, 1.0);
  ticks = linearAxisTicks(2e-9, 2e-9, 8, true);
  EXPECT_LT(ticks.lo, 2e-9);
  EXPECT_GT(ticks.hi, 2e-9);
  EXPECT_GT(ticks.lo, 0.0);
}

TEST(AxisTicksTest, LogTicksArePerDecade) {
  AxisTicks ticks = log10AxisTicks(1e-4, 1.0, 10, false);
  EXPECT_EQ(ticks.labels, (std::vector<std::string>{"1e-4", "0.001", "0.01", "0.1", "1"}));
  EXPECT_EQ(ticks.minor.size(), 4u * 8u);

  ticks = log10AxisTicks(3.0, 700.0, 10, true);
  EXPECT_DOUBLE_EQ(ticks.lo, 1.0);
  EXPECT_DOUBLE_EQ(ticks.hi, 1000.0);
  EXPECT_EQ(ticks.labels, (std::vector<std::string>{"1", "10", "100", "1000"}));

  ticks = log10AxisTicks(1e-30, 1e30, 8, false);
  EXPECT_LE(ticks.major.size(), 8u);
  EXPECT_GE(ticks.major.size(), 4u);
  for (std::size_t i = 2; i < ticks.major.size(); ++i) {
    EXPECT_NEAR(std::log10(ticks.major[i]) - std::log10(ticks.major[i - 1]),
                std::log10(ticks.major[1]) - std::log10(ticks.major[0]), 1e-9);
  }

  ticks = log10AxisTicks(2.0, 30.0, 10, false);
  EXPECT_EQ(ticks.labels, (std::vector<std::string>{"2", "5", "10", "20"}));
}

TEST(AxisTicksTest, InvalidRangesThrow) {
  EXPECT_THROW(linearAxisTicks(2.0, 1.0, 8, true), std::invalid_argument);
  EXPECT_THROW(linearAxisTicks(kNaN, 1.0, 8, true), std::invalid_argument);
  EXPECT_THROW(linearAxisTicks(1.0, 1.0, 8, false), std::invalid_argument);
  EXPECT_THROW(log10AxisTicks(0.0, 1.0, 8, true), std::invalid_argument);
  EXPECT_THROW(log10AxisTicks(1.0, kInf, 8, true), std::invalid_argument);
}

TEST(TickFormatTest, FixedOrScientificByStep) {
  EXPECT_EQ(formatTickValue(250.0, 50.0), "250");
  EXPECT_EQ(formatTickValue(0.002, 0.001), "0.002");
  EXPECT_EQ(formatTickValue(0.5, 0.1), "0.5");
  EXPECT_EQ(formatTickValue(1.0, 0.5), "1.0");
  EXPECT_EQ(formatTickValue(-1.5, 0.5), "-1.5");
  EXPECT_EQ(formatTickValue(1e-4, 1e-4), "1e-4");
  EXPECT_EQ(formatTickValue(1.2e-3, 2e-4), "1.2e-3");
  EXPECT_EQ(formatTickValue(2.5e6, 5e5), "2.5e6");
  EXPECT_EQ(formatTickValue(1e5, 1e5), "1e5");
  EXPECT_EQ(formatTickValue(-3e-7, 1e-7), "-3e-7");
  EXPECT_EQ(formatTickValue(1e-17, 0.1), "0");
  EXPECT_EQ(formatTickValue(-0.0, 1.0), "0");
  EXPECT_EQ(formatTickValue(40000.0, 10000.0), "40000");
}

}  // namespace
}  // namespace terramesh::cli
