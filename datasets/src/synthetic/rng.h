#pragma once
// Deterministic random numbers for the synthetic data: the same seed gives the same scene and
// stream on every platform (std:: distributions are implementation-defined, so we derive uniform
// and normal variates from mt19937_64's exactly specified output ourselves).

#include <cmath>
#include <cstdint>
#include <random>

namespace terramesh::datasets::synthetic {

class Rng {
 public:
  /// `stream` separates independent sequences drawn from one seed (e.g. cars and trees), so that
  /// changing how many numbers one consumer draws does not change the others.
  explicit Rng(std::uint64_t seed, std::uint64_t stream = 0) : engine_(mix(seed, stream)) {}

  /// Uniform in [0, 1).
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// True with probability p.
  bool chance(double p) { return uniform() < p; }
  /// Standard normal variate (Box-Muller).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - uniform();  // (0, 1]
    const double u2 = uniform();
    const double radius = std::sqrt(-2.0 * std::log(u1));
    const double angle = 2.0 * M_PI * u2;
    spare_ = radius * std::sin(angle);
    has_spare_ = true;
    return radius * std::cos(angle);
  }

 private:
  /// SplitMix64 of the pair, so nearby seeds and streams give unrelated engines.
  static std::uint64_t mix(std::uint64_t seed, std::uint64_t stream) {
    std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL + stream * 0xD1B54A32D192ED03ULL + 0x632BE59BD9B4E019ULL;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }

  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace terramesh::datasets::synthetic
