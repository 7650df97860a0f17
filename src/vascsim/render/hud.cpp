#include "vascsim/render/hud.hpp"

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#include <imgui_stdlib.h>

#include <fmt/format.h>
#include <algorithm>
#include <cmath>

#include "vascsim/render/colour_map.hpp"
#include "vascsim/render/gl_context.hpp"

namespace vascsim::render {

namespace {

void text(const std::string& s) {
  ImGui::TextUnformatted(s.c_str());
}

// A combo box over `choices`; true when the user picked a different one.
bool choose(const char* label, const std::vector<std::string>& choices, std::string& chosen) {
  bool changed = false;
  if (ImGui::BeginCombo(label, chosen.empty() ? "(none)" : chosen.c_str())) {
    for (const std::string& c : choices) {
      const bool selected = c == chosen;
      if (ImGui::Selectable(c.c_str(), selected) && !selected) {
        chosen = c;
        changed = true;
      }
    }
    ImGui::EndCombo();
  }
  return changed;
}

void draw_legend(const ScalarField& field) {
  const ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - 12.0f, io.DisplaySize.y - 12.0f), ImGuiCond_Always,
                          ImVec2(1.0f, 1.0f));
  ImGui::SetNextWindowBgAlpha(0.75f);
  const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                 ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav |
                                 ImGuiWindowFlags_NoMove;
  if (ImGui::Begin("legend", nullptr, flags)) {
    text(field.unit.empty() ? field.label : fmt::format("{} ({})", field.label, field.unit));
    const float w = 220.0f, h = 16.0f;
    const ImVec2 p = ImGui::GetCursorScreenPos();
    ImDrawList* dl = ImGui::GetWindowDrawList();
    constexpr int kSegments = 16;
    for (int i = 0; i < kSegments; ++i) {
      const float t0 = static_cast<float>(i) / kSegments, t1 = static_cast<float>(i + 1) / kSegments;
      const Float3 a = colour_map(t0), b = colour_map(t1);
      const ImU32 ca = ImGui::ColorConvertFloat4ToU32(ImVec4(a.x(), a.y(), a.z(), 1.0f));
      const ImU32 cb = ImGui::ColorConvertFloat4ToU32(ImVec4(b.x(), b.y(), b.z(), 1.0f));
      dl->AddRectFilledMultiColor(ImVec2(p.x + t0 * w, p.y), ImVec2(p.x + t1 * w, p.y + h), ca, cb, cb, ca);
    }
    ImGui::Dummy(ImVec2(w, h));
    const std::string lo = fmt::format("{:.3g}", field.min),
                      mid = fmt::format("{:.3g}", 0.5f * (field.min + field.max)),
                      hi = fmt::format("{:.3g}", field.max);
    text(lo);
    ImGui::SameLine(0.5f * w - 0.5f * ImGui::CalcTextSize(mid.c_str()).x);
    text(mid);
    ImGui::SameLine(w - ImGui::CalcTextSize(hi.c_str()).x);
    text(hi);
  }
  ImGui::End();
}

void draw_stats(const HudStats& s) {
  text(fmt::format("{}  |  model {}", s.scene_name.empty() ? std::string("(no scene)") : s.scene_name,
                   s.model_name.empty() ? std::string("-") : s.model_name));
  text(fmt::format("{:.1f} fps  (upload {:.1f} ms, draw {:.1f} ms)", s.visual_fps, s.upload_ms, s.draw_ms));
  text(fmt::format("deformation {:.0f} steps/s   t = {:.3f} s{}", s.deformation_steps_per_s, s.sim_time_s,
                   s.paused ? "  [paused]" : ""));
  text(fmt::format("frame {:.1f} ms, map {:.2f} ms, normals {:.2f} ms", s.simulation_ms, s.map_ms,
                   s.normals_ms));
  text(s.device.empty() ? std::string("haptics: no tool in this scene")
                        : fmt::format("haptics {:.0f} Hz, p99 jitter {:.0f} us ({})", s.haptic_rate_hz,
                                      s.haptic_p99_jitter_us, s.device));
  text(fmt::format("{} nodes, {} triangles", s.nodes, s.triangles));
  text(std::isnan(s.solver_residual) ? std::string("residual: - (not reported)")
                                     : fmt::format("residual {:.3e}", s.solver_residual));
  const bool over = s.force_threshold_n > 0.0 && s.tool_force_n > s.force_threshold_n;
  ImGui::PushStyleColor(ImGuiCol_Text,
                        over ? ImVec4(1.0f, 0.35f, 0.3f, 1.0f) : ImVec4(0.6f, 1.0f, 0.6f, 1.0f));
  text(fmt::format(
      "tool force {:.4g} N{}", s.tool_force_n,
      s.force_threshold_n > 0.0 ? fmt::format(" (threshold {:.3g} N)", s.force_threshold_n) : ""));
  ImGui::PopStyleColor();
  // Wrapped: with the tool lag and the force age it is wider than the panel.
  if (const std::string hand = hand_line(s); !hand.empty()) ImGui::TextWrapped("%s", hand.c_str());
  if (!s.force_history_n.empty()) {
    const float top = std::max({*std::max_element(s.force_history_n.begin(), s.force_history_n.end()),
                                static_cast<float>(s.force_threshold_n), 1e-9f});
    ImGui::PlotLines("##force", s.force_history_n.data(), static_cast<int>(s.force_history_n.size()), 0,
                     "force (N)", 0.0f, 1.1f * top, ImVec2(ImGui::GetContentRegionAvail().x, 60.0f));
  }
  if (!s.message.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.85f, 0.4f, 1.0f));
    ImGui::TextWrapped("%s", s.message.c_str());
    ImGui::PopStyleColor();
  }
}

