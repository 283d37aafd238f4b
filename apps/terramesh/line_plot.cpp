#include "line_plot.h"

#include <png.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include "common/atomic_file.h"

namespace terramesh::cli {
namespace {

// The font: 5 columns by 9 rows per glyph, 7 rows above the baseline and 2 for descenders.
// Each row is a byte whose bit 4 is the leftmost column.
constexpr int kGlyphRows = 9;
constexpr int kGlyphColumns = 5;
constexpr int kGlyphAdvance = kGlyphColumns + 1;
constexpr int kCapRows = 7;
using Glyph = std::array<std::uint8_t, kGlyphRows>;

// ASCII 32..126, then the micro sign.
constexpr std::array<Glyph, 96> kFont = {{
    {{0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}},  // space
    {{0x04, 0x04, 0x04, 0x04, 0x04, 0x00, 0x04, 0x00, 0x00}},  // !
    {{0x0A, 0x0A, 0x0A, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}},  // "
    {{0x0A, 0x0A, 0x1F, 0x0A, 0x1F, 0x0A, 0x0A, 0x00, 0x00}},  // #
    {{0x04, 0x0F, 0x14, 0x0E, 0x05, 0x1E, 0x04, 0x00, 0x00}},  // $
    {{0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03, 0x00, 0x00}},  // %
    {{0x0C, 0x12, 0x14, 0x08, 0x15, 0x12, 0x0D, 0x00, 0x00}},  // &
    {{0x04, 0x04, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}},  // quote
    {{0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02, 0x00, 0x00}},  // (
    {{0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08, 0x00, 0x00}},  // )
    {{0x00, 0x04, 0x15, 0x0E, 0x15, 0x04, 0x00, 0x00, 0x00}},  // *
    {{0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00, 0x00, 0x00}},  // +
    {{0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C, 0x04, 0x08}},  // ,
    {{0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00, 0x00, 0x00}},  // -
    {{0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C, 0x00, 0x00}},  // .
    {{0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00, 0x00, 0x00}},  // /
    {{0x0E, 0x11, 0x11, 0x15, 0x11, 0x11, 0x0E, 0x00, 0x00}},  // 0 (dotted, unlike O)
    {{0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E, 0x00, 0x00}},  // 1
    {{0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F, 0x00, 0x00}},  // 2
    {{0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E, 0x00, 0x00}},  // 3
    {{0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02, 0x00, 0x00}},  // 4
    {{0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E, 0x00, 0x00}},  // 5
    {{0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E, 0x00, 0x00}},  // 6
    {{0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08, 0x00, 0x00}},  // 7
    {{0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E, 0x00, 0x00}},  // 8
    {{0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C, 0x00, 0x00}},  // 9
    {{0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00, 0x00, 0x00}},  // :
    {{0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x04, 0x08, 0x00}},  // ;
    {{0x02, 0x04, 0x08, 0x10, 0x08, 0x04, 0x02, 0x00, 0x00}},  // <
    {{0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00, 0x00, 0x00}},  // =
    {{0x08, 0x04, 0x02, 0x01, 0x02, 0x04, 0x08, 0x00, 0x00}},  // >
    {{0x0E, 0x11, 0x01, 0x02, 0x04, 0x00, 0x04, 0x00, 0x00}},  // ?
    {{0x0E, 0x11, 0x01, 0x0D, 0x15, 0x15, 0x0E, 0x00, 0x00}},  // @
    {{0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11, 0x00, 0x00}},  // A
    {{0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E, 0x00, 0x00}},  // B
    {{0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E, 0x00, 0x00}},  // C
    {{0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C, 0x00, 0x00}},  // D
    {{0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F, 0x00, 0x00}},  // E
    {{0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10, 0x00, 0x00}},  // F
    {{0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F, 0x00, 0x00}},  // G
    {{0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11, 0x00, 0x00}},  // H
    {{0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E, 0x00, 0x00}},  // I
    {{0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C, 0x00, 0x00}},  // J
    {{0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11, 0x00, 0x00}},  // K
    {{0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F, 0x00, 0x00}},  // L
    {{0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11, 0x00, 0x00}},  // M
    {{0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11, 0x00, 0x00}},  // N
    {{0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E, 0x00, 0x00}},  // O
    {{0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10, 0x00, 0x00}},  // P
    {{0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D, 0x00, 0x00}},  // Q
    {{0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11, 0x00, 0x00}},  // R
    {{0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E, 0x00, 0x00}},  // S
    {{0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x00, 0x00}},  // T
    {{0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E, 0x00, 0x00}},  // U
    {{0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04, 0x00, 0x00}},  // V
    {{0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A, 0x00, 0x00}},  // W
    {{0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11, 0x00, 0x00}},  // X
    {{0x11, 0x11, 0x0A, 0x04, 0x04, 0x04, 0x04, 0x00, 0x00}},  // Y
    {{0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F, 0x00, 0x00}},  // Z
    {{0x0E, 0x08, 0x08, 0x08, 0x08, 0x08, 0x0E, 0x00, 0x00}},  // [
    {{0x00, 0x10, 0x08, 0x04, 0x02, 0x01, 0x00, 0x00, 0x00}},  // backslash
    {{0x0E, 0x02, 0x02, 0x02, 0x02, 0x02, 0x0E, 0x00, 0x00}},  // ]
    {{0x04, 0x0A, 0x11, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}},  // ^
    {{0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F, 0x00}},  // _
    {{0x08, 0x04, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}},  // `
    {{0x00, 0x00, 0x0E, 0x01, 0x0F, 0x11, 0x0F, 0x00, 0x00}},  // a
    {{0x10, 0x10, 0x1E, 0x11, 0x11, 0x11, 0x1E, 0x00, 0x00}},  // b
    {{0x00, 0x00, 0x0E, 0x10, 0x10, 0x11, 0x0E, 0x00, 0x00}},  // c
    {{0x01, 0x01, 0x0F, 0x11, 0x11, 0x11, 0x0F, 0x00, 0x00}},  // d
    {{0x00, 0x00, 0x0E, 0x11, 0x1F, 0x10, 0x0E, 0x00, 0x00}},  // e
    {{0x06, 0x09, 0x08, 0x1C, 0x08, 0x08, 0x08, 0x00, 0x00}},  // f
    {{0x00, 0x00, 0x0F, 0x11, 0x11, 0x11, 0x0F, 0x01, 0x0E}},  // g
    {{0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x11, 0x00, 0x00}},  // h
    {{0x04, 0x00, 0x0C, 0x04, 0x04, 0x04, 0x0E, 0x00, 0x00}},  // i
    {{0x02, 0x00, 0x06, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}},  // j
    {{0x10, 0x10, 0x12, 0x14, 0x18, 0x14, 0x12, 0x00, 0x00}},  // k
    {{0x0C, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E, 0x00, 0x00}},  // l
    {{0x00, 0x00, 0x1A, 0x15, 0x15, 0x15, 0x15, 0x00, 0x00}},  // m
    {{0x00, 0x00, 0x16, 0x19, 0x11, 0x11, 0x11, 0x00, 0x00}},  // n
    {{0x00, 0x00, 0x0E, 0x11, 0x11, 0x11, 0x0E, 0x00, 0x00}},  // o
    {{0x00, 0x00, 0x1E, 0x11, 0x11, 0x11, 0x1E, 0x10, 0x10}},  // p
    {{0x00, 0x00, 0x0F, 0x11, 0x11, 0x11, 0x0F, 0x01, 0x01}},  // q
    {{0x00, 0x00, 0x16, 0x19, 0x10, 0x10, 0x10, 0x00, 0x00}},  // r
    {{0x00, 0x00, 0x0F, 0x10, 0x0E, 0x01, 0x1E, 0x00, 0x00}},  // s
    {{0x08, 0x08, 0x1C, 0x08, 0x08, 0x09, 0x06, 0x00, 0x00}},  // t
    {{0x00, 0x00, 0x11, 0x11, 0x11, 0x13, 0x0D, 0x00, 0x00}},  // u
    {{0x00, 0x00, 0x11, 0x11, 0x11, 0x0A, 0x04, 0x00, 0x00}},  // v
    {{0x00, 0x00, 0x11, 0x11, 0x15, 0x15, 0x0A, 0x00, 0x00}},  // w
    {{0x00, 0x00, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x00, 0x00}},  // x
    {{0x00, 0x00, 0x11, 0x11, 0x11, 0x11, 0x0F, 0x01, 0x0E}},  // y
    {{0x00, 0x00, 0x1F, 0x02, 0x04, 0x08, 0x1F, 0x00, 0x00}},  // z
    {{0x03, 0x04, 0x04, 0x08, 0x04, 0x04, 0x03, 0x00, 0x00}},  // {
    {{0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},  // |
    {{0x18, 0x04, 0x04, 0x02, 0x04, 0x04, 0x18, 0x00, 0x00}},  // }
    {{0x00, 0x00, 0x08, 0x15, 0x02, 0x00, 0x00, 0x00, 0x00}},  // ~
    {{0x00, 0x00, 0x11, 0x11, 0x11, 0x13, 0x1D, 0x10, 0x10}},  // micro sign (U+00B5)
}};
constexpr std::size_t kMicroGlyph = 95;
constexpr std::size_t kUnknownGlyph = '?' - ' ';
constexpr std::size_t kDotGlyph = '.' - ' ';

// Okabe & Ito, "Color Universal Design" (2008), in an order that keeps similar hues apart.
constexpr std::array<Rgb, 8> kPalette = {{{0, 114, 178},
                                          {213, 94, 0},
                                          {0, 158, 115},
                                          {204, 121, 167},
                                          {230, 159, 0},
                                          {86, 180, 233},
                                          {0, 0, 0},
                                          {240, 228, 66}}};

constexpr Rgb kWhite{255, 255, 255};
constexpr Rgb kInk{34, 34, 34};
constexpr Rgb kMajorGrid{221, 221, 221};
constexpr Rgb kMinorGrid{240, 240, 240};
constexpr Rgb kLegendBorder{190, 190, 190};

constexpr int kMinWidthPx = 200;
constexpr int kMinHeightPx = 150;
constexpr int kMaxSidePx = 16384;

// Tick positions are found by rounding value / step; this absorbs the rounding error of that
// division. Ranges narrower than kDegenerateSpan times their magnitude are widened first, which
// keeps value / step below ~1e8 and the error far below the tolerance.
constexpr double kTickTolerance = 1e-6;
constexpr double kDegenerateSpan = 1e-7;
// Points farther than this many plot sizes outside the axes are pulled in, so that pixel
// coordinates stay well inside int range; where a line leaves the plot moves by < 0.2 px.
constexpr double kMaxFraction = 1e5;

/// Inclusive pixel rectangle.
struct PixelRect {
  int x0 = 0;
  int y0 = 0;
  int x1 = -1;
  int y1 = -1;
  int width() const { return x1 - x0 + 1; }
  int height() const { return y1 - y0 + 1; }
};

/// A point in pixel coordinates; pixel (i, j) has its centre at (i, j).
struct Point {
  double x = 0.0;
  double y = 0.0;
};

class Canvas {
 public:
  Canvas(int width, int height)
      : width_(width), height_(height), rgb_(3 * std::size_t(width) * height, 255) {}

  int width() const { return width_; }
  int height() const { return height_; }
  const std::uint8_t* row(int y) const { return rgb_.data() + 3 * std::size_t(width_) * y; }

  void blend(int x, int y, Rgb color, double alpha) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
    std::uint8_t* pixel = rgb_.data() + 3 * (std::size_t(width_) * y + x);
    const std::array<std::uint8_t, 3> target{color.r, color.g, color.b};
    for (int c = 0; c < 3; ++c) {
      pixel[c] = static_cast<std::uint8_t>(
          std::lround(pixel[c] + alpha * (static_cast<double>(target[c]) - pixel[c])));
    }
  }

  void fill(const PixelRect& rect, Rgb color) {
    const int x0 = std::max(rect.x0, 0);
    const int x1 = std::min(rect.x1, width_ - 1);
    const int y0 = std::max(rect.y0, 0);
    const int y1 = std::min(rect.y1, height_ - 1);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        std::uint8_t* pixel = rgb_.data() + 3 * (std::size_t(width_) * y + x);
        pixel[0] = color.r;
        pixel[1] = color.g;
        pixel[2] = color.b;
      }
    }
  }

