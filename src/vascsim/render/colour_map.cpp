#include "vascsim/render/colour_map.hpp"

#include <algorithm>
#include <array>

#include <fmt/format.h>

namespace vascsim::render {

namespace {
constexpr std::array<std::array<float, 3>, 5> kStops = {{
    {0.16f, 0.20f, 0.58f},
    {0.13f, 0.56f, 0.78f},
    {0.36f, 0.78f, 0.47f},
    {0.96f, 0.84f, 0.28f},
    {0.84f, 0.17f, 0.13f},
}};
}

Float3 colour_map(float t) {
  const float x = std::clamp(t, 0.0f, 1.0f) * static_cast<float>(kStops.size() - 1);
  const int i = std::min(static_cast<int>(x), static_cast<int>(kStops.size()) - 2);
  const float f = x - static_cast<float>(i);
  const Float3 a(kStops[i][0], kStops[i][1], kStops[i][2]);
  const Float3 b(kStops[i + 1][0], kStops[i + 1][1], kStops[i + 1][2]);
  return (1.0f - f) * a + f * b;
}

std::string colour_map_glsl() {
  std::string stops;
  for (std::size_t i = 0; i < kStops.size(); ++i)
    stops += fmt::format("{}vec3({:.4f}, {:.4f}, {:.4f})", i == 0 ? "" : ", ", kStops[i][0], kStops[i][1],
                         kStops[i][2]);
  return fmt::format(R"(
const vec3 kColourStops[{0}] = vec3[{0}]({1});
vec3 colour_map(float t) {{
  float x = clamp(t, 0.0, 1.0) * float({2});
  int i = min(int(x), {3});
  return mix(kColourStops[i], kColourStops[i + 1], x - float(i));
}}
)",
                     kStops.size(), stops, kStops.size() - 1, kStops.size() - 2);
}

}  // namespace vascsim::render
