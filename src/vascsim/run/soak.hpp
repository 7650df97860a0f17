#pragma once
// The soak test (`vascsim soak`, `make soak`, docs/reliability.md): a realtime haptic session of a scene with
// a wandering device (interaction/wandering_device.hpp: random but bounded tool motion, seeded) for a long
// time, keeping no ticks so that memory should stay flat, while a sampler thread reads the process's resident
// memory. Reports the ticks, the NaN and clamp events, the largest forces, the loop's jitter percentiles and
// the memory growth after warm-up, into soak.json and soak.md (next to the session's summary.json).

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>

#include "vascsim/interaction/wandering_device.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {

struct SoakOptions {
  std::filesystem::path out_dir;
  double seconds = 3600.0;      ///< session length, s (wall clock: the session runs in real time)
  WanderingBounds bounds;       ///< the tool's motion around the first pose of the scene's trajectory
  double rss_interval_s = 1.0;  ///< resident memory sampled this often, s
  /// Memory growth is measured from this long after the session's first frame on (the set-up, allocations of
  /// the first frames, caches and the OS settling in are not growth); < 0: max(10 s, 10 % of the session).
  double warmup_s = -1.0;
  std::function<void(double, double)> on_progress;  ///< (session time done, session length), s
};

/// Runs the soak and returns soak.json's content (also written, with soak.md). Throws InputError for a scene
/// without a haptics block.
nlohmann::json run_soak(const Scene& scene, const SoakOptions& options);

/// This process's resident memory, MiB (Linux: /proc/self/statm; 0 where it cannot be read).
double resident_memory_mib();

}  // namespace vascsim