 private:
  int width_;
  int height_;
  std::vector<std::uint8_t> rgb_;
};

/// Per-pixel coverage of one series over a clip rectangle. Coverage from overlapping segments is
/// max-combined, so joints and dense polylines do not darken, then composited once.
class CoverageMask {
 public:
  explicit CoverageMask(const PixelRect& clip)
      : clip_(clip), coverage_(std::size_t(clip.width()) * clip.height(), 0.0f) {}

  void clear() { std::fill(coverage_.begin(), coverage_.end(), 0.0f); }

  /// Covers the pixels within `half_width` of segment ab, anti-aliased over one pixel.
  /// Cost: O(length * half_width) — only a band around the segment is visited.
  void addSegment(Point a, Point b, double half_width) {
    const double reach = half_width + 0.5;
    // Walk the major axis (u) and cover a band of the minor axis (v) around the line.
    const bool steep = std::abs(b.y - a.y) > std::abs(b.x - a.x);
    const double au = steep ? a.y : a.x;
    const double av = steep ? a.x : a.y;
    const double bu = steep ? b.y : b.x;
    const double bv = steep ? b.x : b.y;
    const double slope = bu != au ? (bv - av) / (bu - au) : 0.0;
    const double band = reach * std::sqrt(1.0 + slope * slope);
    const double u_min = std::min(au, bu);
    const double u_max = std::max(au, bu);
    const int clip_u0 = steep ? clip_.y0 : clip_.x0;
    const int clip_u1 = steep ? clip_.y1 : clip_.x1;
    const int clip_v0 = steep ? clip_.x0 : clip_.y0;
    const int clip_v1 = steep ? clip_.x1 : clip_.y1;
    const int u0 = clampedCeil(u_min - reach, clip_u0, clip_u1 + 1);
    const int u1 = clampedFloor(u_max + reach, clip_u0 - 1, clip_u1);
    for (int u = u0; u <= u1; ++u) {
      const double centre = av + (std::clamp(double(u), u_min, u_max) - au) * slope;
      const int v0 = clampedCeil(centre - band, clip_v0, clip_v1 + 1);
      const int v1 = clampedFloor(centre + band, clip_v0 - 1, clip_v1);
      for (int v = v0; v <= v1; ++v) {
        const Point p = steep ? Point{double(v), double(u)} : Point{double(u), double(v)};
        cover(p, distanceToSegment(p, a, b), half_width);
      }
    }
  }

