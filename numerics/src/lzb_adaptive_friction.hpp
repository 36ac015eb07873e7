#pragma once

// Coulomb friction in the adaptive LZB impact (docs/model.md, "Friction"). Beside each active
// contact's delta_j and normal impulse P_j, a contact with friction mu_j > 0 carries its
// tangential impulse P_t (one row in the plane, two in space) in the ODE state, driven by its
// coulomb::Phase with F_j = dP_j/dt as the normal force; its switches are located as events
// (EventKind).

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <array>
#include <cstddef>
#include <vector>

#include "lzb_adaptive_state.hpp"
#include "mimpact/numerics/coulomb_phase.hpp"
#include "mimpact/numerics/dense_output.hpp"
#include "mimpact/numerics/event_scan.hpp"
#include "mimpact/numerics/impact_integrator.hpp"

namespace mimpact::numerics::adaptive_lzb {

class Friction {
 public:
  using State = DenseOutput::State;

  // Reads and writes `impact`, and reads the steps of `ode`, both the integration's.
  Friction(ImpactState& impact, const DenseOutput& ode) : impact_(impact), ode_(ode) {}
  Friction(const Friction&) = delete;
  Friction& operator=(const Friction&) = delete;

  // A new impact: on when some contact's friction is > 0 (the input then has tangential rows).
  void prepare(const ImpactIntegrator::Input& input);
  bool on() const { return on_; }

  // Appends to the segment's members the contacts whose u_j an active frictional contact's
  // P_t moves (its rows' columns of H_tn^T).
  void add_reached();
  // After the normal part of the segment's state is sized: the active frictional contacts'
  // rows appended to y (zero increments), each contact's slip at the segment's start, and the
  // mode of the contacts that are new or switched: slip where |s| > tolerance * V, else stick
  // where the force that keeps it is within the cone, else slip where that force points.
  void size_segment();

  // + H_tn^T dP_t onto the members' normal velocities at y (member order)
  void push_normal(const State& y, std::vector<double>& velocity) const;
  // the same onto contact j's alone (its column of H_tn)
  double normal_increment(const State& y, Eigen::Index j) const;
  // the tangential rows' derivatives at y, scaled as their impulses
  void derivative(const State& y, State& dydt);

  // two values per frictional member, > 0 before its switch (EventKind): the first for its
  // slip stopping or its stick ending, the second for a slip from rest growing free
  void watch(const State& y, std::vector<double>& values);
  // the switches of [t0, t1] (the segment began at segment_start), narrowed on the dense output
  void locate(double t0, double t1, double segment_start, const std::vector<double>& before,
              const std::vector<double>& after, std::vector<Crossing>& found);
  // a switch at the segment's end (after end_segment): the contact's mode chosen again
  void apply(const Crossing& crossing);

  // each contact's slip work since the last accounting, by the trapezoidal rule on s
  void account_work(const State& y);
  // the segment's P_t increments into the contacts' totals
  void end_segment(const State& y);
  // row r's P_t (N s): its total at the segment's start, plus its increment at y (none: null)
  double tangential_impulse(Eigen::Index row, const State* y) const;
  void finish(ImpactResult& result) const;

 private:
  using Mode = coulomb::Phase::Mode;
  struct Member {
    std::size_t active;  // its place among the segment's active members
    Eigen::Index contact, row;
    int rows;
    std::size_t slot;  // its first row's place among the segment's tangential rows
  };

  double scale(std::size_t slot) const;  // the P_t scale of a slot (its contact's)
  // F of the active members at y; `start`: a contact at delta = 0 approaching gets the force of
  // a small indentation instead, so that the mode chosen at its start is that of its growth
  void normal_forces(const State& y, bool start);
  void slips(const State& y);  // s of the slots at y
  void rates();                // dP_t/dt of the slots from the scratch's forces and slips
  void factor_stick();
  void choose_modes();
  // the member's two watched values at y (watch), or one of them
  double value(std::size_t member, int which, const State& y);
  std::array<double, 2> values_of(const Member& member) const;  // from the scratch

  struct ContactFriction {  // across segments
    coulomb::Phase phase;
    double slip_work = 0.0;  // J
  };
  struct Slot {  // one tangential row of the segment
    Eigen::Index row = 0;
    std::size_t member = 0;  // its contact's place in members_
    double start = 0.0;      // s at the segment's start (m/s)
    double accounted_slip = 0.0, accounted_impulse = 0.0;
    int stick = -1;  // its place in the sticking rows' system, -1 if slipping
  };
  struct Scratch {
    std::vector<double> forces, slips, rates;  // per active member, per slot, per slot
    Eigen::VectorXd stick_rhs;
  };

  ImpactState& impact_;
  const DenseOutput& ode_;
  bool on_ = false;
  const TangentialRows* rows_ = nullptr;
  const Eigen::SparseMatrix<double>* tangent_to_normal_ = nullptr;  // H_tn^T
  std::vector<double> mu_;
  std::vector<ContactFriction> contacts_;
  std::vector<double> impulse_;   // per row: P_t at the segment's start (N s)
  std::vector<int> slot_of_row_;  // per row: its slot, -1 outside the segment
  std::vector<Member> members_;
  std::vector<Eigen::Index> previous_;  // the previous segment's frictional contacts
  std::size_t base_ = 0;                // the first slot's place in y
  std::vector<Slot> slots_;
  std::vector<std::size_t> stick_slots_;
  Eigen::LDLT<Eigen::MatrixXd> stick_factor_;  // H_tt on the sticking rows
  Scratch scratch_;
};

}  // namespace mimpact::numerics::adaptive_lzb
