// vascsim.Scene and the two ways to get one: from a file (load_scene, as `vascsim run FILE --set ...`) or
// from a document (parse_scene: the package's parse_scene turns a dict into JSON text). Both validate exactly
// as the command line does and raise InputError with its message.

#include <fmt/format.h>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "conversions.hpp"
#include "log_bridge.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim::python {

namespace {

Scene parse_text(const std::string& text, const std::string& file,
                 const std::vector<std::string>& overrides) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text, nullptr, true, /*ignore_comments=*/true);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: not valid JSON: {}", file, e.what()));
  }
  for (const auto& o : overrides) apply_override(doc, o);
  return parse_scene(doc, file);
}

std::vector<std::string> tool_names(const Scene& s) {
  std::vector<std::string> names;
  for (const auto& o : s.obstacles) names.push_back(o.name);
  return names;
}

std::vector<std::string> region_names(const Scene& s) {
  std::vector<std::string> names;
  for (const auto& r : s.regions) names.push_back(r.name);
  return names;
}

}  // namespace

void bind_scene(py::module_& m) {
  py::class_<Scene>(
      m, "Scene",
      "A validated scene (docs/scene-format.md). Get one with vascsim.load_scene or vascsim.parse_scene.")
      .def_readonly("file", &Scene::file, "The file it was read from (or the name given to parse_scene).")
      .def_readonly("name", &Scene::name)
      .def_readonly("description", &Scene::description)
      .def_readonly("model", &Scene::model, "The model it runs (the registry name).")
      .def_property_readonly("tools", &tool_names, "Names of the rigid tools (obstacles), in scene order.")
      .def_property_readonly("regions", &region_names, "Names of the regions, in scene order.")
      .def_property_readonly(
          "probes",
          [](const Scene& s) {
            std::vector<std::string> names;
            for (const auto& p : s.probes) names.push_back(p.name);
            return names;
          },
          "Names of the point probes, in scene order.")
      .def_property_readonly(
          "has_haptics", [](const Scene& s) { return s.haptics.enabled; },
          "True when the scene has a haptics block (a device drives its tool).")
      .def_property_readonly(
          "document", [](const Scene& s) { return to_python(s.resolved); },
          "The scene's JSON after the overrides, as a dict.")
      .def("__repr__", [](const Scene& s) {
        return fmt::format("<vascsim.Scene '{}' ({}), model {}, {} regions, {} tools>", s.name, s.file,
                           s.model, s.regions.size(), s.obstacles.size());
      });
  // Called by the package's wrappers: what the parser logs names their caller's line (stacklevel 2).
  m.def(
      "_load_scene",
      [](const std::string& path, const std::vector<std::string>& overrides) {
        Scene s = load_scene(path, overrides);
        emit_log(2);
        return s;
      },
      py::arg("path"), py::arg("overrides") = std::vector<std::string>{});
  m.def(
      "_parse_scene",
      [](const std::string& text, const std::string& file, const std::vector<std::string>& overrides) {
        Scene s = parse_text(text, file, overrides);
        emit_log(2);
        return s;
      },
      py::arg("text"), py::arg("file"), py::arg("overrides") = std::vector<std::string>{});
}

}  // namespace vascsim::python