  /// Covers a disc of `radius` around `centre`.
  void addDot(Point centre, double radius) {
    const double reach = radius + 0.5;
    const int x0 = clampedCeil(centre.x - reach, clip_.x0, clip_.x1 + 1);
    const int x1 = clampedFloor(centre.x + reach, clip_.x0 - 1, clip_.x1);
    const int y0 = clampedCeil(centre.y - reach, clip_.y0, clip_.y1 + 1);
    const int y1 = clampedFloor(centre.y + reach, clip_.y0 - 1, clip_.y1);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const Point p{double(x), double(y)};
        cover(p, std::hypot(p.x - centre.x, p.y - centre.y), radius);
      }
    }
  }

  void compositeOnto(Canvas& canvas, Rgb color) const {
    for (int y = clip_.y0; y <= clip_.y1; ++y) {
      for (int x = clip_.x0; x <= clip_.x1; ++x) {
        const float coverage = coverage_[index(x, y)];
        if (coverage > 0.0f) canvas.blend(x, y, color, coverage);
      }
    }
  }

 private:
  static int clampedCeil(double value, int lo, int hi) {
    return static_cast<int>(std::clamp(std::ceil(value), double(lo), double(hi)));
  }
  static int clampedFloor(double value, int lo, int hi) {
    return static_cast<int>(std::clamp(std::floor(value), double(lo), double(hi)));
  }

  static double distanceToSegment(Point p, Point a, Point b) {
    const double dx = b.x - a.x;
    const double dy = b.y - a.y;
    const double length2 = dx * dx + dy * dy;
    const double t =
        length2 > 0.0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / length2, 0.0, 1.0) : 0.0;
    return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
  }

  std::size_t index(int x, int y) const {
    return std::size_t(y - clip_.y0) * clip_.width() + (x - clip_.x0);
  }

  void cover(Point p, double distance, double half_width) {
    const float coverage = static_cast<float>(std::clamp(half_width + 0.5 - distance, 0.0, 1.0));
    float& cell = coverage_[index(static_cast<int>(p.x), static_cast<int>(p.y))];
    cell = std::max(cell, coverage);
  }

  PixelRect clip_;
  std::vector<float> coverage_;
};

/// Glyph indices of UTF-8 text: printable ASCII as is, U+00B5 and U+03BC as the micro sign,
/// anything else as '?'.
std::vector<std::size_t> glyphsOf(const std::string& text) {
  std::vector<std::size_t> glyphs;
  for (std::size_t i = 0; i < text.size();) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (byte < 0x80) {
      glyphs.push_back(byte >= ' ' && byte <= '~' ? std::size_t(byte - ' ') : kUnknownGlyph);
      ++i;
      continue;
    }
    const std::size_t length = byte >= 0xF0 ? 4 : byte >= 0xE0 ? 3 : byte >= 0xC0 ? 2 : 1;
    const auto next = i + 1 < text.size() ? static_cast<unsigned char>(text[i + 1]) : 0;
    const bool micro = (byte == 0xC2 && next == 0xB5) || (byte == 0xCE && next == 0xBC);
    glyphs.push_back(micro ? kMicroGlyph : kUnknownGlyph);
    i += length;
  }
  return glyphs;
}

int textWidth(std::size_t glyphs, int scale) {
  return glyphs == 0 ? 0 : (static_cast<int>(glyphs) * kGlyphAdvance - 1) * scale;
}

int textHeight(int scale) { return kGlyphRows * scale; }

/// The glyphs, cut and ended with "..." if they are wider than `max_width` px.
std::vector<std::size_t> fitText(std::vector<std::size_t> glyphs, int max_width, int scale) {
  if (textWidth(glyphs.size(), scale) <= max_width) return glyphs;
  std::size_t keep = glyphs.size();
  while (keep > 0 && textWidth(keep + 3, scale) > max_width) --keep;
  glyphs.resize(keep);
  glyphs.insert(glyphs.end(), 3, kDotGlyph);
  return glyphs;
}

