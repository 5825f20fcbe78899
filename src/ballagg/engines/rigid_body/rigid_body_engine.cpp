// The rigid-body engine (Richardson 1995). Bodies fly and spin freely between events; an
// event is one of
//   collision       two spheres of different bodies touch: stick (8)-(12), bounce
//                   (13)-(28), or break up (§2.6), as collision.outcome decides;
//   wall            a sphere touches a wall: an elastic, frictionless impulse;
//   contact_search  resume the search for the first contact of two bodies at least one of
//                   which rotates (or of a rotating body and a wall);
//   list_rebuild    a body may have moved half the skin: its neighbour lists expire.
//
// Detection (§2.3). Each sphere lists the spheres of other bodies whose bins (where they
// were put on the cell grid) are within sigma + skin of its own, as in the event-driven
// engine (engines/event_driven/neighbor_keeper.hpp); a sphere's drift from its bin is
// bounded by its body's translation plus the rotation of its lever arm. Two bodies can only touch through
// listed pairs. If neither rotates (single spheres, or no spin) their pairs' contact times
// are exact roots (eq. A.3 of Degond et al.) as in `ed`. Otherwise the bounding spheres of
// radius R_max (7) are tested first, and then the listed pairs sphere by sphere on the
// rotating trajectories, by conservative advancement (contact_search.hpp): a search runs
// until it finds the contact (within kContactGap of a diameter), until the next event
// in the calendar (which might change either body: the search resumes after it), or until
// the lists expire (a rebuild re-predicts).
//
// Positions: a body's centre of mass is the state's cluster anchor, a straight line; its
// orientation comes from the exact free-rotation propagator. The state's sphere offsets
// are written only when an observer reads them (RunObserver::next_position_read) and at
// the end.
#include "ballagg/engines/rigid_body/rigid_body_engine.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "ballagg/engines/event_driven/event_driven_engine.hpp"
#include "ballagg/engines/event_driven/event_loop.hpp"
#include "ballagg/engines/rigid_body/rigid_body_core.hpp"

namespace ballagg {
namespace {

// Keeps the state exact whenever an observer reads it (RunObserver::next_position_read).
template <int D>
class ObservedState final : public RunObserver<D> {
 public:
  ObservedState(RigidBodyCore<D>& core, State<D>& state, RunObserver<D>& inner)
      : core_(core), s_(state), inner_(inner) {}

  void on_start(const State<D>& s) override {
    if (!core_.take_resumed()) core_.write_state(s.time);
    inner_.on_start(s);
  }
  void before_event(const State<D>& s, double t) override {
    for (double read = inner_.next_position_read(); read < t && read >= s_.time;) {
      s_.time = read;
      core_.write_state(read);
      inner_.before_event(s, std::nextafter(read, kNever));
      const double next = inner_.next_position_read();
      if (!(next > read)) break;  // the observer did not move on: do not loop
      read = next;
    }
    inner_.before_event(s, t);
  }
  void after_event(const State<D>& s, const EventRecord& e, const EngineCounters& c) override {
    if (inner_.next_position_read() <= s.time) core_.write_state(s.time);
    inner_.after_event(s, e, c);
  }
  void on_finish(const State<D>& s, const RunResult& r) override {
    core_.write_state(s.time);
    inner_.on_finish(s, r);
  }
  bool checkpoint_due() override { return inner_.checkpoint_due(); }
  void on_checkpoint_stream(const State<D>& s, const EngineCounters& c,
                            const typename RunObserver<D>::EngineSave& save) override {
    inner_.on_checkpoint_stream(s, c, save);
  }
  void on_checkpoint(const State<D>& s, const EngineCounters& c, const std::string& engine_state) override {
    inner_.on_checkpoint(s, c, engine_state);
  }

 private:
  RigidBodyCore<D>& core_;
  State<D>& s_;
  RunObserver<D>& inner_;
};

}  // namespace

template <int D>
RunResult RigidBodyCore<D>::run(State<D>& state, const StopCriteria& stop, RunObserver<D>& observer) {
  set_aggregated_target(stop.aggregated_fraction);
  ObservedState<D> observed(*this, state, observer);
  const RunResult r = run_event_loop(*this, state, stop, observed);
  write_state(state.time);
  return r;
}

template <int D>
double rigid_body_skin(const State<D>& s) {
  // The rule of an aggregating gas: bodies that bounce are still re-predicted pair by pair
  // after each merge and each bounce, as aggregates are in `ed`.
  return std::min(default_skin(s, CollisionOutcome::stick), kSkinDiameters * 2.0 * s.mean_radius());
}

template <int D>
std::unique_ptr<Engine<D>> make_rigid_body_engine(const RigidBodySettings& settings) {
  return std::make_unique<EventLoopEngine<D, RigidBodyCore<D>>>("rigid-body", settings);
}

template double rigid_body_skin<2>(const State<2>&);
template double rigid_body_skin<3>(const State<3>&);
template std::unique_ptr<Engine<2>> make_rigid_body_engine<2>(const RigidBodySettings&);
template std::unique_ptr<Engine<3>> make_rigid_body_engine<3>(const RigidBodySettings&);

}  // namespace ballagg
