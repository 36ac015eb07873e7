#pragma once

// One group of the moving-geometry integration (moving_contacts.hpp): the bodies linked by
// loaded contacts, integrated over a window on their own. The windows (moving_contacts.cpp)
// form, meet, merge and commit groups; a group reads and writes only the world they share
// (moving_world.hpp).

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "mimpact/numerics/contact_events.hpp"
#include "mimpact/numerics/dense_output.hpp"
#include "mimpact/numerics/onset_quadrature.hpp"
#include "mimpact/numerics/runge_kutta_nystrom.hpp"
#include "moving_world.hpp"

namespace mimpact::granular {

// the tangent (-n_y, n_x) of a planar contact of normal n, n x t = z
inline Eigen::Vector3d planar_tangent(const Eigen::Vector3d& normal) {
  return {-normal.y(), normal.x(), 0.0};
}

class MovingGroup {
 public:
  MovingGroup(MovingWorld& world, std::int32_t id) : world_(world), id_(id) {}

  // Takes `members` (which it owns from now) from `start`, their contacts as the world last
  // committed them; integrate() starts it.
  void begin(double start, const std::vector<std::int32_t>& members);
  // Starts again as group `id` from `start` with `members`, many of them its own (in the window
  // before, or in this window before it met another group): it keeps the contacts among those,
  // as the world last committed them, and pairs only the bodies new to it (pairing every
  // member anew at every window was a fifth of a 100 x 100 run).
  void carry_on(std::int32_t id, double start, const std::vector<std::int32_t>& members);
  // Takes bodies flying freely that meet within the window, `first` and `second` (< 0: a wall)
  // the earliest, at `start`; the others' contacts join as they close.
  void begin_collision(double start, const std::vector<std::int32_t>& members, std::int32_t first,
                       std::int32_t second);
  // Integrates from its start to `end`, restarting at its own events.
  void integrate(double end);
  // Writes its members' states at the end and its contacts into the world.
  void commit();
  // Gives back the bodies it owns (the window is integrated again without it).
  void release();

  std::int32_t id() const { return id_; }
  double start() const { return start_; }
  // the bodies it owns: those it started with, then those it took as they touched it
  const std::vector<std::int32_t>& members() const { return members_; }
  double last_step() const { return last_step_; }  // s, 0 before its first
  // position (m) of member slot `m` at the end of its integration
  Eigen::Vector3d final_position(std::int32_t slot) const;

 private:
  // A contact of two members, or of a member and a wall: its slots (second < 0: -1 - wall), its
  // law and history, and its record's id in the world (-1: not recorded yet). Every contact is
  // a force of the positions in the right-hand side, closing and opening without an event: an
  // elastic one (e = 1) K max(delta, 0)^eta, an inelastic one the bi-stiffness curves from its
  // largest overlap, its history, which changes only where the overlap turns above it (found
  // within a step, and the step amended: amend_switches) and is forgotten where it opens.
  struct Contact : ContactState {
    std::int32_t world_id = -1;
    std::int32_t first_body = 0, second_body = 0;  // world bodies (second < 0: -1 - wall)
    std::int32_t first = 0, second = 0;            // member slots (second < 0: -1 - wall)
    double reach = 0.0;        // m: the sum of the radii, or the bead's radius against a wall
    bool loaded = false;       // overlapping at the last move (force: its force there)
    double compression = 0.0;  // m, at the last move
    std::int32_t slot = -1;    // of its impulse in the state, while in the right-hand side
    Eigen::Vector3d anchor_offset = Eigen::Vector3d::Zero();  // m: the second's anchor less the
                                                              // first's (two members)
  };
  // A contact in the right-hand side as the right-hand side reads it, contiguous, in the order
  // of springs_.active (its impulse's slot is its index), with its reach and stiffness in arrays
  // beside it; a law aside for the few that follow the bi-stiffness curves or touch a wall.
  struct Spring {
    std::int32_t first = 0, second = 0;  // member slots (second < 0: -1 - wall)
    std::int32_t aside = -1;  // of springs_.aside, or -1: elastic Hertz between two members
    // m: the second's anchor and origin less the first's; against a wall, its unit normal
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  };
  // A spring whose law the right-hand side reads from its contact (contacts_[contact], its
  // ContactState: the law and the history).
  struct SpringAside {
    std::int32_t contact = 0;  // its index in contacts_
    std::int32_t spring = 0;   // its index in springs_.list
    double height = 0.0;       // m, against a wall: the first's anchor and origin above it
  };
  // An elastic spring's largest force (N), and when (s).
  struct Peak {
    double max_force = 0.0, time_of_max = 0.0;
  };
  // A member and a body flying freely, which it takes when they touch.
  struct Watch {
    std::int32_t member = 0;  // slot
    std::int32_t other = 0;   // world body
  };
  // Gaps (m) and rates (m/s) of the scanned entries at one time.
  struct Samples {
    std::vector<double> gap, rate;
  };
  // A body taken where it touches a member (a restart).
  struct Event {
    std::size_t entry = 0;  // of search_.watched
    double time = 0.0;
  };
  // An inelastic spring's history changed within the step just taken (amend_switches): where
  // it turned above its history (its overlap there, m, and the history from then on), or
  // opened (0); at time (s), which the group passes before the spring's law changes for it
  // (settle_histories).
  struct HistoryChange {
    std::int32_t spring = 0;
    double time = 0.0, overlap = 0.0, max_compression = 0.0;
  };