/// Draws text with its top-left corner at (x, y); `upward` turns it 90 degrees counter-clockwise
/// about that corner, so that it reads from bottom to top and extends up and to the right.
void drawText(Canvas& canvas, const std::vector<std::size_t>& glyphs, int x, int y, int scale,
              bool upward = false) {
  for (std::size_t i = 0; i < glyphs.size(); ++i) {
    const Glyph& glyph = kFont[glyphs[i]];
    for (int row = 0; row < kGlyphRows; ++row) {
      for (int column = 0; column < kGlyphColumns; ++column) {
        if ((glyph[row] & (0x10 >> column)) == 0) continue;
        const int along = (static_cast<int>(i) * kGlyphAdvance + column) * scale;
        const int across = row * scale;
        const PixelRect block =
            upward
                ? PixelRect{x + across, y - along - scale + 1, x + across + scale - 1, y - along}
                : PixelRect{x + along, y + across, x + along + scale - 1, y + across + scale - 1};
        canvas.fill(block, kInk);
      }
    }
  }
}

/// Linear ticks; an end marked `expand` is rounded out to the tick step.
AxisTicks makeLinearTicks(double lo, double hi, int max_ticks, bool expand_lo, bool expand_hi) {
  // A range around zero always needs three ticks (-step, 0, step) once rounded out; any range
  // fits in three once the step exceeds its span, so the step search below ends.
  max_ticks = std::max(max_ticks, 3);
  const double magnitude = std::max(std::abs(lo), std::abs(hi));
  if (hi - lo <= 0.0 || (expand_lo && expand_hi && hi - lo <= kDegenerateSpan * magnitude)) {
    // A constant series: centre it in a range of +-10 % (or +-1 around zero).
    const double centre = lo * 0.5 + hi * 0.5;
    const double pad = magnitude > 1e-290 ? std::abs(centre) * 0.1 : 1.0;
    lo = std::max(centre - pad, -DBL_MAX);
    hi = std::min(centre + pad, DBL_MAX);
  }
  // Halved values keep spans of up to 2 * DBL_MAX finite.
  const double half_span = hi * 0.5 - lo * 0.5;
  const int exponent = static_cast<int>(std::floor(std::log10(half_span / max_ticks * 2.0)));
  constexpr std::array<double, 3> kMantissas{1.0, 2.0, 5.0};
  double step = 0.0;
  double first = 0.0;
  double last = 0.0;
  for (int i = 0;; ++i) {
    step = kMantissas[i % 3] * std::pow(10.0, exponent + i / 3);
    const double lo_steps = lo / step;
    const double hi_steps = hi / step;
    first =
        expand_lo ? std::floor(lo_steps + kTickTolerance) : std::ceil(lo_steps - kTickTolerance);
    last = expand_hi ? std::ceil(hi_steps - kTickTolerance) : std::floor(hi_steps + kTickTolerance);
    // Rounding out past DBL_MAX would make the axis infinite; keep that end as it is.
    if (!std::isfinite(first * step)) first = std::ceil(lo_steps - kTickTolerance);
    if (!std::isfinite(last * step)) last = std::floor(hi_steps + kTickTolerance);
    if (last - first + 1.0 <= max_ticks) break;
  }
  AxisTicks ticks;
  ticks.lo = expand_lo && std::isfinite(first * step) ? std::min(first * step, lo) : lo;
  ticks.hi = expand_hi && std::isfinite(last * step) ? std::max(last * step, hi) : hi;
  // An integer counter: near 2^53 steps from zero, k += 1 would not move.
  const int count = static_cast<int>(std::max(last - first + 1.0, 0.0));
  for (int i = 0; i < count; ++i) {
    ticks.major.push_back((first + i) * step);
    ticks.labels.push_back(formatTickValue(ticks.major.back(), step));
  }
  return ticks;
}

/// log10 ticks; an end marked `expand` is rounded out to a decade.
AxisTicks makeLog10Ticks(double lo, double hi, int max_ticks, bool expand_lo, bool expand_hi) {
  max_ticks = std::max(max_ticks, 2);
  double e_lo = std::log10(lo);
  double e_hi = std::log10(hi);
  if (expand_lo) e_lo = std::floor(e_lo + kTickTolerance);
  if (expand_hi) e_hi = std::ceil(e_hi - kTickTolerance);
  if (e_hi <= e_lo) {
    // A constant power of ten: a decade either side.
    if (expand_lo) e_lo -= 1.0;
    if (expand_hi) e_hi += 1.0;
  }
  // The decades that doubles can hold as normal numbers.
  e_lo = std::max(e_lo, -307.0);
  e_hi = std::min(e_hi, 308.0);
  AxisTicks ticks;
  ticks.lo = expand_lo ? std::pow(10.0, e_lo) : lo;
  ticks.hi = expand_hi ? std::pow(10.0, e_hi) : hi;
  const auto inside = [&ticks](double value) {
    return value >= ticks.lo * (1.0 - 1e-12) && value <= ticks.hi * (1.0 + 1e-12);
  };

  const int first = static_cast<int>(std::ceil(std::log10(ticks.lo) - kTickTolerance));
  const int last = static_cast<int>(std::floor(std::log10(ticks.hi) + kTickTolerance));
  if (last - first + 1 >= 2) {
    int stride = 1;
    constexpr std::array<int, 3> kStrides{1, 2, 5};
    for (int i = 0;; ++i) {
      stride = kStrides[i % 3] * static_cast<int>(std::lround(std::pow(10.0, i / 3)));
      const int count =
          static_cast<int>(std::floor(double(last) / stride) - std::ceil(double(first) / stride)) +
          1;
      if (count <= max_ticks) break;
    }
    const bool fine = stride == 1 && last - first <= 8;
    for (int e = first - 1; e <= last; ++e) {
      const double decade = std::pow(10.0, e);
      if (e >= first && e % stride == 0) {
        ticks.major.push_back(decade);
        ticks.labels.push_back(formatTickValue(decade, decade));
      } else if (e >= first && stride <= 5) {
        ticks.minor.push_back(decade);  // beyond 4 between labels they would blur into grey
      }
      for (int m = 2; fine && m <= 9; ++m) {
        if (inside(m * decade)) ticks.minor.push_back(m * decade);
      }
    }
    return ticks;
  }

  // Less than two decades in view: label 1-2-5 multiples, or every multiple if that is too few.
  const int e0 = static_cast<int>(std::floor(std::log10(ticks.lo) + kTickTolerance));
  const int e1 = static_cast<int>(std::floor(std::log10(ticks.hi) + kTickTolerance));
  std::vector<double> candidates;
  for (int e = e0; e <= e1; ++e) {
    for (int m = 1; m <= 9; ++m) {
      const double value = m * std::pow(10.0, e);
      if (inside(value)) candidates.push_back(value);
    }
  }
  const auto isOneTwoFive = [](double value) {
    const double mantissa = value / std::pow(10.0, std::floor(std::log10(value) + kTickTolerance));
    const long digit = std::lround(mantissa);
    return digit == 1 || digit == 2 || digit == 5;
  };
  const auto preferred = std::count_if(candidates.begin(), candidates.end(), isOneTwoFive);
  for (double value : candidates) {
    if (preferred >= 2 && !isOneTwoFive(value)) {
      ticks.minor.push_back(value);
      continue;
    }
    const double decade = std::pow(10.0, std::floor(std::log10(value) + kTickTolerance));
    ticks.major.push_back(value);
    ticks.labels.push_back(formatTickValue(value, decade));
  }
  return ticks;
}

