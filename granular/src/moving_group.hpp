#pragma once

// One group of the moving-geometry integration (moving_contacts.hpp): the bodies linked by
// loaded contacts, integrated over a window on their own. Shared by moving_contacts.cpp (the
// windows: groups formed, met, merged, committed) and moving_group.cpp (one group's
// integration: its right-hand side, its events, its restarts).

#include <Eigen/Dense>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include "mimpact/granular/moving_contacts.hpp"
#include "mimpact/numerics/internal/dense_output.hpp"
#include "mimpact/plugins/internal/contact_events.hpp"

namespace mimpact::granular {

// The key of a contact: two bodies, the lower first, or a body and -1 - wall.
inline std::uint64_t contact_key(std::int32_t first, std::int32_t second) {
  return (std::uint64_t(std::uint32_t(first)) << 32) | std::uint64_t(std::uint32_t(second));
}

// A body between windows: where it is and how it moves.
struct MovingContacts::Body {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();  // m, at `time`
  Eigen::Vector3d v = Eigen::Vector3d::Zero();  // m/s
  double time = 0.0;                            // s; flying freely, it is at x + v (t - time)
  double inverse_mass = 0.0;
  std::int32_t owner = -1;     // the group integrating it in this window, or -1: flying freely
  std::int32_t slot = -1;      // its place among its group's members
  double step_hint = 0.0;      // s: the last step its group took, where the next group starts
  bool listed_moving = false;  // in MovingContacts::moving_

  Eigen::Vector3d position_at(double t) const { return x + v * (t - time); }
};

class MovingContacts::Group {
 public:
  Group(MovingContacts& world, std::int32_t id) : world_(world), id_(id) {}

  // Starts at `start` with `members` (which it owns from now) and the contacts `loaded`
  // (ids of world contacts that carry force).
  void begin(double start, const std::vector<std::int32_t>& members,
             const std::vector<std::int32_t>& loaded);
  // Starts at `start` with two bodies flying freely that meet there (second < 0: a wall).
  void begin_collision(double start, std::int32_t first, std::int32_t second);
  // Integrates to `end`, restarting at its own events.
  void integrate(double end);
  // Writes its members' states at the end and its contacts into the world.
  void commit();
  // Gives back the bodies it owns (the window is integrated again without it).
  void release();

  std::int32_t id() const { return id_; }
  double start() const { return start_; }
  // the bodies it owns: those it started with, then those it took as they touched it
  const std::vector<std::int32_t>& members() const { return members_; }
  std::size_t loaded_contacts() const { return loaded_.size(); }
  // position (m) of member slot `m` at the end of its integration
  Eigen::Vector3d final_position(std::int32_t slot) const;

 private:
  // A contact as the group sees it: its members' slots (second < 0: -1 - wall), its law and
  // history, and its record's id in the world (-1: first met in this window).
  struct Contact {
    std::int32_t world_id = -1;
    std::int32_t first_body = 0, second_body = 0;  // world bodies (second < 0: -1 - wall)
    std::int32_t first = 0, second = 0;            // member slots (second < 0: -1 - wall)
    numerics::ContactLaw law;
    double reach = 0.0;  // m: the sum of the radii, or the bead's radius against a wall
    bool loaded = false;
    double max_compression = 0.0;
    double compression = 0.0, force = 0.0;  // m, N: at the last move
    double impulse = 0.0;                   // N s, until the last restart
    double max_force = 0.0, time_of_max_force = 0.0, dissipated = 0.0;
    std::int32_t slot = -1;  // of its impulse in the state
  };
  // A pair that may close: a member and another member, a body flying freely, or a wall.
  struct Watch {
    std::int32_t member = 0;
    std::int32_t other = 0;  // world body, or -1 - wall
  };
  // Gaps (m) and rates (m/s) of the watched pairs and loaded contacts at one time.
  struct Samples {
    std::vector<double> gap, rate;
  };
  struct Event {
    std::size_t entry = 0;  // watched pairs, then loaded contacts
    plugins::internal::ContactEvent kind = plugins::internal::ContactEvent::none;
    double time = 0.0;
  };

  void add_member(std::int32_t body);
  // the contact of the two (a body and -1 - wall), as the world last committed it or new
  std::int32_t find_contact(std::int32_t first_body, std::int32_t second_body);
  void restart(double t);
  void rhs(const double* y, double* dydt);
  // gap and rate of a loaded contact, or of a watched pair, at time t along the state y
  void contact_gap(const Contact& c, const double* y, double& gap, double& rate) const;
  void watch_gap(const Watch& w, double t, const double* y, double& gap, double& rate) const;
  void measure(double t, Samples& samples);
  bool next_event(double a, double b, Event& event);
  void move_to(double t);
  void handle(const Event& event);
  void take_step();

  MovingContacts& world_;
  std::int32_t id_;
  int dimension_ = 2;
  double start_ = 0.0, time_ = 0.0;
  std::vector<std::int32_t> members_;
  std::vector<Eigen::Vector3d> position_, velocity_;  // members', at time_ (after move_to)
  std::vector<Eigen::Vector3d> origin_;               // members' positions at the last restart
  // per member: the bodies (and -1 - wall) it has loaded contacts with
  std::vector<std::vector<std::int32_t>> partners_;
  std::unordered_map<std::uint64_t, std::int32_t> local_ids_;  // contact_key -> contacts_
  std::vector<Contact> contacts_;     // every contact it touched in this window
  std::vector<std::int32_t> loaded_;  // of contacts_: those carrying force
  std::vector<Watch> watched_;
  std::unique_ptr<numerics::internal::DenseOutput> dense_;
  std::vector<double> y_, probe_;
  Samples before_, after_, one_;
  double last_step_ = 0.0;
  bool fresh_ = true;  // restarted, no step taken since
  std::size_t last_event_ = std::size_t(-1);
};

}  // namespace mimpact::granular