  void add_member(std::int32_t body);
  // c's state as the world last committed it (world_id), or that of a contact never loaded
  void recall(Contact& c) const;
  // the contact of the two (a body and -1 - wall), as the world last committed it or new
  void add_contact(std::int32_t first_body, std::int32_t second_body);
  // the contacts of the members that joined since the last call with the other members and
  // the walls
  void pair_new_members();
  void restart(double t);
  // The integration restarted: its first step (s), and its controller's memory
  // (RungeKuttaNystrom::restart's last_error).
  struct StepStart {
    double step = 0.0, last_error = 0.0;
  };
  StepStart step_start() const;
  void rhs(const double* y, double* dydt);
  template <int D>
  void rhs_in(const double* y, double* dydt);
  // With friction (world_.rough; moving_group_rough.cpp): the state holds, after the impulses,
  // each member's spin as T r omega (m; one component in the plane, three in space), each
  // spring's tangential impulse on its second body (T p_t / m_s, m) and its stretch (m), D
  // components each, then each spring's slip work (J, times T / (m_s speed_bound): m); the
  // group steps by Dormand-Prince 5(4) (rough_), the forces reading the
  // velocities. Every contact is Hertz's with Mindlin's spring under Coulomb's cap
  // (numerics::mindlin::rates_by_state; docs/friction.md, section 3) and LAMMPS's conventions:
  // the slip with the full radii, the torque's lever r - delta/2 between beads, r at a wall.
  struct RoughLayout {
    std::size_t spins = 0, tangential = 0, stretches = 0, works = 0;  // first slots
    int spin_size = 1;
    // a spring's stretch: in the plane its one component along the tangent (-n_y, n_x), which
    // turns with the normal; in space three
    std::size_t stretch_size = 1;
  };
  // A rough spring's contact along the state y: the normal n from its first body to its second
  // (a wall: against the wall's normal), their distance (m; 0 at a wall) and overlap (m), the
  // second's velocity less the first's, r_a w_a + r_b w_b (m/s).
  struct RoughKinematics {
    Eigen::Vector3d normal, relative, rolling;
    double distance = 0.0, delta = 0.0;
  };
  template <int D>
  RoughKinematics rough_kinematics(std::size_t spring, const double* y) const;
  template <int D>
  Eigen::Vector3d rolling_of(std::size_t member, const double* y) const;  // r omega (m/s)
  // What both rough right-hand sides add to, zeroed (x' = w / T written): the members'
  // accelerations and spins' rates, and the scales of the state's units.
  struct RoughRates {
    double *acceleration, *spin_rate;
    double inverse_T, impulse_rate, work_rate;  // 1 / T, T / m_s, T / (m_s speed_bound)
  };
  RoughRates start_rough_rhs(const double* y, double* dydt) const;
  void rhs_planar_rough(const double* y, double* dydt);
  void rhs_spatial_rough(const double* y, double* dydt);
  void restart_rough();  // y_ extended past the impulses, from the members and contacts
  // The regimes a rough spring went through in the right-hand side's calls since the last step
  // (bits; numerics::mindlin::ByState's shifted above kOpen), and its last.
  enum RegimeBit : std::uint8_t { kOpen = 1, kUnderCap = 2, kOnCap = 4, kSlipping = 8 };
  void note_regime(std::size_t spring, std::uint8_t regime) {
    springs_.regimes[spring] |= regime;
    springs_.last_regime[spring] = regime;
  }
  // After a step of a rough group (moving_group_amend.cpp): each spring whose regime changed
  // within it, its stretch's rate jumping, and in space each that slipped in it (its direction
  // turns toward the slip's at |s| / r_c, stiffly), is integrated again along the step's
  // continuous extension with its switches located (numerics::mindlin::PlanarPlay,
  // SpatialPlay), and the step's end amended by what the stages missed of its tangential
  // impulse, its torques, its slip work and its stretch.
  void amend_rough_step();
  void sample_rough_nodes();  // rough_nodes_ over the step just taken
  // The same amendment, at the share `share` of the last step, of y there (the pair's own
  // dense output): the springs amended at its end, integrated to `share`.
  void amend_rough(double share, std::vector<double>& y) const;
  template <int D>
  void amend_rough_in(double share, std::vector<double>& y) const;
  // Spring j's part: its missed impulse into y (the kinetic energy it gives booked as slip
  // work), and what that impulse would have moved its bodies by over the step into `moved`
  // (per member: the displacement, m, and r times the turn, m; three each); returns that
  // moment's size.
  template <int D>
  double amend_spring(std::size_t spring, double share, std::vector<double>& y,
                      std::vector<double>& moved) const;
  // Spring j's missed impulse (N s, on its second body) and its moment (N s times the step's
  // share) into its bodies' velocities and spins in y, and their moves into `moved`; returns
  // the kinetic energy (J) it gave them.
  template <int D>
  double push_missed(std::size_t spring, const Eigen::Vector3d& missed,
                     const Eigen::Vector3d& missed_moment, std::vector<double>& y,
                     std::vector<double>& moved) const;
  // The stretches of the planar springs that slipped throughout the last step put on their caps.
  void put_on_caps(std::vector<double>& y) const;
  // The bodies moved, and the stretches of the sticking springs on them with the slip that
  // makes; returns the energy (J) their normal springs gained.
  template <int D>
  double move_bodies(const std::vector<double>& moved, std::vector<double>& y) const;
  template <int D>
  double kinetic_energy(std::size_t member, const std::vector<double>& y) const;  // J, with spin
  template <int D>
  double normal_energy(std::size_t spring, const std::vector<double>& y) const;  // J
  // Takes out of a step's error estimate what the amended springs (so far: in the step's
  // attempts) contributed through their tangential impulses: amend_rough_step replaces those by
  // its own integration.
  void adjust_rough_error(std::vector<double>& error) const;
  template <int D>
  void adjust_rough_error_in(std::vector<double>& error) const;
  static bool switching(std::uint8_t seen) {
    return (seen & (seen - 1)) != 0 || (seen & kOnCap) != 0;  // two regimes or more, or capped
  }
  // the springs a step amends (amend_rough_step), by the regimes they went through
  bool amended(std::uint8_t seen) const {
    return switching(seen) || (dimension_ == 3 && (seen & kSlipping) != 0);
  }
  // the lever arms (m) of spring j's tangential force's torques on its two bodies at overlap
  // delta (LAMMPS's: r - delta/2 between beads, r at a wall)
  std::pair<double, double> levers(std::size_t spring, double delta) const;
  // A rough group's motion as the Dormand-Prince pair reads it: the right-hand side, and the
  // error estimate without the switching springs' tangential impulses.
  struct RoughMotion {
    MovingGroup& group;
    void operator()(const std::vector<double>& y, std::vector<double>& dydt, double) {
      group.rhs(y.data(), dydt.data());
    }
    void adjust_error(std::vector<double>& error) const { group.adjust_rough_error(error); }
  };
  void move_rough();  // the spins, tangential impulses and stretches of y_ into them
  double stepper_time() const { return rough_ ? rough_->time() : dense_->time(); }
  const std::vector<double>& stepper_state() const {
    return rough_ ? rough_->state() : dense_->state();
  }
  // a member's position (m) and velocity (m/s) along the state y
  double wall_height(const Contact& c) const;
  void member_state(std::size_t slot, const double* y, Eigen::Vector3d& x,
                    Eigen::Vector3d& v) const;
  // gap and rate of contact c, or of watched pair w at time t, along the state y
  void contact_gap(const Contact& c, const double* y, double& gap, double& rate) const;
  void watch_gap(const Watch& w, double t, const double* y, double& gap, double& rate) const;
  template <class Stepper>
  void probe_entry(const Stepper& stepper, std::size_t entry, const typename Stepper::Weights& w);
  void probe_entry_at(std::size_t entry, double t);  // the same, by whichever stepper steps
  // the entries' gaps and rates at t, in their order
  void measure(double t, const std::vector<std::size_t>& entries, Samples& samples);
  bool suspect(std::size_t k, double h, const numerics::Overlaps& overlaps) const;
  bool next_event(double a, double b, Event& event);
  void move_to(double t);
  void handle(const Event& event);
  // The elastic contacts' largest forces over [t0, t1] of the current step: the cubic through
  // their forces at the step's four nodes, which its right-hand side formed (error O(h^4);
  // docs/design/moving_geometry.md, "Peaks, events and the right-hand side"). Only the reported
  // peak forces depend on it, not the motion. Kept in springs_.peaks, by the springs' order, and
  // folded into the contacts by move_to.
  void track_peaks(double t0, double t1);
  using State = numerics::RungeKuttaNystrom::State;
  // The group's motion as the Nystrom step reads it: its right-hand side, and the amendment at
  // the contacts that switched within a step.
  struct Motion {
    MovingGroup& group;
    void operator()(const State& y, State& dydt, double) { group.rhs(y.data(), dydt.data()); }
    double amend(const State& start, const State& start_rate, State& end, const State& end_rate,
                 double h, std::span<const std::size_t> switching) {
      return group.amend_switches(start, start_rate, end, end_rate, h, switching);
    }
  };
  // 1, or the share of h a shorter step should take (amend_histories)
  double amend_switches(const State& start, const State& start_rate, State& end,
                        const State& end_rate, double h, std::span<const std::size_t> switching);
  // spring j's separation (m), its rate times h and, given the state's derivative dydt, its
  // acceleration times h^2 (m) along the state y (a wall's: from the bead to its plane)
  struct Separation {
    Eigen::Vector3d r, u, a;  // m: the separation, its rate times h, its acceleration times h^2
  };
  Separation spring_separation(std::size_t j, const double* y, const double* dydt, double h) const;
  // the history changes up to t taken into the springs and contacts
  void settle_histories(double t);
  static double stored_energy(const Contact& c);
  // 1, or the share of the step h to cut it to, just past spring j's turn (amend_histories)
  double turn_cut(std::size_t j, const numerics::ContactLaw& law,
                  const numerics::OnsetQuadrature& missed, double end_overlap, double h) const;
  // the inelastic springs' part of amend_switches
  double amend_histories(const State& start, const State& start_rate, State& end,
                         const State& end_rate, double h);
  void take_step();

