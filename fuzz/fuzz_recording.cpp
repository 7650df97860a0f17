// Fuzz target: the session-recording reader (`vascsim run --replay FILE`).
#include "fuzz_support.hpp"
#include "vascsim/interaction/session_recording.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = vascsim::fuzz::write_input(data, size, ".csv");
  vascsim::fuzz::expect_clean([&] { vascsim::read_session_recording(file); });
  return 0;
}