/// Maps axis values to fractions of the axis length, 0 at `lo` and 1 at `hi`.
struct AxisScale {
  double lo = 0.0;
  double hi = 1.0;
  bool log = false;

  double fraction(double value) const {
    const double f = log ? (std::log10(value) - std::log10(lo)) / (std::log10(hi) - std::log10(lo))
                         : (value * 0.5 - lo * 0.5) / (hi * 0.5 - lo * 0.5);
    return std::clamp(f, -kMaxFraction, kMaxFraction);
  }
};

struct DataRange {
  double min = DBL_MAX;
  double max = -DBL_MAX;
  bool empty() const { return min > max; }
  void add(double value) {
    min = std::min(min, value);
    max = std::max(max, value);
  }
};

/// Sizes of the plot furniture in px, proportional to the text scale.
struct Metrics {
  explicit Metrics(int text_scale)
      : scale(text_scale),
        pad(4 * text_scale),
        gap(2 * text_scale),
        tick(3 * text_scale),
        stroke(std::max(1, text_scale / 2)),
        line_half_width(std::max(1.0, 0.5 * text_scale)),
        dot_radius(1.25 * text_scale + 1.0) {}

  int scale;   ///< Bitmap font scale: 2 at the default image size.
  int pad;     ///< Margin around the image.
  int gap;     ///< Space between neighbouring items.
  int tick;    ///< Tick mark length.
  int stroke;  ///< Frame and tick thickness.
  double line_half_width;
  double dot_radius;  ///< Radius of a point without neighbours.
};

int textScale(int width, int height) {
  const double fit = std::min(width / 600.0, height / 350.0);
  return std::clamp(static_cast<int>(std::lround(fit)), 1, 4);
}

AxisTicks yAxisTicks(const LinePlot& plot, const DataRange& data, int max_ticks) {
  const bool auto_lo = !plot.y_min;
  const bool auto_hi = !plot.y_max;
  double lo = plot.y_min.value_or(data.empty() ? (plot.log_y ? 1.0 : 0.0) : data.min);
  double hi = plot.y_max.value_or(data.empty() ? (plot.log_y ? 10.0 : 1.0) : data.max);
  if (auto_lo != auto_hi && lo >= hi) {
    // All data lies beyond the one fixed end: show a range of the fixed end's size next to it.
    const auto reach = [](double end) { return end != 0.0 ? std::abs(end) : 1.0; };
    if (auto_lo) {
      lo = plot.log_y ? hi / 10.0 : std::max(hi - reach(hi), -DBL_MAX);
    } else {
      hi = plot.log_y ? lo * 10.0 : std::min(lo + reach(lo), DBL_MAX);
    }
  }
  if (plot.log_y) return makeLog10Ticks(lo, hi, max_ticks, auto_lo, auto_hi);
  AxisTicks ticks = makeLinearTicks(lo, hi, max_ticks, auto_lo, auto_hi);
  // A maximum on the top tick would run along the frame: leave a little room above it.
  const double span = ticks.hi - ticks.lo;
  if (auto_hi && !data.empty() && ticks.hi - hi < 0.01 * span && std::isfinite(hi + 0.02 * span)) {
    ticks = makeLinearTicks(lo, hi + 0.02 * span, max_ticks, auto_lo, auto_hi);
  }
  return ticks;
}

int widestLabel(const AxisTicks& ticks, int scale) {
  int widest = 0;
  for (const std::string& label : ticks.labels) {
    widest = std::max(widest, textWidth(glyphsOf(label).size(), scale));
  }
  return widest;
}

/// Where everything goes: the plot area (its frame lies on the rectangle's border pixels), the
/// axes and the texts, fitted to their space.
struct Layout {
  PixelRect plot;
  AxisTicks x_ticks;
  AxisTicks y_ticks;
  AxisScale x_scale;
  AxisScale y_scale;
  int title_scale = 1;
  std::vector<std::size_t> title;
  std::vector<std::size_t> x_label;
  std::vector<std::size_t> y_label;

  Point toPixel(double x, double y) const {
    return {plot.x0 + x_scale.fraction(x) * (plot.x1 - plot.x0),
            plot.y1 - y_scale.fraction(y) * (plot.y1 - plot.y0)};
  }
};