  // The members' states at time_ (after move_to), by slot.
  struct MemberStates {
    std::vector<Eigen::Vector3d> position, velocity;  // m, m/s
    std::vector<Eigen::Vector3d> shift;               // position less anchor (m)
    std::vector<Eigen::Vector3d> origin;              // shifts at the last restart (m)
    std::vector<double> gain;           // T / m, a force to the state's w' (moving_contacts.hpp)
    std::vector<Eigen::Vector3d> spin;  // rad/s (world_.rough)
    std::vector<double> spin_gain;      // T / (0.4 m r), a torque to the state's spin rate
  };
  // The contacts in the right-hand side, as it reads them. It takes the springs a chunk at a
  // time in three passes: the separations gathered from the state, the elastic Hertz forces
  // formed together from `reach` and `stiffness` beside them (their square roots and division
  // are most of a packing's right-hand side, and the compiler packs two contacts' into one
  // instruction), the accelerations scattered in the springs' order (the same sums as one pass,
  // to the bit).
  struct Springs {
    std::vector<std::int32_t> active;  // of contacts_: those in the right-hand side
    std::vector<Spring> list;          // the same, as the right-hand side reads them
    std::vector<SpringAside> aside;
    std::vector<double> reach, stiffness;            // m, N / m^(3/2): by the springs' order
    std::vector<Peak> peaks;                         // by the springs' order
    std::vector<HistoryChange> history_changes;      // of the step just taken, by time
    std::vector<std::uint8_t> regimes, last_regime;  // rough springs (note_regime)
    std::vector<std::size_t> amended;                // rough springs that switched in the last step
    std::vector<std::size_t> slipping;               // and those that slipped throughout it
  };
  // The event search: every entry's gap and rate at the current segment's ends (the start kept
  // from the segment before, at sampled_at: a segment's end is the next one's start), and the
  // few whose ends or cubic Hermite say they may cross within (suspect()) sampled at the
  // compliant integrator's cuts, where sampling every entry there was a tenth of a run.
  struct EventSearch {
    std::vector<Watch> watched;
    std::vector<std::size_t> entries, suspects;  // entries: all; those searched in this segment
    std::vector<std::int32_t> taken;  // world bodies the next take event adds (next_event)
    Samples start_samples, end_samples;
    double sampled_at = 0.0;  // s, or NaN: start_samples not taken
    Samples before, after, one;
  };

  MovingWorld& world_;
  std::int32_t id_;
  int dimension_ = 2;
  double start_ = 0.0, time_ = 0.0;
  std::vector<std::int32_t> members_;
  std::size_t paired_members_ = 0;  // members whose pairs with the others are in contacts_
  MemberStates state_;
  std::vector<Contact> contacts_;  // its members' contacts: every pair within reach
  Springs springs_;
  EventSearch search_;
  std::unique_ptr<numerics::RungeKuttaNystrom> dense_;
  std::unique_ptr<numerics::DenseOutput> rough_;  // in place of dense_ where world_.rough
  RoughLayout rough_layout_;
  // the state's first RoughLayout::stretches components (positions, velocities, impulses,
  // spins and tangential impulses) at the shares 0, 1/4, 1/2, 3/4, 1 of the last step, as the
  // pair's dense output gives them (amend_rough)
  std::array<std::vector<double>, 5> rough_nodes_;
  std::vector<double> y_, probe_;
  double last_step_ = 0.0;
  bool fresh_ = true;  // restarted, no step taken since
};

}  // namespace mimpact::granular
