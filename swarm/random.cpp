#include "swarm/random.hpp"
#include "numerics/util/error.hpp"

#include <cassert>
#include <limits>
#include <locale>
#include <sstream>
#include <stdexcept>

namespace yarnfit::swarm {

double RandomStream::uniform() {
  return static_cast<double>(m_engine() >> 11) * 0x1.0p-53;
}

std::uint64_t RandomStream::index(std::uint64_t n) {
  assert(n >= 1);
  // Accept draws below the largest multiple of n that fits in 2⁶⁴; the rest would favour
  // small results.
  const std::uint64_t limit = std::numeric_limits<std::uint64_t>::max() - std::numeric_limits<std::uint64_t>::max() % n;
  std::uint64_t r = m_engine();
  while (r >= limit) r = m_engine();
  return r % n;
}

std::string RandomStream::state() const {
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out << m_engine;
  return out.str();
}

void RandomStream::restore(const std::string& text) {
  std::istringstream in(text);
  in.imbue(std::locale::classic());
  std::mt19937_64 engine;
  in >> engine;
  if (in.fail()) throw Error(ErrorCategory::input, "random state: not an mt19937_64 state");
  in >> std::ws;
  if (!in.eof()) throw Error(ErrorCategory::input, "random state: unexpected text after the mt19937_64 state");
  m_engine = engine;
}

}  // namespace yarnfit::swarm