Layout computeLayout(const LinePlot& plot, const DataRange& x_data, const DataRange& y_data,
                     int width, int height, const Metrics& m) {
  Layout layout;
  const int line_height = textHeight(m.scale);
  layout.title = glyphsOf(plot.title);
  layout.title_scale = m.scale + 1;
  if (textWidth(layout.title.size(), layout.title_scale) > width - 2 * m.pad) {
    layout.title_scale = m.scale;
  }
  layout.title = fitText(std::move(layout.title), width - 2 * m.pad, layout.title_scale);
  layout.x_label = glyphsOf(plot.x_label);
  layout.y_label = glyphsOf(plot.y_label);

  const int top =
      m.pad + (layout.title.empty() ? line_height / 2 : textHeight(layout.title_scale) + 2 * m.gap);
  const int bottom = height - 1 - m.pad - m.tick - m.gap - line_height -
                     (layout.x_label.empty() ? 0 : 2 * m.gap + line_height);
  layout.y_ticks = yAxisTicks(plot, y_data, std::clamp((bottom - top) / (32 * m.scale), 2, 10));
  layout.y_label = fitText(std::move(layout.y_label), bottom - top, m.scale);

  // The right margin leaves room for half of a last x tick label of up to 6 characters.
  const int right = width - 1 - m.pad - 3 * kGlyphAdvance * m.scale;
  const int left = std::min(m.pad + (layout.y_label.empty() ? 0 : line_height + 3 * m.gap) +
                                widestLabel(layout.y_ticks, m.scale) + m.gap + m.tick,
                            right - width / 4);
  const double x_lo = x_data.empty() ? 0.0 : x_data.min;
  const double x_hi = x_data.empty() ? 1.0 : x_data.max;
  for (int max_ticks = std::clamp((right - left) / (60 * m.scale), 2, 12);; --max_ticks) {
    layout.x_ticks = makeLinearTicks(x_lo, x_hi, max_ticks, true, true);
    // Rounding out to a tick can leave a wide empty margin (0..899 becoming 0..1000); the data's
    // own end is kept then.
    const double slack = 0.05 * (x_hi - x_lo);
    const bool expand_lo = x_lo - layout.x_ticks.lo <= slack;
    const bool expand_hi = layout.x_ticks.hi - x_hi <= slack;
    const bool degenerate =
        x_hi - x_lo <= kDegenerateSpan * std::max(std::abs(x_lo), std::abs(x_hi));
    if (!degenerate && !(expand_lo && expand_hi)) {
      layout.x_ticks = makeLinearTicks(x_lo, x_hi, max_ticks, expand_lo, expand_hi);
    }
    const std::vector<double>& major = layout.x_ticks.major;
    if (max_ticks == 2 || major.size() < 2) break;
    const AxisScale scale{layout.x_ticks.lo, layout.x_ticks.hi, false};
    const double spacing = (scale.fraction(major[1]) - scale.fraction(major[0])) * (right - left);
    if (spacing >= widestLabel(layout.x_ticks, m.scale) + 2 * kGlyphAdvance * m.scale) break;
  }
  layout.x_label = fitText(std::move(layout.x_label), right - left, m.scale);

  layout.plot = {left, top, right, bottom};
  layout.x_scale = {layout.x_ticks.lo, layout.x_ticks.hi, false};
  layout.y_scale = {layout.y_ticks.lo, layout.y_ticks.hi, plot.log_y};
  return layout;
}

/// Polylines in pixel coordinates: the runs of consecutive drawable points of one series.
using SeriesPath = std::vector<std::vector<Point>>;

SeriesPath pathOf(const PlotSeries& series, const Layout& layout) {
  SeriesPath path;
  bool in_run = false;
  for (std::size_t i = 0; i < series.x.size(); ++i) {
    if (!std::isfinite(series.x[i]) || !std::isfinite(series.y[i])) {
      in_run = false;
      continue;
    }
    if (!in_run) path.emplace_back();
    in_run = true;
    path.back().push_back(layout.toPixel(series.x[i], series.y[i]));
  }
  return path;
}

void drawPath(CoverageMask& mask, const SeriesPath& path, const Metrics& m) {
  for (const std::vector<Point>& run : path) {
    if (run.size() == 1) mask.addDot(run.front(), m.dot_radius);
    for (std::size_t i = 1; i < run.size(); ++i) {
      mask.addSegment(run[i - 1], run[i], m.line_half_width);
    }
  }
}

/// Liang-Barsky: whether segment ab has a point inside `rect`.
bool segmentMeetsRect(Point a, Point b, const PixelRect& rect) {
  const double dx = b.x - a.x;
  const double dy = b.y - a.y;
  const std::array<double, 4> p{-dx, dx, -dy, dy};
  const std::array<double, 4> q{a.x - rect.x0, rect.x1 - a.x, a.y - rect.y0, rect.y1 - a.y};
  double t0 = 0.0;
  double t1 = 1.0;
  for (std::size_t i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
    } else if (p[i] < 0.0) {
      t0 = std::max(t0, q[i] / p[i]);
    } else {
      t1 = std::min(t1, q[i] / p[i]);
    }
  }
  return t0 <= t1;
}

/// How many segments and dots of the data a legend box at `box` would hide.
std::size_t hiddenData(const PixelRect& box, const std::vector<SeriesPath>& paths) {
  std::size_t hidden = 0;
  for (const SeriesPath& path : paths) {
    for (const std::vector<Point>& run : path) {
      if (run.size() == 1) hidden += segmentMeetsRect(run.front(), run.front(), box) ? 1 : 0;
      for (std::size_t i = 1; i < run.size(); ++i) {
        hidden += segmentMeetsRect(run[i - 1], run[i], box) ? 1 : 0;
      }
    }
  }
  return hidden;
}

void drawFrame(Canvas& canvas, const PixelRect& rect, int stroke, Rgb color) {
  canvas.fill({rect.x0 - stroke + 1, rect.y0 - stroke + 1, rect.x1 + stroke - 1, rect.y0}, color);
  canvas.fill({rect.x0 - stroke + 1, rect.y1, rect.x1 + stroke - 1, rect.y1 + stroke - 1}, color);
  canvas.fill({rect.x0 - stroke + 1, rect.y0, rect.x0, rect.y1}, color);
  canvas.fill({rect.x1, rect.y0, rect.x1 + stroke - 1, rect.y1}, color);
}