void draw_view(HudControls& c, HudRequests& r) {
  if (!ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) return;
  int mode = c.mode == ViewMode::lit ? 0 : 1;
  ImGui::RadioButton("lit", &mode, 0);
  ImGui::SameLine();
  ImGui::RadioButton("fluoroscopy", &mode, 1);
  c.mode = mode == 0 ? ViewMode::lit : ViewMode::fluoroscopy;
  if (c.mode == ViewMode::fluoroscopy) {
    ImGui::SliderFloat("LAO(+)/RAO(-)", &c.carm_lao_deg, -90.0f, 90.0f, "%.0f deg");
    ImGui::SliderFloat("cranial(+)/caudal(-)", &c.carm_cranial_deg, -45.0f, 45.0f, "%.0f deg");
    ImGui::Checkbox("contrast", &c.contrast_filled);
    ImGui::SliderFloat("window", &c.fluoro_window, 0.01f, 100.0f, "%.3g x", ImGuiSliderFlags_Logarithmic);
  } else {
    ImGui::Checkbox("cutaway", &c.cutaway);
    ImGui::SameLine();
    ImGui::Checkbox("nodes", &c.show_nodes);
    ImGui::SameLine();
    ImGui::Checkbox("tetrahedra", &c.show_tets);
    int field = static_cast<int>(c.colour_field);
    ImGui::Combo("colour", &field, "texture\0displacement\0stress\0");
    c.colour_field = static_cast<ColourField>(field);
  }
  ImGui::Checkbox("tools", &c.show_tools);
  ImGui::SameLine();
  ImGui::Checkbox("force arrow", &c.show_force);
  ImGui::SliderFloat("threshold (N)", &c.force_threshold_n, 1e-6f, 10.0f, "%.4g",
                     ImGuiSliderFlags_Logarithmic);
  r.reset_camera = ImGui::Button("reset camera");
  ImGui::SameLine();
  r.screenshot = ImGui::Button("screenshot");
}

void draw_simulation(HudControls& c, HudRequests& r) {
  if (!ImGui::CollapsingHeader("Simulation", ImGuiTreeNodeFlags_DefaultOpen)) return;
  r.toggle_pause = ImGui::Button(c.paused ? "run" : "pause");
  ImGui::SameLine();
  r.step = ImGui::Button("step");
  ImGui::SameLine();
  r.reset_simulation = ImGui::Button("reset");
  r.load_scene = choose("scene", c.scene_choices, c.scene);
  r.change_model = choose("model", c.model_choices, c.model);
}

// One input per setting of the model's block, in the reader's range.
void edit_setting(JsonField& f) {
  bool changed = false;
  switch (f.kind) {
    case JsonField::Kind::number:
      changed = ImGui::InputDouble(f.key.c_str(), &f.value, 0.0, 0.0, "%.6g");
      break;
    case JsonField::Kind::integer: {
      int v = static_cast<int>(f.value);
      changed = ImGui::InputInt(f.key.c_str(), &v);
      f.value = v;
      break;
    }
    case JsonField::Kind::boolean: {
      bool v = f.value != 0.0;
      changed = ImGui::Checkbox(f.key.c_str(), &v);
      f.value = v ? 1.0 : 0.0;
      break;
    }
    case JsonField::Kind::string:
      changed = f.allowed.empty() ? ImGui::InputText(f.key.c_str(), &f.text)
                                  : choose(f.key.c_str(), f.allowed, f.text);
      break;
  }
  if (changed && f.kind != JsonField::Kind::string) f.value = std::clamp(f.value, f.lo, f.hi);
}

