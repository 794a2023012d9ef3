#pragma once
// Platform-independent random numbers for the seeded searches (SPEC §5: "fixed seeds for every
// random search" → byte-identical outputs). std::mt19937_64 is fully specified by the C++
// standard, but std::uniform_real_distribution and std::normal_distribution are not (libstdc++,
// libc++ and MSVC draw different sequences), so the distributions are written out here:
//   uniform()  = (next 64-bit word >> 11)·2⁻⁵³          ∈ [0, 1), 53 random bits
//   normal()   = Box–Muller on two uniforms, both outputs used in turn
//   below(k)   = unbiased integer in [0, k) by rejection of the top partial range
// The only platform dependence left is the last-ulp behaviour of std::log/cos/sin/sqrt in the
// C library (sqrt is exact under IEEE 754; glibc's log/sin/cos are correctly rounded in
// practice), so results are identical on every glibc x86-64/arm64 build.
#include <cmath>
#include <cstdint>
#include <random>

namespace rangecal {

class DeterministicRandom {
 public:
  explicit DeterministicRandom(std::uint64_t seed) : engine_(seed) {}

  /// Uniform in [0, 1).
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  /// Uniform in (0, 1] (for divisors and logarithms).
  double uniform_open_zero() { return 1.0 - uniform(); }
  /// Uniform in [a, b).
  double uniform(double a, double b) { return a + (b - a) * uniform(); }

  /// Standard normal N(0, 1) by the Box–Muller transform (both variates used).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = uniform_open_zero();  // (0, 1]: log is finite
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double a = 6.283185307179586476925286766559 * u2;
    spare_ = r * std::sin(a);
    has_spare_ = true;
    return r * std::cos(a);
  }

  /// Uniform integer in [0, k), k ≥ 1, without modulo bias.
  std::uint64_t below(std::uint64_t k) {
    const std::uint64_t limit = UINT64_MAX - UINT64_MAX % k;  // multiple of k
    std::uint64_t x;
    do {
      x = engine_();
    } while (x >= limit);
    return x % k;
  }

  /// +1 or −1 with equal probability.
  double sign() { return (engine_() >> 63) ? 1.0 : -1.0; }

 private:
  std::mt19937_64 engine_;
  double spare_ = 0;
  bool has_spare_ = false;
};

}  // namespace rangecal