/// The legend: a sample line and the label of each labelled series, in the corner of the plot
/// area that hides the least data (top right on ties). Entries that do not fit are counted in a
/// last "+N more" row.
void drawLegend(Canvas& canvas, const LinePlot& plot, const std::vector<SeriesPath>& paths,
                const Layout& layout, const Metrics& m) {
  std::vector<std::size_t> entries;
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    if (!plot.series[i].label.empty()) entries.push_back(i);
  }
  const int inner = 3 * m.scale;
  const int row_height = textHeight(m.scale) + m.gap;
  const int max_rows = (layout.plot.height() - 2 * inner - 2 * m.pad) / row_height;
  if (entries.empty() || max_rows < 1) return;
  std::vector<std::vector<std::size_t>> labels;
  const std::size_t shown =
      entries.size() <= std::size_t(max_rows) ? entries.size() : std::size_t(max_rows) - 1;
  const int sample = 10 * m.scale;
  const int max_text = layout.plot.width() / 2;
  int text_width = 0;
  for (std::size_t i = 0; i < shown; ++i) {
    labels.push_back(fitText(glyphsOf(plot.series[entries[i]].label), max_text, m.scale));
    text_width = std::max(text_width, textWidth(labels.back().size(), m.scale));
  }
  std::vector<std::size_t> more;
  if (shown < entries.size()) {
    more = glyphsOf("+" + std::to_string(entries.size() - shown) + " more");
    text_width = std::max(text_width, textWidth(more.size(), m.scale));
  }
  const int rows = static_cast<int>(shown) + (more.empty() ? 0 : 1);
  const int box_width = inner + sample + m.gap * 2 + text_width + inner;
  const int box_height = inner + rows * row_height - m.gap + inner - 2 * m.scale;

  const PixelRect& area = layout.plot;
  const int x_left = area.x0 + m.pad;
  const int x_right = area.x1 - m.pad - box_width + 1;
  const int y_top = area.y0 + m.pad;
  const int y_bottom = area.y1 - m.pad - box_height + 1;
  const std::array<PixelRect, 4> corners{{
      {x_right, y_top, x_right + box_width - 1, y_top + box_height - 1},
      {x_left, y_top, x_left + box_width - 1, y_top + box_height - 1},
      {x_right, y_bottom, x_right + box_width - 1, y_bottom + box_height - 1},
      {x_left, y_bottom, x_left + box_width - 1, y_bottom + box_height - 1},
  }};
  PixelRect box = corners[0];
  std::size_t least = hiddenData(box, paths);
  for (std::size_t i = 1; i < corners.size() && least > 0; ++i) {
    const std::size_t hidden = hiddenData(corners[i], paths);
    if (hidden < least) {
      least = hidden;
      box = corners[i];
    }
  }

  canvas.fill(box, kWhite);
  drawFrame(canvas, box, 1, kLegendBorder);
  CoverageMask mask(box);
  for (int row = 0; row < rows; ++row) {
    const int text_top = box.y0 + inner + row * row_height;
    const int text_left = box.x0 + inner + sample + 2 * m.gap;
    if (row == static_cast<int>(shown)) {
      drawText(canvas, more, text_left, text_top, m.scale);
      continue;
    }
    const double centre = text_top + 0.5 * (kCapRows * m.scale - 1);
    mask.clear();
    mask.addSegment({double(box.x0 + inner), centre}, {double(box.x0 + inner + sample), centre},
                    m.line_half_width);
    mask.compositeOnto(canvas, plotSeriesColor(entries[row]));
    drawText(canvas, labels[row], text_left, text_top, m.scale);
  }
}

Canvas renderPlot(const LinePlot& plot, int width, int height) {
  const Metrics m(textScale(width, height));
  DataRange x_data;
  DataRange y_data;
  for (const PlotSeries& series : plot.series) {
    for (std::size_t i = 0; i < series.x.size(); ++i) {
      if (!std::isfinite(series.x[i]) || !std::isfinite(series.y[i])) continue;
      x_data.add(series.x[i]);
      y_data.add(series.y[i]);
    }
  }
  const Layout layout = computeLayout(plot, x_data, y_data, width, height, m);
  const PixelRect& area = layout.plot;
  Canvas canvas(width, height);

  const auto column = [&layout](double x) {
    return static_cast<int>(std::lround(layout.toPixel(x, layout.y_scale.lo).x));
  };
  const auto row = [&layout](double y) {
    return static_cast<int>(std::lround(layout.toPixel(layout.x_scale.lo, y).y));
  };
  for (double y : layout.y_ticks.minor) canvas.fill({area.x0, row(y), area.x1, row(y)}, kMinorGrid);
  for (double y : layout.y_ticks.major) canvas.fill({area.x0, row(y), area.x1, row(y)}, kMajorGrid);
  for (double x : layout.x_ticks.major) {
    canvas.fill({column(x), area.y0, column(x), area.y1}, kMajorGrid);
  }

  std::vector<SeriesPath> paths;
  CoverageMask mask(area);
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    paths.push_back(pathOf(plot.series[i], layout));
    if (paths.back().empty()) continue;
    mask.clear();
    drawPath(mask, paths.back(), m);
    mask.compositeOnto(canvas, plotSeriesColor(i));
  }

  drawFrame(canvas, area, m.stroke, kInk);
  const int label_top = area.y1 + m.tick + m.gap;
  for (std::size_t i = 0; i < layout.x_ticks.major.size(); ++i) {
    const int x = column(layout.x_ticks.major[i]);
    canvas.fill({x, area.y1 + 1, x + m.stroke - 1, area.y1 + m.tick}, kInk);
    const auto label = glyphsOf(layout.x_ticks.labels[i]);
    const int label_width = textWidth(label.size(), m.scale);
    drawText(canvas, label, std::clamp(x - label_width / 2, 0, std::max(0, width - label_width)),
             label_top, m.scale);
  }
  for (double y : layout.y_ticks.minor) {
    canvas.fill({area.x0 - m.tick / 2, row(y), area.x0 - 1, row(y)}, kInk);
  }
  for (std::size_t i = 0; i < layout.y_ticks.major.size(); ++i) {
    const int y = row(layout.y_ticks.major[i]);
    canvas.fill({area.x0 - m.tick, y, area.x0 - 1, y + m.stroke - 1}, kInk);
    const auto label = glyphsOf(layout.y_ticks.labels[i]);
    drawText(canvas, label, area.x0 - m.tick - m.gap - textWidth(label.size(), m.scale),
             y - kCapRows * m.scale / 2, m.scale);
  }

  const int title_width = textWidth(layout.title.size(), layout.title_scale);
  drawText(canvas, layout.title,
           std::clamp(area.x0 + (area.width() - title_width) / 2, 0, width - title_width), m.pad,
           layout.title_scale);
  const int x_label_width = textWidth(layout.x_label.size(), m.scale);
  drawText(canvas, layout.x_label, area.x0 + (area.width() - x_label_width) / 2,
           label_top + textHeight(m.scale) + 2 * m.gap, m.scale);
  const int y_label_width = textWidth(layout.y_label.size(), m.scale);
  drawText(canvas, layout.y_label, m.pad, area.y0 + (area.height() + y_label_width) / 2, m.scale,
           true);

  drawLegend(canvas, plot, paths, layout, m);
  return canvas;
}

