#pragma once
// A State saved into a checkpoint and restored from it bit for bit: the spheres, the
// clusters (stamps included: the event-driven engine's saved events refer to them) and
// the state's own bookkeeping (the order of the live clusters, which engines iterate;
// the running totals, which timeseries.csv prints). A restored state continues exactly as
// the saved one would have.
#include <string>
#include <string_view>

#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/state.hpp"

namespace ballagg {

template <int D>
struct StateCodec {
  static std::string encode(const State<D>& s);
  // The same bytes put into w (a checkpoint file streamed, never holding them whole).
  static void encode(const State<D>& s, ByteWriter& w);
  // Throws CheckpointError (naming what is wrong) for bytes that are not a saved state
  // of dimension D, including one whose indices are out of range.
  static State<D> decode(std::string_view bytes);
};

extern template struct StateCodec<2>;
extern template struct StateCodec<3>;

}  // namespace ballagg
