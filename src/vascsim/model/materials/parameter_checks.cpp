#include "vascsim/model/materials/parameter_checks.hpp"

#include <fmt/format.h>

#include <cmath>

#include "vascsim/core/error.hpp"

namespace vascsim::materials {

namespace {
[[noreturn]] void fail(std::string_view law, std::string_view key, double value, std::string_view allowed) {
  throw InputError(fmt::format("hyperelastic law '{}': {} = {} must be {}", law, key, value, allowed));
}
}  // namespace

void require_positive(std::string_view law, std::string_view key, double value) {
  if (!(value > 0.0) || !std::isfinite(value)) fail(law, key, value, "finite and > 0");
}

void require_non_negative(std::string_view law, std::string_view key, double value) {
  if (!(value >= 0.0) || !std::isfinite(value)) fail(law, key, value, "finite and >= 0");
}

void require_open_range(std::string_view law, std::string_view key, double value, double lo, double hi) {
  if (!(value > lo && value < hi)) fail(law, key, value, fmt::format("in ({}, {})", lo, hi));
}

void require_closed_range(std::string_view law, std::string_view key, double value, double lo, double hi) {
  if (!(value >= lo && value <= hi)) fail(law, key, value, fmt::format("in [{}, {}]", lo, hi));
}

LameConstants checked_lame_constants(std::string_view law, double youngs_modulus_pa, double poisson_ratio) {
  require_positive(law, "youngs_modulus_pa", youngs_modulus_pa);
  require_open_range(law, "poisson_ratio", poisson_ratio, -1.0, 0.5);
  const double E = youngs_modulus_pa, nu = poisson_ratio;
  return {E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))};
}

}  // namespace vascsim::materials