[[noreturn]] void onPngError(png_structp png, png_const_charp /*message*/) { png_longjmp(png, 1); }

void onPngWarning(png_structp /*png*/, png_const_charp /*message*/) {}

void appendPngBytes(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::string*>(png_get_io_ptr(png));
  bool appended = true;
  try {
    out->append(reinterpret_cast<const char*>(data), length);
  } catch (const std::exception&) {
    appended = false;
  }
  if (!appended) png_error(png, "out of memory");
}

void flushPngBytes(png_structp /*png*/) {}

// libpng reports errors by a longjmp back into this frame, which therefore holds only trivially
// destructible objects.
bool writePngImage(png_structp png, png_infop info, png_uint_32 width, png_uint_32 height,
                   png_bytepp rows, std::string* out) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_write_fn(png, out, appendPngBytes, flushPngBytes);
  png_set_IHDR(png, info, width, height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}

std::string encodePng(const Canvas& canvas) {
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, onPngError, onPngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    throw std::runtime_error("line plot: cannot initialise libpng");
  }
  std::vector<png_bytep> rows;
  for (int y = 0; y < canvas.height(); ++y) rows.push_back(const_cast<png_bytep>(canvas.row(y)));
  std::string out;
  const bool written = writePngImage(png, info, png_uint_32(canvas.width()),
                                     png_uint_32(canvas.height()), rows.data(), &out);
  png_destroy_write_struct(&png, &info);
  if (!written) throw std::runtime_error("line plot: libpng failed to encode the image");
  return out;
}

void validate(const LinePlot& plot, int width, int height) {
  if (width < kMinWidthPx || width > kMaxSidePx || height < kMinHeightPx || height > kMaxSidePx) {
    throw std::invalid_argument("line plot: image size " + std::to_string(width) + "x" +
                                std::to_string(height) + " outside [200, 16384] x [150, 16384]");
  }
  for (const auto& [end, name] : {std::pair{plot.y_min, "y_min"}, std::pair{plot.y_max, "y_max"}}) {
    if (end && (!std::isfinite(*end) || (plot.log_y && *end <= 0.0))) {
      throw std::invalid_argument(
          std::string("line plot: ") + name + " = " + std::to_string(*end) +
          (plot.log_y ? " must be finite and > 0 on a log axis" : " must be finite"));
    }
  }
  if (plot.y_min && plot.y_max && !(*plot.y_min < *plot.y_max)) {
    throw std::invalid_argument("line plot: y_min must be below y_max");
  }
  for (const PlotSeries& series : plot.series) {
    if (series.x.size() != series.y.size()) {
      throw std::invalid_argument("line plot: series '" + series.label + "' has " +
                                  std::to_string(series.x.size()) + " x and " +
                                  std::to_string(series.y.size()) + " y values");
    }
    for (std::size_t i = 0; plot.log_y && i < series.y.size(); ++i) {
      if (std::isfinite(series.y[i]) && series.y[i] <= 0.0) {
        throw std::invalid_argument("line plot: series '" + series.label + "' has y[" +
                                    std::to_string(i) + "] = " + std::to_string(series.y[i]) +
                                    " on a log axis");
      }
    }
  }
}

}  // namespace

Rgb plotSeriesColor(std::size_t index) { return kPalette[index % kPalette.size()]; }

AxisTicks linearAxisTicks(double lo, double hi, int max_ticks, bool expand) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || lo > hi) {
    throw std::invalid_argument("linearAxisTicks: need finite lo <= hi");
  }
  if (!expand && lo == hi) throw std::invalid_argument("linearAxisTicks: empty fixed range");
  return makeLinearTicks(lo, hi, max_ticks, expand, expand);
}

AxisTicks log10AxisTicks(double lo, double hi, int max_ticks, bool expand) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo > 0.0) || lo > hi) {
    throw std::invalid_argument("log10AxisTicks: need finite 0 < lo <= hi");
  }
  if (!expand && lo == hi) throw std::invalid_argument("log10AxisTicks: empty fixed range");
  return makeLog10Ticks(lo, hi, max_ticks, expand, expand);
}

std::string formatTickValue(double value, double step) {
  if (!(step > 0.0) || !std::isfinite(step)) step = value != 0.0 ? std::abs(value) : 1.0;
  if (std::abs(value) < step * 1e-9) return "0";
  const int step_exponent = static_cast<int>(std::floor(std::log10(step) + 1e-9));
  std::array<char, 64> buffer{};
  if (step_exponent >= -3 && step_exponent < 5) {
    std::snprintf(buffer.data(), buffer.size(), "%.*f", std::max(0, -step_exponent), value);
    return buffer.data();
  }
  const int value_exponent = static_cast<int>(std::floor(std::log10(std::abs(value)) + 1e-9));
  std::snprintf(buffer.data(), buffer.size(), "%.*e",
                std::clamp(value_exponent - step_exponent, 0, 16), value);
  // "2.50e-05" -> "2.5e-5", "1.0e+06" -> "1e6".
  const std::string text = buffer.data();
  const std::size_t e = text.find('e');
  std::string mantissa = text.substr(0, e);
  if (mantissa.find('.') != std::string::npos) {
    mantissa.erase(mantissa.find_last_not_of('0') + 1);
    if (mantissa.back() == '.') mantissa.pop_back();
  }
  std::string exponent = text.substr(e + 1);
  const bool negative = exponent.front() == '-';
  exponent.erase(0, exponent.find_first_not_of("+-0"));
  return mantissa + "e" + (negative ? "-" : "") + (exponent.empty() ? "0" : exponent);
}

void writeLinePlotPng(const std::filesystem::path& path, const LinePlot& plot, int width_px,
                      int height_px) {
  validate(plot, width_px, height_px);
  const std::string png = encodePng(renderPlot(plot, width_px, height_px));
  terramesh::writeFileAtomically(path, png);
}

}  // namespace terramesh::cli
