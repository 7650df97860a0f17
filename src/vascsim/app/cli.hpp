#pragma once
// The `vascsim` command line, callable in-process (tests) with its own output streams.
//   vascsim [-q|-v] [-j THREADS] run SCENE.json [--set key=value ...] [--out DIR]   (global options may
//   also follow the subcommand)
//   vascsim [-q|-v] [-j THREADS] validate cantilever [--out DIR] [--sizes 2,3,4,6]
//   vascsim [-q|-v] bench [SCENE.json] [--model xpbd] [--nodes 1000,3000,10000,30000] [--threads 1,2]
//     [--steps 200] [--warmup 20] [--set key=value ...] [--out FILE.csv|FILE.json ...]
// Exit codes: 0 success, 1 internal error (a bug), 2 bad input (scene, key, value, file),
// 3 numerical failure (ill-conditioned discretisation, unstable or non-finite solution).

#include <ostream>
#include <string>
#include <vector>

namespace vascsim {

int run_cli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace vascsim
