#pragma once
// Seeded Gaussian and uniform numbers: every simulated run is reproducible from its seed.
#include <cstdint>
#include <random>

namespace rig::sim {

class RandomSource {
 public:
  explicit RandomSource(std::uint64_t seed) : engine_(seed) {}
  double gaussian(double sigma) { return sigma * normal_(engine_); }
  double uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(engine_);
  }
  double sign() { return uniform(0.0, 1.0) < 0.5 ? -1.0 : 1.0; }
  void reseed(std::uint64_t seed) {
    engine_.seed(seed);
    normal_.reset();
  }

 private:
  std::mt19937_64 engine_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

}  // namespace rig::sim
