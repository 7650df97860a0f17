#pragma once
// The one-line status of an output point that progress bars show.

#include <fmt/format.h>
#include <string>

#include "vascsim/model/registry.hpp"
#include "vascsim/run/simulation.hpp"

namespace vascsim {

/// "load 0.500: 5 Newton / 850 CG it., residual 1.2e-07" for load-stepped models, "t = 0.01 s, 80 substeps"
/// for dynamic ones.
inline std::string step_status(const std::string& model, const StepRecord& r) {
  if (r.step == 0) return "rest state";
  if (!find_model(model).capabilities.dynamic)
    return fmt::format("load {:.3f}: {} Newton / {} CG it., residual {:.1e}{}", r.report.load_factor,
                       r.report.iterations, r.report.inner_iterations, r.report.residual,
                       r.report.converged ? "" : " NOT CONVERGED");
  return fmt::format("t = {:.4g} s, {} substeps", r.report.time_s, r.report.iterations);
}

}  // namespace vascsim
