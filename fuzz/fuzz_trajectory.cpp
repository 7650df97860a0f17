// Fuzz target: the trajectory reader (CSV and JSON). The first byte picks the format, the rest is the file.
#include "fuzz_support.hpp"
#include "vascsim/interaction/trajectory.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const auto file = vascsim::fuzz::write_input(data + 1, size - 1, data[0] % 2 ? ".json" : ".csv");
  vascsim::fuzz::expect_clean([&] { vascsim::read_trajectory(file); });
  return 0;
}
