#pragma once
// The time-stepping engine's class, shared by the files that define its stages:
//   time_stepping_engine.cpp  one step of §3: advect, detect, the loop (3.1)-(3.2), commit
//   time_stepping_run.cpp     the run around the steps, checkpoints
//   sphere_moves.cpp          a round's solutions moved into the step's positions, and
//                             the step's moves into the state at commit
//   contact_passes.cpp        the contacts of the moved spheres: (3.2)'s new pairs
//   settle.cpp                what a step does when the loop gives up with overlaps left
// The parts with a concept of their own are classes in their own files: StepCells (the
// positions and the cell list), NearPairs, OverlapSightings, BeyondSkinMarks, AdhesiveSet,
// StepBodies, and the solvers of a group (minimisation_problem, retreat, flight_sweep).
#include <optional>
#include <string>
#include <vector>

#include "ballagg/core/adaptive_team.hpp"
#include "ballagg/core/pair_index.hpp"
#include "ballagg/engines/engine.hpp"
#include "ballagg/engines/time_stepping/adhesive_links.hpp"
#include "ballagg/engines/time_stepping/adhesive_set.hpp"
#include "ballagg/engines/time_stepping/beyond_skin_marks.hpp"
#include "ballagg/engines/time_stepping/minimisation_problem.hpp"
#include "ballagg/engines/time_stepping/near_pairs.hpp"
#include "ballagg/engines/time_stepping/overlap_sightings.hpp"
#include "ballagg/engines/time_stepping/sorted_ids.hpp"
#include "ballagg/engines/time_stepping/step_bodies.hpp"
#include "ballagg/engines/time_stepping/step_cells.hpp"
#include "ballagg/engines/time_stepping/step_view.hpp"
#include "ballagg/engines/time_stepping/time_step_rule.hpp"
#include "ballagg/engines/time_stepping/ts_counters.hpp"
#include "ballagg/engines/time_stepping/ts_settings.hpp"

namespace ballagg {

template <int D>
class TimeSteppingEngine final : public Engine<D> {
 public:
  TimeSteppingEngine(const TimeSteppingSettings& settings, DahaProblemSink<D>* sink)
      : settings_(settings), sink_(sink) {}
  std::string_view name() const override { return "ts"; }
  RunResult run(State<D>& s, const StopCriteria& stop, RunObserver<D>& observer) override;
  bool supports_checkpoints() const override { return true; }
  void resume_from(State<D>& s, std::string_view saved) override;

 private:
  // time_stepping_run.cpp. Checkpoints, taken between two steps: all a step leaves behind
  // is the counters, the step rule's reference values and the links of the per-sphere models.
  void save(ByteWriter& w) const;
  void prepare(const State<D>& s);
  bool outside_walls(const State<D>& s) const;

  // time_stepping_engine.cpp: the stages of a step.
  void step(State<D>& s, double t, RunObserver<D>& observer);
  void advect(State<D>& s, double dt);
  void detect_overlaps(const State<D>& s);
  void resolve(const State<D>& s);
  bool round_is_last(int round, std::vector<std::uint64_t>& earlier_rounds);
  void end_of_loop(const State<D>& s, const std::vector<SpherePair>& left);
  std::vector<GroupSolution<D>> minimise_groups(const State<D>& s, const std::vector<CollisionGroup>& groups,
                                                bool out_of_rounds);
  void repair_unsolved(const State<D>& s, const std::vector<CollisionGroup>& groups,
                       std::vector<GroupSolution<D>>& solutions, std::vector<int>& moved);
  GroupSolution<D> repair(const StepView<D>& view, const CollisionGroup& group) const;
  bool beyond_minimisation(const State<D>& s, const CollisionGroup& group) const;
  std::uint64_t round_signature() const;
  bool end_round(const State<D>& s, const std::vector<CollisionGroup>& groups,
                 const std::vector<GroupSolution<D>>& solutions, const std::vector<SpherePair>& overlaps);
  bool link_touching_contacts(const State<D>& s, const std::vector<GroupSolution<D>>& solutions);
  int commit(State<D>& s);
  double residual_overlap() { return sightings_.residual(moved_in_step_); }
  void poll_team() {
    if (team_) team_->poll();
  }

  // sphere_moves.cpp
  struct ApplyPiece {
    const GroupSolution<D>* solution;
    std::size_t begin, end;  // its spheres [begin, end)
    std::size_t at;          // where its spheres go in the round's moved list, and in to_rebin_
    std::size_t n_rebin;     // how many of them moved beyond the cell slack (to_rebin_[at, at + n_rebin))
  };
  void apply(const State<D>& s, const std::vector<const GroupSolution<D>*>& solutions, std::vector<int>& moved);
  void apply(const State<D>& s, const GroupSolution<D>& solution, std::vector<int>& moved) { apply(s, {&solution}, moved); }
  std::size_t count_solutions(const std::vector<const GroupSolution<D>*>& solutions);
  bool move_pieces(const State<D>& s, std::vector<int>& moved, std::size_t first_moved);
  void commit_moves(State<D>& s, std::vector<std::int32_t>& moved_clusters);
  void commit_rigid_moves(State<D>& s, std::vector<std::int32_t>& moved_clusters);

  // contact_passes.cpp
  template <class F>
  void for_each_contact(const State<D>& s, const std::vector<int>& spheres, F&& f) const;
  template <class F>
  void contact_pass(const State<D>& s, const std::vector<int>& moved, F&& f);
  bool needs_no_contact_query(const State<D>& s, int i) const;
  std::vector<SpherePair> new_overlaps(const State<D>& s, std::vector<int>& moved);
  std::vector<std::int32_t> clusters_overlapping_outside(const State<D>& s, std::vector<int>& spheres,
                                                         const std::vector<std::int32_t>& inside);

  // settle.cpp
  void settle(const State<D>& s, const std::vector<SpherePair>& left);
  void return_to_start(const State<D>& s);

  // What the solvers of the round's groups read of the step.
  StepView<D> view(const State<D>& s) const {
    return {.state = s,
            .positions = positions_,
            .step_shift = step_shift_,
            .flight = flight_,
            .bodies = bodies_,
            .cells = cells_.list(),
            .cell_slack = cells_.slack(),
            .S = S_,
            .links = links_,
            .settings = settings_,
            .length_scale = length_scale_,
            .delta_w = delta_w_,
            .mean_mass = mean_mass_,
            .sink = sink_,
            .guard = guard_};
  }
  bool rigid() const { return settings_.model == TsModel::rigid; }
  bool paper() const { return settings_.method == TsMethod::paper; }
  // Whether sphere i may have moved more than the near list's half skin since its
  // cluster's pairs were listed.
  bool beyond_half_skin(const State<D>& s, int i) const {
    return near_.travel(s.spheres.cluster[i]) + step_shift_[i].norm() > 0.5 * near_.skin();
  }
  int body_of_sphere(const State<D>& s, int i) const { return bodies_.body_of(s.spheres.cluster[i]); }

  TimeSteppingSettings settings_;
  DahaProblemSink<D>* sink_;
  TimeSteppingCounters counters_;
  std::optional<Box<D>> box_;
  StepCells<D> cells_;                       // the step's positions and the cell list
  std::vector<Vec<D>>& positions_ = cells_.positions();
  std::vector<Vec<D>> step_shift_;           // per sphere: its displacement by this step's minimisations
  std::vector<Vec<D>> flight_;               // per cluster: its displacement by this step's free flight
  std::vector<ApplyPiece> apply_pieces_;     // within apply(): the work shared among the threads
  std::vector<std::int32_t> to_rebin_;       // within apply(): per piece, its spheres moved beyond the cell slack
  AdhesiveSet S_;                            // the adhesive set of a round and its groups (of bodies)
  StepBodies bodies_;                        // the clusters of the step, joined by its links
  AdhesiveLinks links_;                      // per-sphere models: the links of the old clusters
  NearPairs<D> near_;                        // pairs of spheres of different clusters that may touch
  PairIndex round_contacts_;                 // the pairs the solutions of a round leave touching
  std::vector<int> moved_in_step_;           // spheres moved by this step's minimisations
  OverlapSightings sightings_;               // what the contact passes of the step saw
  // Set: no cluster has moved more than the near-pair list allows since it was listed, so
  // a sphere in no listed pair touches no other cluster (NearPairs::listed). Unset, the
  // marks say where a sphere moved beyond the half skin may be.
  bool near_list_complete_ = false;
  BeyondSkinMarks<D> beyond_skin_;
  double length_scale_ = 1.0, delta_w_ = 0.0, mean_mass_ = 1.0;
  std::optional<TimeStepRule> rule_;         // from the state at the start of the run
  RunGuard* guard_ = nullptr;                // the guard of the run under way
  bool resumed_ = false;                     // resume_from prepared the next run()
  AdaptiveTeam* team_ = nullptr;             // during run(): the team of its parallel regions
};

}  // namespace ballagg
