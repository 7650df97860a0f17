// Fuzz target: the scene loader with --set overrides. The input is a scene file; an optional NUL byte
// separates it from newline-separated overrides ("path.to.key=value"), given as the CLI's --set would.
#include <string>
#include <vector>

#include "fuzz_support.hpp"
#include "vascsim/scene/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const auto nul = input.find('\0');
  const std::string scene = input.substr(0, nul);
  std::vector<std::string> overrides;
  if (nul != std::string::npos) {
    std::size_t start = nul + 1;
    while (start <= input.size()) {
      const auto end = std::min(input.find('\n', start), input.size());
      overrides.push_back(input.substr(start, end - start));
      start = end + 1;
    }
  }
  const auto file =
      vascsim::fuzz::write_input(reinterpret_cast<const std::uint8_t*>(scene.data()), scene.size(), ".json");
  vascsim::fuzz::expect_clean([&] { vascsim::load_scene(file.string(), overrides); });
  return 0;
}
