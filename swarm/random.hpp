#pragma once
// The swarm's only source of randomness: one std::mt19937_64 per run, drawn from serially.
//
// mt19937_64's output sequence and its text form (operator<<) are fixed by the C++
// standard, but std::uniform_real_distribution and friends are not: libstdc++, libc++ and
// MSVC give different numbers for the same engine state. The distributions are therefore
// written here, so a seed means the same run on every platform and a checkpoint restores
// the exact stream.

#include <cstdint>
#include <random>
#include <string>

namespace yarnfit::swarm {

class RandomStream {
 public:
  explicit RandomStream(std::uint64_t seed) : m_engine(seed) {}

  // Uniform in [0, 1): the top 53 bits of one draw, so every double of the grid k·2⁻⁵³ is
  // equally likely.
  [[nodiscard]] double uniform();
  // Uniform in [a, b).
  [[nodiscard]] double uniform(double a, double b) { return a + (b - a) * uniform(); }
  // Uniform integer in [0, n), n ≥ 1, without modulo bias (rejection of the short tail).
  [[nodiscard]] std::uint64_t index(std::uint64_t n);

  // The engine's full state as text (the standard's format), and its inverse. restore
  // throws an input Error when the text is not an mt19937_64 state.
  [[nodiscard]] std::string state() const;
  void restore(const std::string& text);

 private:
  std::mt19937_64 m_engine;
};

}  // namespace yarnfit::swarm
