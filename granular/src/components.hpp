#pragma once

#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

namespace mimpact::granular {

// Union-find over small integers, for the groups' components.
class Components {
 public:
  explicit Components(std::size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), std::int32_t(0));
  }
  std::int32_t find(std::int32_t i) {
    while (parent_[std::size_t(i)] != i)
      i = parent_[std::size_t(i)] = parent_[std::size_t(parent_[std::size_t(i)])];
    return i;
  }
  void join(std::int32_t a, std::int32_t b) { parent_[std::size_t(find(a))] = find(b); }

 private:
  std::vector<std::int32_t> parent_;
};

}  // namespace mimpact::granular
