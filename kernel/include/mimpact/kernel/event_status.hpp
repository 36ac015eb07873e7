#pragma once

#include <string>
#include <utility>

namespace mimpact::kernel {

// What an observer asks of a run after each advance, as Drake's monitors answer with an
// EventStatus: go on, or end the run here, saying why (the run's summary keeps the reason).
class EventStatus {
 public:
  static EventStatus proceed() { return EventStatus(false, {}); }
  static EventStatus terminate(std::string reason) { return EventStatus(true, std::move(reason)); }

  bool terminates() const { return terminates_; }
  const std::string& reason() const { return reason_; }

 private:
  EventStatus(bool terminates, std::string reason)
      : terminates_(terminates), reason_(std::move(reason)) {}

  bool terminates_;
  std::string reason_;
};

}  // namespace mimpact::kernel
