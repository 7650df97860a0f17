// A flexible instrument's frame in the vessel's lumen (issue 43's speed; docs/model/26-rod.md section 26.7):
// the example scene scenes/navigation/aorta-bent-guidewire.json (a 0.035" J wire, 160 edges of 1 mm, fed from
// 10 to 80 mm into the bent aorta's rigid lumen at 20 mm/s in 10 ms frames, then turned 180 degrees in 0.5 s,
// Coulomb friction mu 0.05), run whole by run_navigation. Counters: the frames' solve time (median and 90th
// percentile, ms) and the frames that did not converge. The wall is rigid here: the deformable wall's
// coupling is not built.
//
// Run: build/bench/vascsim_bench --benchmark_filter=Navigation --benchmark_repetitions=3
//        --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <string>
#include <vector>

#include "vascsim/run/navigation.hpp"
#include "vascsim/scene/scene.hpp"

namespace {

using namespace vascsim;

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5))];
}

void BM_NavigationFrame(benchmark::State& state) {
  spdlog::set_level(spdlog::level::warn);
  const Scene scene =
      load_scene(std::string(VASCSIM_SOURCE_DIR) + "/scenes/navigation/aorta-bent-guidewire.json", {});
  NavigationResult r;
  for (auto _ : state) r = run_navigation(scene, {});
  std::vector<double> ms;
  for (std::size_t k = 1; k < r.frames.size(); ++k) ms.push_back(r.frames[k].wall_ms);
  state.counters["frames"] = static_cast<double>(ms.size());
  state.counters["frame_ms_median"] = quantile(ms, 0.5);
  state.counters["frame_ms_p90"] = quantile(ms, 0.9);
  state.counters["unconverged"] = r.unconverged;
}
BENCHMARK(BM_NavigationFrame)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace
