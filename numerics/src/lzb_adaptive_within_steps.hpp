#pragma once

// The adaptive LZB's within-steps strategy (docs/design/adaptive_lzb.md). An impact whose every
// law is continuous at the switches (e = 1, or bi-stiffness with e > 0: d delta_j/dt = -u_j or
// -u_j / e^2 meet where u_j = 0) keeps them within the steps once enough contacts take part: its
// members, the contacts holding energy or approaching and two rings of their neighbours, all
// carry delta_j and P_j; a contact's delta_j runs below 0 once it separates, its force
// K max(delta_j, 0)^eta switching off by itself, and where it approaches again (u_j turning
// negative, a "closing" turn) it is set back to the clamp, delta_j - delta_j(turn); where an
// inelastic contact's u_j changes sign, delta_j goes on at the other rate. Both are settled
// after the step: the contact integrated again alone from the turn.

#include <cstddef>
#include <span>
#include <vector>

#include "lzb_adaptive_state.hpp"
#include "mimpact/numerics/dense_output.hpp"
#include "mimpact/numerics/impact_integrator.hpp"

namespace mimpact::numerics::adaptive_lzb {

// Where a member's u_j changed sign within a step kept whole.
struct Turn {
  std::size_t member;
  double time;
  bool closing;  // u_j turned negative (else positive: a peak of delta_j)
};

class WithinSteps {
 public:
  using State = DenseOutput::State;

  // Reads and writes `impact`, and reads the steps of `ode`, both the integration's.
  WithinSteps(ImpactState& impact, const DenseOutput& ode) : impact_(impact), ode_(ode) {}
  WithinSteps(const WithinSteps&) = delete;
  WithinSteps& operator=(const WithinSteps&) = delete;

  // A new impact of these laws, kept within the steps from `from` contacts taking part on.
  void prepare(const LawTable& laws, std::size_t from);
  // Whether the segment that starts now keeps its switches within its steps: the laws allow it
  // and the contacts taking part reach `from` (while on: half of it).
  bool choose();
  bool on() const { return on_; }
  // The members of a segment within the steps: the contacts holding energy or approaching
  // faster than tolerance * V, then the ring of their neighbours through H, then the ring of
  // those. The caller sizes the segment.
  void begin_segment();
  // Active member a's phase at the segment's end, from its delta_j and u_j; an outer ring's
  // contact whose impulse grew by `increment` (N s) moves the contacts beyond the members.
  void end_member(std::size_t a, double increment);
  // Appends the contacts a member's impulse set approaching to `members` (a segment that
  // locates its switches takes them).
  void hand_pending(std::vector<Eigen::Index>& members);
  // Where a member's u_j changes sign within [t0, t1] (the step just taken).
  void locate_turns(double t0, double t1, const Watched& before, const Watched& after);
  // The peaks and closings of the step [t0, t1] just taken; true if one changed the state (then
  // settled() holds it).
  bool settle_turns(double t0, double t1);
  const State& settled() const { return y_settled_; }
  // A contact of the outer ring holds energy or approaches at the state y: its neighbours must
  // join.
  bool outgrown(const State& y) const;

 private:
  double member_velocity_at(const DenseOutput::Weights& w, std::size_t member) const;
  bool settle_member(double t0, double t1, std::span<const Turn> turns);

  ImpactState& impact_;
  const DenseOutput& ode_;
  bool continuous_laws_ = false;       // every contact's law continuous at its switches
  bool on_ = false;                    // the current segment keeps its switches within its steps
  std::size_t enter_ = 0, leave_ = 0;  // contacts taking part
  std::vector<unsigned char> ring_;    // per member: 0 holding energy or approaching, 1, 2 around
  std::vector<Turn> turns_;            // by member, then time, once settle_turns sorts them
  State y_settled_;                    // the state at a step's end with its turns settled
  std::vector<Eigen::Index> pending_;  // non-members a member's impulse set approaching
};

}  // namespace mimpact::numerics::adaptive_lzb
