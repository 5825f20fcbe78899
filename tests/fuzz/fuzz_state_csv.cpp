// libFuzzer target: the CSV state reader (initial.file), in 2D and 3D. Any input must
// give a table or one InputError, never a crash, a hang or another exception; an accepted
// table has one entry per sphere in every column.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "ballagg/config/config.hpp"
#include "ballagg/io/state_csv.hpp"

namespace {

template <int D>
void parse(const std::string& text) {
  try {
    const ballagg::SphereTable<D> t = ballagg::parse_state_csv<D>(text, "fuzz.csv");
    const std::size_t n = t.radius.size();
    if (n == 0 || t.position.size() != n || t.velocity.size() != n || t.mass.size() != n || t.line.size() != n ||
        (!t.cluster.empty() && t.cluster.size() != n) || (!t.spin.empty() && t.spin.size() != n))
      std::abort();
  } catch (const ballagg::InputError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  parse<2>(text);
  parse<3>(text);
  return 0;
}
