#pragma once
// The AHP evaluation's measurable indicators (docs/ahp.md, `vascsim ahp --measurements`) from the comparison
// experiments: per model, I3 update_time_ms (the timing's simulation median, ms per 1 ms step) and I2
// visual_refresh_rate_hz (its frames per second), both at the largest node count the model was timed at, and,
// when the force-displacement comparison's rms_error.json is given, I7 force_rms_error_percent
// (100 RMS(F - F_ref) / RMS(F_ref)). Model ids are the model names; the reference model of the comparison is
// left out of I7 (its error is 0 by construction).

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "vascsim/experiments/timing_sweep.hpp"

namespace vascsim {

/// The measurements document (data/ahp/measurements.schema.json). `rms_error` may be null.
nlohmann::json ahp_measurements(const std::vector<TimingPoint>& points, const nlohmann::json& rms_error,
                                const std::string& source);

}  // namespace vascsim
