#pragma once

namespace mimpact::plugins {

// Adds the plugins to the kernel's registries: integrator "event-driven", impact problem
// "lzb", contact force problem "acceleration-lcp". Safe to call more than once.
void register_plugins();

}  // namespace mimpact::plugins
