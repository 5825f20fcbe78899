#pragma once
// Several observers of one run, told of every event in the order they were added: a run's
// recorders (time series, trajectories, checkpoints, progress) and, from Python, its callback.
#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include "ballagg/engines/engine.hpp"

namespace ballagg {

template <int D>
class ObserverList final : public RunObserver<D> {
 public:
  void add(RunObserver<D>* o) { list_.push_back(o); }
  void on_start(const State<D>& s) override { for (auto* o : list_) o->on_start(s); }
  void before_event(const State<D>& s, double t) override { for (auto* o : list_) o->before_event(s, t); }
  void after_event(const State<D>& s, const EventRecord& e, const EngineCounters& c) override {
    for (auto* o : list_) o->after_event(s, e, c);
  }
  void on_finish(const State<D>& s, const RunResult& r) override { for (auto* o : list_) o->on_finish(s, r); }
  bool checkpoint_due() override {
    for (auto* o : list_)
      if (o->checkpoint_due()) return true;
    return false;
  }
  void on_checkpoint_stream(const State<D>& s, const EngineCounters& c,
                            const typename RunObserver<D>::EngineSave& save) override {
    for (auto* o : list_)
      if (o->checkpoint_due()) o->on_checkpoint_stream(s, c, save);
  }
  void on_checkpoint(const State<D>& s, const EngineCounters& c, const std::string& engine_state) override {
    for (auto* o : list_)
      if (o->checkpoint_due()) o->on_checkpoint(s, c, engine_state);
  }
  double next_position_read() const override {
    double t = std::numeric_limits<double>::infinity();
    for (auto* o : list_) t = std::min(t, o->next_position_read());
    return t;
  }

 private:
  std::vector<RunObserver<D>*> list_;
};

}  // namespace ballagg
