#include "moving_world.hpp"

#include <string>
#include <utility>

#include "mimpact/common/error.hpp"

namespace mimpact::granular {

MovingWorld::MovingWorld(const BeadGeometry& beads, const MovingContactsOptions& asked)
    : geometry(beads),
      options((validate(asked, "moving contacts"), asked)),
      lists(beads, asked.skin > 0.0 ? asked.skin : 0.2 * beads.radius.minCoeff()),
      bodies(std::size_t(beads.body_count())),
      contacts_of(bodies.size()) {}

std::int32_t MovingWorld::find_contact_id(std::int32_t first, std::int32_t second) const {
  if (second >= 0 && second < first) std::swap(first, second);
  for (const auto& [other, id] : contacts_of[std::size_t(first)])
    if (other == second) return id;
  return -1;
}

std::int32_t MovingWorld::contact_id(std::int32_t first, std::int32_t second) {
  if (second >= 0 && second < first) std::swap(first, second);
  const std::int32_t known = find_contact_id(first, second);
  if (known >= 0) return known;
  MovingContact c;
  c.first = first;
  c.second = second;
  c.law = second >= 0 ? geometry.bead_law(first, second)
                      : geometry.wall_law(first, std::size_t(-1 - second));
  const std::int32_t id = std::int32_t(contacts.size());
  contacts.push_back(c);
  contacts_of[std::size_t(first)].emplace_back(second, id);
  return id;
}

void MovingWorld::check_budgets(double t) const {
  if (stats.member_steps > options.max_body_steps)
    throw BudgetSpent("moving contacts: " + std::to_string(stats.member_steps) +
                          " body steps taken by t = " + to_text(t) + " s, beyond the budget of " +
                          std::to_string(options.max_body_steps),
                      t);
  if (stats.steps + stats.windows > options.max_steps)
    throw BudgetSpent("moving contacts: max_steps = " + std::to_string(options.max_steps) +
                          " time steps and windows taken by t = " + to_text(t) +
                          " s (compliant.max_steps in a scene): " + std::to_string(stats.steps) +
                          " steps, " + std::to_string(stats.windows) + " windows",
                      t);
}

}  // namespace mimpact::granular
