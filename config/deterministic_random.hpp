#pragma once
// Platform-independent random numbers (docs/outputs.md: "fixed seeds for every random search" →
// byte-identical outputs). The distributions are written out once here, because the standard
// library's std::uniform_real_distribution and std::normal_distribution are not specified to the
// bit (libstdc++, libc++ and MSVC draw different sequences):
//   uniform()  = (next 64-bit word >> 11)·2⁻⁵³          ∈ [0, 1), 53 random bits
//   normal()   = Box–Muller on two uniforms, both outputs used in turn
//   below(k)   = unbiased integer in [0, k) by rejection of the top partial range
// over one of three fully specified engines, each kept where its streams are part of published
// figures (the demo's tables, the seed tests):
//   std::mt19937_64     the searches (sparrow search, Monte Carlo)
//   Xoshiro256StarStar  the simulator and the frame renderer (Blackman & Vigna 2018)
//   SplitMix64          RANSAC sampling (Steele, Lea & Flood 2014)
// and one seed mixer, so each purpose (GNSS noise, frame n of camera c, trial t, …) draws from its
// own stream and adding frames or trials never changes the other draws. The only platform
// dependence left is the last-ulp behaviour of std::log/cos/sin in the C library (glibc's are
// correctly rounded in practice), so results are identical on every glibc x86-64/arm64 build.
#include <cmath>
#include <cstdint>
#include <random>

namespace rangecal {

/// SplitMix64 as a generator: state += golden gamma, then the avalanche mix.
struct SplitMix64 {
  std::uint64_t state;
  explicit SplitMix64(std::uint64_t seed) : state(seed) {}
  std::uint64_t operator()() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
};

/// xoshiro256** (Blackman & Vigna 2018), its four words seeded by SplitMix64 from `seed`.
class Xoshiro256StarStar {
 public:
  explicit Xoshiro256StarStar(std::uint64_t seed) {
    SplitMix64 sm(seed);
    for (auto& s : s_) s = sm();
  }
  std::uint64_t operator()() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t s_[4];
};

/// The distributions over an engine (a callable returning uniform 64-bit words).
template <typename Engine>
class BasicDeterministicRandom {
 public:
  explicit BasicDeterministicRandom(std::uint64_t seed) : engine_(seed) {}

  /// The next 64-bit word.
  std::uint64_t next() { return engine_(); }
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
  Engine engine_;
  double spare_ = 0;
  bool has_spare_ = false;
};

using DeterministicRandom = BasicDeterministicRandom<std::mt19937_64>;  ///< searches, Monte Carlo
using RenderRandom = BasicDeterministicRandom<Xoshiro256StarStar>;      ///< simulator, renderer
using SampleRandom = BasicDeterministicRandom<SplitMix64>;              ///< RANSAC

/// The seed of one purpose's stream: `seed` mixed with up to three stream ids (a purpose, a
/// camera, a frame …), boost::hash_combine-style with a SplitMix-like avalanche per id.
inline std::uint64_t mix_seed(std::uint64_t seed, std::uint64_t a, std::uint64_t b = 0, std::uint64_t c = 0) {
  std::uint64_t h = seed ^ 0x243F6A8885A308D3ull;
  for (std::uint64_t x : {a, b, c}) {
    h ^= x + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h = (h ^ (h >> 31)) * 0xBF58476D1CE4E5B9ull;
    h ^= h >> 29;
  }
  return h;
}

}  // namespace rangecal
