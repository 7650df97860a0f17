// The model registry (model/registry.hpp): every model is one self-describing entry, and what an entry
// says of its model is what the model does. These are the checks a new model's entry must pass too.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>

#include "vascsim/core/error.hpp"
#include "vascsim/model/device_driven_model.hpp"
#include "vascsim/model/registry.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {
namespace {

using nlohmann::json;

// A tiny fixed-base block that every model can build (no tools: not every model takes them).
json tiny_block(const std::string& model) {
  json doc = json::parse(R"({
    "name": "registry-block",
    "geometry": { "type": "box", "min_m": [0, 0, 0], "max_m": [0.002, 0.002, 0.002], "node_spacing_m": 0.0005 },
    "material": { "youngs_modulus_pa": 1e5, "poisson_ratio": 0.3, "density_kg_m3": 1060 },
    "regions": [ { "name": "base", "select": { "type": "box", "max_m": [1, 1, 0] }, "bc": { "type": "fixed" } } ],
    "quasi_static": { "load_steps": 1 },
    "explicit": { "duration_s": 1e-4, "output_interval_s": 1e-4 },
    "xpbd": { "duration_s": 1e-3 },
    "paper_literal": { "duration_s": 1e-4, "output_interval_s": 1e-4 }
  })");
  doc["model"] = model;
  return doc;
}

TEST(ModelRegistry, EveryEntryIsCompleteAndUnique) {
  std::set<std::string> names;
  for (const ModelEntry& e : model_registry()) {
    EXPECT_FALSE(e.name.empty());
    EXPECT_TRUE(names.insert(e.name).second) << "duplicate model name " << e.name;
    EXPECT_FALSE(e.summary.empty()) << e.name;
    EXPECT_TRUE(e.read_settings) << e.name;
    EXPECT_TRUE(e.make) << e.name;
    // A dynamic model reports its time schedule; a load-stepped one has none.
    EXPECT_EQ(static_cast<bool>(e.schedule), e.capabilities.dynamic) << e.name;
  }
  EXPECT_GE(names.size(), 4u);
}

// What the entry says is what the built model does: its name, whether a device can drive it, and (for
// dynamic models) the schedule it reads from its block.
TEST(ModelRegistry, CapabilitiesMatchTheBuiltModel) {
  for (const ModelEntry& e : model_registry()) {
    Simulation sim(parse_scene(tiny_block(e.name), "registry.json"));
    EXPECT_EQ(sim.model().name(), e.name);
    EXPECT_EQ(sim.model().device_driven() != nullptr, e.capabilities.device_driven) << e.name;
    if (e.schedule) {
      const TimeSchedule s = e.schedule(sim.scene().own_model_settings());
      EXPECT_GT(s.duration_s, 0.0) << e.name;
      EXPECT_GT(s.output_interval_s, 0.0) << e.name;
    }
  }
}

TEST(ModelRegistry, UnknownNamesListTheModels) {
  try {
    find_model("no_such_model");
    ADD_FAILURE() << "unknown model accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    for (const std::string& n : model_names()) EXPECT_NE(what.find(n), std::string::npos) << what;
  }
}

// Each reader owns its block: an unknown key in it is an error naming the key.
TEST(ModelRegistry, ReadersRejectUnknownKeys) {
  for (const ModelEntry& e : model_registry()) {
    const json block = {{"no_such_key", 1}};
    JsonReader reader(block, e.name, "blocks.json");
    try {
      e.read_settings(reader);
      ADD_FAILURE() << e.name << " accepted an unknown key";
    } catch (const InputError& err) {
      EXPECT_NE(std::string(err.what()).find("no_such_key"), std::string::npos) << err.what();
    }
  }
}

// A scene asks the registry what its model can do: tools and released regions name the key and the models
// that can, for every model that cannot.
TEST(ModelRegistry, SceneChecksCapabilities) {
  for (const ModelEntry& e : model_registry()) {
    json tools = tiny_block(e.name);
    tools["obstacles"] =
        json::array({{{"name", "ball"}, {"radius_m", 0.001}, {"centre_m", {0.001, 0.001, 0.004}}}});
    if (e.capabilities.takes_tools) {
      EXPECT_NO_THROW(parse_scene(tools, "t.json")) << e.name;
    } else {
      try {
        parse_scene(tools, "t.json");
        ADD_FAILURE() << e.name << " took a tool";
      } catch (const InputError& err) {
        EXPECT_NE(std::string(err.what()).find("obstacles"), std::string::npos) << err.what();
      }
    }
    json release = tiny_block(e.name);
    release["regions"][0]["bc"]["release_time_s"] = 1e-4;
    if (e.capabilities.releases_regions)
      EXPECT_NO_THROW(parse_scene(release, "r.json")) << e.name;
    else
      EXPECT_THROW(parse_scene(release, "r.json"), InputError) << e.name;
  }
}

}  // namespace
}  // namespace vascsim
