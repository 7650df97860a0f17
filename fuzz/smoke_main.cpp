// A fuzz target without libFuzzer, for the test suite (`make test`, ctest label "fuzz"): runs every file of
// the folders given, then `-mutations=N` deterministic variants of each (a byte changed, the input cut short,
// a byte inserted, a slice repeated), so that the harness and the readers run under the suite's sanitizers in
// seconds. A crash ends the process as it would under libFuzzer; `make fuzz` does the real search.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

std::uint64_t next_random(std::uint64_t& state) {  // SplitMix64
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

std::string mutate(std::string s, std::uint64_t& state) {
  const auto pick = [&](std::size_t n) {
    return n == 0 ? 0 : static_cast<std::size_t>(next_random(state) % n);
  };
  switch (next_random(state) % 4) {
    case 0:
      if (!s.empty()) s[pick(s.size())] = static_cast<char>(next_random(state));
      break;
    case 1:
      s.resize(pick(s.size() + 1));
      break;
    case 2:
      s.insert(s.begin() + static_cast<std::ptrdiff_t>(pick(s.size() + 1)),
               static_cast<char>(next_random(state)));
      break;
    default: {
      const std::size_t at = pick(s.size() + 1), length = pick(s.size() - at + 1);
      s.insert(at, s.substr(at, length));
    }
  }
  return s;
}

// With VASCSIM_FUZZ_SMOKE_LAST=<file> every input is written there first: after a crash it holds the culprit.
void run(const std::string& input) {
  static const char* const last = std::getenv("VASCSIM_FUZZ_SMOKE_LAST");
  if (last != nullptr) std::ofstream(last, std::ios::binary | std::ios::trunc) << input;
  LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(input.data()), input.size());
}

}  // namespace

int main(int argc, char** argv) {
  long mutations = 0;
  std::vector<std::filesystem::path> files;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg.rfind("-mutations=", 0) == 0) {
      mutations = std::strtol(arg.c_str() + 11, nullptr, 10);
    } else if (std::filesystem::is_directory(arg)) {
      for (const auto& e : std::filesystem::directory_iterator(arg))
        if (e.is_regular_file()) files.push_back(e.path());
    } else {
      files.emplace_back(arg);
    }
  }
  std::uint64_t state = 1, runs = 0;
  for (const auto& file : files) {
    std::ifstream in(file, std::ios::binary);
    const std::string seed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    run(seed);
    ++runs;
    std::string variant = seed;
    for (long m = 0; m < mutations; ++m, ++runs) {
      variant = m % 8 == 0 ? mutate(seed, state) : mutate(variant, state);  // chains of changes, restarted
      if (variant.size() > (1u << 20)) variant = seed;
      run(variant);
    }
  }
  std::printf("fuzz smoke: %llu inputs from %zu seeds, no crash\n", static_cast<unsigned long long>(runs),
              files.size());
  return files.empty() ? 1 : 0;
}
