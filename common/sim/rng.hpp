#pragma once
/// Deterministic randomness for the simulator. Per-pixel noise is a pure function of
/// (seed, frame, x, y, channel), so any thread order gives the same bytes; scene set-up uses the
/// sequential Rng below, from one thread.
#include <cmath>
#include <cstdint>

namespace df::sim {

/// SplitMix64 finaliser: a bijective 64-bit mix.
inline uint64_t mix64(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

inline uint64_t hash64(uint64_t seed, uint64_t a, uint64_t b = 0, uint64_t c = 0, uint64_t d = 0) {
    uint64_t h = mix64(seed ^ 0x6A09E667F3BCC909ull);
    h = mix64(h ^ a);
    h = mix64(h ^ (b + 0x3C6EF372FE94F82Bull));
    h = mix64(h ^ (c + 0xA54FF53A5F1D36F1ull));
    return mix64(h ^ (d + 0x510E527FADE682D1ull));
}

/// Uniform in [0, 1) from the top 53 bits.
inline double unit_from_bits(uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

inline double hash01(uint64_t seed, uint64_t a, uint64_t b = 0, uint64_t c = 0, uint64_t d = 0) {
    return unit_from_bits(hash64(seed, a, b, c, d));
}

/// Approximately standard normal from one hash: the sum of four 16-bit uniforms (Irwin-Hall),
/// rescaled to unit variance. Bounded by +-3.46; cheap enough for every pixel of every frame.
inline double normal_from_bits(uint64_t h) {
    double sum = 0;
    for (int k = 0; k < 4; ++k) sum += static_cast<double>((h >> (16 * k)) & 0xFFFF) + 0.5;
    return (sum * (1.0 / 65536.0) - 2.0) * 1.7320508075688772;
}

inline double hash_normal(uint64_t seed, uint64_t a, uint64_t b = 0, uint64_t c = 0,
                          uint64_t d = 0) {
    return normal_from_bits(hash64(seed, a, b, c, d));
}

/// Sequential generator for scene set-up and surface sampling (single thread).
class Rng {
  public:
    explicit Rng(uint64_t seed) : state_(mix64(seed ^ 0xD1B54A32D192ED03ull)) {}
    uint64_t next() {
        state_ += 0x9E3779B97F4A7C15ull;
        return mix64(state_);
    }
    double uniform() { return unit_from_bits(next()); }
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    double normal() { return normal_from_bits(next()); }
    /// Integer in [0, n).
    int index(int n) { return static_cast<int>(uniform() * n); }

  private:
    uint64_t state_;
};

}  // namespace df::sim
