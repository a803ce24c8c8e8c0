#pragma once
// A deterministic random source for the simulator. Why not <random>'s distributions: their
// algorithms are implementation-defined, so the same seed could give other numbers with another
// standard library; bit-identical runs by seed need our own. xoshiro256** (Blackman & Vigna) for
// the bits, SplitMix64 to expand a seed, and the Marsaglia polar method for normal deviates.
//
// Every independent part of the rig (each unit's parameter draw, each unit's noise, the chamber,
// the supply, the encoder) gets its own stream: Rng(seed, stream_id). Adding a unit or switching
// an effect therefore never changes the numbers any other part draws.
#include <cmath>
#include <cstdint>

namespace gyrocal::sim {

inline uint64_t SplitMix64(uint64_t& state) {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

class Rng {
public:
    // stream_id separates independent streams of one seed.
    Rng(uint64_t seed, uint64_t stream_id) {
        uint64_t sm = seed ^ (stream_id * 0xD1B54A32D192ED03ull + 0x8CB92BA72F3D8DD7ull);
        for (auto& word : s_) word = SplitMix64(sm);
    }

    uint64_t NextU64() {
        const uint64_t result = Rotl(s_[1] * 5, 7) * 9;
        const uint64_t t = s_[1] << 17;
        s_[2] ^= s_[0];
        s_[3] ^= s_[1];
        s_[1] ^= s_[2];
        s_[0] ^= s_[3];
        s_[2] ^= t;
        s_[3] = Rotl(s_[3], 45);
        return result;
    }

    // Uniform in [0, 1) with 53 random bits.
    double Uniform() { return static_cast<double>(NextU64() >> 11) * 0x1.0p-53; }
    double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
    // +1 or -1 with equal probability.
    double Sign() { return (NextU64() >> 63) ? 1.0 : -1.0; }

    // Standard normal deviate (Marsaglia polar; the second deviate of each pair is cached).
    double Normal() {
        if (has_spare_) {
            has_spare_ = false;
            return spare_;
        }
        double u, v, s;
        do {
            u = 2.0 * Uniform() - 1.0;
            v = 2.0 * Uniform() - 1.0;
            s = u * u + v * v;
        } while (s >= 1.0 || s == 0.0);
        const double m = std::sqrt(-2.0 * std::log(s) / s);
        spare_ = v * m;
        has_spare_ = true;
        return u * m;
    }

private:
    static uint64_t Rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
    uint64_t s_[4];
    double spare_ = 0.0;
    bool has_spare_ = false;
};

// Stream ids: fixed, so that a part's numbers never depend on which other parts exist.
inline constexpr uint64_t kStreamChamber = 1;
inline constexpr uint64_t kStreamSupply = 2;
inline constexpr uint64_t kStreamEncoder = 3;
inline uint64_t UnitParamStream(int unit_index) {
    return 1000 + 2 * static_cast<uint64_t>(unit_index);
}
inline uint64_t UnitNoiseStream(int unit_index) {
    return 1001 + 2 * static_cast<uint64_t>(unit_index);
}

}  // namespace gyrocal::sim
