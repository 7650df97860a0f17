#pragma once
// Order statistics of measured samples (step times, jitter, errors): one definition for every report.

#include <algorithm>
#include <cstddef>
#include <vector>

namespace vascsim {

/// The q-quantile (q in [0, 1]) by linear interpolation between order statistics (numpy's default, so a
/// reader's script gives the same number). 0 for no samples. Takes a copy: the caller's order is kept.
inline double quantile(std::vector<double> samples, double q) {
  if (samples.empty()) return 0.0;
  std::sort(samples.begin(), samples.end());
  const double position = std::clamp(q, 0.0, 1.0) * static_cast<double>(samples.size() - 1);
  const auto i = static_cast<std::size_t>(position);
  if (i + 1 >= samples.size()) return samples.back();
  return samples[i] + (position - static_cast<double>(i)) * (samples[i + 1] - samples[i]);
}

inline double median(std::vector<double> samples) {
  return quantile(std::move(samples), 0.5);
}

}  // namespace vascsim
