#pragma once
// Models by name (the scene's top-level key `model`). Every model describes itself in one ModelEntry, next to
// its code: its name, a reader for its own settings block, what it can do, and a factory. registry.cpp lists
// the entries, one line per model. The scene parser and every driver (runner, haptic session, benchmark,
// viewer) ask the registry; no code above model/ names a concrete model.
//
// Adding a model: one file implementing Model (and DeviceDrivenModel if a device can drive it) with its
// `<name>_model_entry()`, one line in registry.cpp, its docs and tests (docs/architecture.md).

#include <any>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "vascsim/core/json_reader.hpp"
#include "vascsim/model/model.hpp"
#include "vascsim/model/time_schedule.hpp"

namespace vascsim {

/// What a model can do; drivers and the scene validation decide by these, never by the name.
struct ModelCapabilities {
  bool dynamic = false;        ///< advances in simulated time (TimeSchedule); false: quasi-static load steps
  bool takes_tools = false;    ///< frictionless rigid tools (the catheter) in the problem
  bool device_driven = false;  ///< implements DeviceDrivenModel: haptic sessions and the viewer can drive it
  bool releases_regions = false;  ///< supports regions' bc.release_time_s
  /// takes discretization.basis "quadratic" and energy.stabilizer_fit "quadratic" (false: its constraints
  /// assume the linear fit)
  bool quadratic_basis = true;
  /// On a wall with node layers (tube, vessel) its default discretization.support is "wall": the equilibrium
  /// models, whose forces docs/validation.md measures against the FEM references with either support. The
  /// others keep the isotropic support they were tuned and tested with (xpbd inverts a coarse tube with the
  /// wall's).
  bool wall_support_default = false;
  /// On such a wall its default energy.stabilizer_fit is "quadratic"
  /// (docs/model/09-volume-term-and-stabiliser.md section 9.3): the same models, for the same reason; the
  /// others keep the stabiliser they were tuned with.
  bool quadratic_stabilizer_default = false;
  /// On such a wall its defaults are the configuration docs/validation.md finds within about 2 % of the FEM
  /// references at the default resolutions ("Through-wall Gauss points"): discretization.basis "quadratic",
  /// wall_reach "thickness", wall_quadrature "gauss_cell" and, with tools, contact.surface "embedded".
  /// quasi_static only: at the real-time resolutions the linear basis is nearer on the vein, and implicit's
  /// tools meet the nodes.
  bool accurate_wall_default = false;
  /// takes contact.surface "embedded": its tools meet the wall's surface through a penalty term of its
  /// equilibrium solve (embedded_contact.hpp)
  bool embedded_contact = false;
};

struct ModelEntry {
  std::string name;     ///< the scene's `model` value and the name of the model's settings block
  std::string summary;  ///< one line for help texts
  ModelCapabilities capabilities;
  /// Reads the model's settings block (the scene key `name`; an empty object when absent) with the model's
  /// defaults, ranges and messages. Returns the model's settings struct.
  std::function<std::any(JsonReader& block)> read_settings;
  /// Builds the model on a problem with settings from read_settings.
  std::function<std::unique_ptr<Model>(const Problem& problem, const std::any& settings)> make;
  /// Dynamic models: the schedule of their settings. Null for load-stepped models.
  std::function<TimeSchedule(const std::any& settings)> schedule;
  /// Why the model cannot use material law `law` with these settings (empty: it can). Null: every law.
  std::function<std::string(const std::any& settings, const std::string& law)> law_restriction;
};

/// Every model, in the order help texts list them.
const std::vector<ModelEntry>& model_registry();

/// The entry named `name`. Throws InputError naming the allowed names.
const ModelEntry& find_model(const std::string& name);

/// The registered names, in registry order.
std::vector<std::string> model_names();

/// The model a scene gets when it names none: the real-time default (`implicit`) for a scene a device drives
/// (a haptic session, the viewer), the static solver (`quasi_static`) otherwise.
std::string default_model_name(bool device_driven);

/// The registered names of the models that have a capability, e.g. &ModelCapabilities::device_driven.
std::vector<std::string> model_names_with(bool ModelCapabilities::*capability);

/// Builds model `name` (InputError for an unknown name).
std::unique_ptr<Model> make_model(const std::string& name, const Problem& problem, const std::any& settings);

/// The settings a reader returned, as the model's settings struct S (std::bad_any_cast if it is not one).
template <class S>
const S& settings_as(const std::any& settings) {
  return std::any_cast<const S&>(settings);
}

}  // namespace vascsim
