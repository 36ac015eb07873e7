#pragma once

#include <string_view>

namespace mimpact::kernel {

// What happens at a contact when it closes: the impact law. The kernel knows no concrete
// law; a plugin defines them, and an impact problem says which ones it can handle.
class NonSmoothLaw {
 public:
  virtual ~NonSmoothLaw() = default;
  // A short name for messages, e.g. "lzb".
  virtual std::string_view kind() const = 0;
};

}  // namespace mimpact::kernel
