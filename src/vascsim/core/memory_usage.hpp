#pragma once
// How much memory this process holds, as the kernel counts it (Linux /proc and getrusage): what a dry run
// (`vascsim check`) reports after building a scene, and what the cost calibration compares against.

#include <cstddef>

namespace vascsim {

/// The resident set now (VmRSS of /proc/self/status), bytes; 0 where the kernel does not say.
std::size_t resident_bytes();

/// The largest resident set this process has had so far (getrusage ru_maxrss), bytes.
std::size_t peak_resident_bytes();

}  // namespace vascsim