void draw_material(HudControls& c, HudRequests& r) {
  if (!ImGui::CollapsingHeader("Material and solver")) return;
  double e_kpa = c.youngs_modulus_pa * 1e-3;
  const double e_min = 1.0, e_max = 1e5, nu_min = 0.0, nu_max = 0.499;
  ImGui::SliderScalar("E (kPa)", ImGuiDataType_Double, &e_kpa, &e_min, &e_max, "%.1f",
                      ImGuiSliderFlags_Logarithmic);
  ImGui::SliderScalar("nu", ImGuiDataType_Double, &c.poisson_ratio, &nu_min, &nu_max, "%.3f");
  c.youngs_modulus_pa = e_kpa * 1e3;
  for (JsonField& f : c.model_settings) edit_setting(f);
  ImGui::InputText("more --set", &c.overrides);
  r.apply_settings = ImGui::Button("apply (rebuilds the simulation)");
}

void draw_session(HudControls& c, HudRequests& r) {
  if (!ImGui::CollapsingHeader("Session")) return;
  ImGui::InputText("recording file", &c.record_path);
  r.toggle_recording = ImGui::Button(c.recording ? "stop recording" : "record (from rest)");
  ImGui::InputText("replay file", &c.replay_path);
  r.start_replay = ImGui::Button("replay") && !c.replay_path.empty();
  if (c.has_trajectory) {
    ImGui::SameLine();
    r.play_trajectory = ImGui::Button("play the scene's trajectory");
  }
}

}  // namespace

std::string hand_line(const HudStats& s) {
  if (s.device.empty() || std::isnan(s.device_force_n)) return {};
  std::string line = fmt::format("hand: {:.4g} N sent (tool {:.4g} N)", s.device_force_n, s.tool_force_n);
  if (!std::isnan(s.tool_lag_m)) line += fmt::format(", tool {:.2f} mm behind", 1e3 * s.tool_lag_m);
  if (!std::isnan(s.force_age_ms) && s.force_age_ms > 0.0)
    line += fmt::format(", force {:.0f} ms old", s.force_age_ms);
  return line;
}

bool HudRequests::any() const {
  return toggle_pause || step || reset_simulation || reset_camera || screenshot || load_scene ||
         change_model || apply_settings || toggle_recording || start_replay || play_trajectory;
}

Hud::Hud(GlContext& context) {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // no imgui.ini next to the user's files
  ImGui::StyleColorsDark();
  ImGuiStyle& style = ImGui::GetStyle();
  style.WindowRounding = 4.0f;
  style.Alpha = 0.95f;
  if (context.window() != nullptr) {
    glfw_ = ImGui_ImplGlfw_InitForOpenGL(context.window(), true);
  }
  ImGui_ImplOpenGL3_Init("#version 330 core");
}

Hud::~Hud() {
  ImGui_ImplOpenGL3_Shutdown();
  if (glfw_) ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

void Hud::begin_frame(int width, int height, double dt_s) {
  ImGui_ImplOpenGL3_NewFrame();
  if (glfw_) {
    ImGui_ImplGlfw_NewFrame();
  } else {
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(static_cast<float>(width), static_cast<float>(height));
    io.DeltaTime = static_cast<float>(std::max(dt_s, 1e-4));
  }
  ImGui::NewFrame();
}

HudRequests Hud::draw(const HudStats& s, HudControls& c, const ScalarField* legend) {
  HudRequests r;
  ImGui::SetNextWindowPos(ImVec2(10.0f, 10.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(420.0f, 0.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.8f);
  if (ImGui::Begin("vascsim")) {
    draw_stats(s);
    draw_view(c, r);
    draw_simulation(c, r);
    draw_material(c, r);
    draw_session(c, r);
    if (!s.gl_renderer.empty()) ImGui::TextDisabled("%s", s.gl_renderer.c_str());
  }
  ImGui::End();
  if (legend != nullptr && c.mode == ViewMode::lit && c.colour_field != ColourField::none)
    draw_legend(*legend);
  return r;
}

void Hud::render() {
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

bool Hud::wants_mouse() const {
  return ImGui::GetIO().WantCaptureMouse;
}
bool Hud::wants_keyboard() const {
  return ImGui::GetIO().WantCaptureKeyboard;
}

void apply_controls(const HudControls& c, RenderSettings& s) {
  s.mode = c.mode;
  s.carm_lao_deg = c.carm_lao_deg;
  s.carm_cranial_deg = c.carm_cranial_deg;
  s.fluoro.contrast_filled = c.contrast_filled;
  const FluoroSettings physical;
  s.fluoro.mu_tissue_per_m = physical.mu_tissue_per_m * c.fluoro_window;
  s.fluoro.mu_contrast_per_m = physical.mu_contrast_per_m * c.fluoro_window;
  s.fluoro.mu_tool_per_m = physical.mu_tool_per_m * c.fluoro_window;
  s.show_tools = c.show_tools;
  s.show_force = c.show_force;
  s.show_nodes = c.show_nodes;
  s.show_tets = c.show_tets;
  s.cutaway = c.cutaway;
  s.show_colour_map = c.colour_field != ColourField::none;
}

}  // namespace vascsim::render
