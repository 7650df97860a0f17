#include "vascsim/viewer/window_input.hpp"

#include <algorithm>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

namespace vascsim::viewer {

namespace {

constexpr double kCarmDegPerPixel = 0.3;
constexpr float kCarmKeyStepDeg = 5.0f;

WindowInput* input_of(GLFWwindow* w) {
  return static_cast<WindowInput*>(glfwGetWindowUserPointer(w));
}

void toggle_mode(render::HudControls& c) {
  c.mode = c.mode == render::ViewMode::lit ? render::ViewMode::fluoroscopy : render::ViewMode::lit;
}

}  // namespace

WindowInput::WindowInput(GLFWwindow* window, render::CameraController& camera, render::OrbitCamera& orbit,
                         MouseKeyboardDevice& tool, render::HudControls& controls)
    : window_(window), camera_(camera), orbit_(orbit), tool_(tool), controls_(controls) {
  glfwSetWindowUserPointer(window, this);
  glfwSetMouseButtonCallback(window,
                             [](GLFWwindow* w, int b, int a, int m) { input_of(w)->on_button(b, a, m); });
  glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) { input_of(w)->on_cursor(x, y); });
  glfwSetScrollCallback(window, [](GLFWwindow* w, double, double dy) {
    const bool ctrl = glfwGetKey(w, GLFW_KEY_LEFT_CONTROL) == GLFW_PRESS ||
                      glfwGetKey(w, GLFW_KEY_RIGHT_CONTROL) == GLFW_PRESS;
    input_of(w)->on_scroll(dy, ctrl);
  });
  glfwSetKeyCallback(window, [](GLFWwindow* w, int k, int, int a, int m) { input_of(w)->on_key(k, a, m); });
}

KeyRequests WindowInput::take() {
  const KeyRequests r = requests_;
  requests_ = {};
  return r;
}

void WindowInput::on_button(int button, int action, int mods) {
  const bool pressed = action == GLFW_PRESS;
  if (!pressed && drag_ != Drag::none) {
    drag_ = Drag::none;
    return;
  }
  if (pressed && hud_has_mouse()) return;
  const bool ctrl = (mods & GLFW_MOD_CONTROL) != 0, shift = (mods & GLFW_MOD_SHIFT) != 0;
  if (pressed && ctrl && button == GLFW_MOUSE_BUTTON_LEFT) {
    drag_ = Drag::push;
  } else if (pressed && ctrl && button == GLFW_MOUSE_BUTTON_RIGHT) {
    drag_ = Drag::steer;
  } else if (pressed && !shift && button == GLFW_MOUSE_BUTTON_LEFT &&
             controls_.mode == render::ViewMode::fluoroscopy) {
    drag_ = Drag::carm;
  } else {
    const render::MouseButton b = button == GLFW_MOUSE_BUTTON_LEFT    ? render::MouseButton::left
                                  : button == GLFW_MOUSE_BUTTON_RIGHT ? render::MouseButton::right
                                                                      : render::MouseButton::middle;
    camera_.button(b, pressed, shift, ctrl);
  }
}

void WindowInput::on_cursor(double x, double y) {
  const double dx = x - last_x_, dy = y - last_y_;
  const bool had = have_cursor_;
  last_x_ = x;
  last_y_ = y;
  have_cursor_ = true;
  int w = 0, h = 0;
  glfwGetWindowSize(window_, &w, &h);
  if (drag_ == Drag::none) {
    camera_.cursor(x, y, h);
    return;
  }
  camera_.cursor(x, y, h);  // keeps the controller's cursor current
  if (!had) return;
  if (drag_ == Drag::push) tool_.move_cursor(dx, dy);
  if (drag_ == Drag::steer) tool_.steer(dx, dy);
  if (drag_ == Drag::carm) {
    controls_.carm_lao_deg =
        std::clamp(controls_.carm_lao_deg + static_cast<float>(kCarmDegPerPixel * dx), -90.0f, 90.0f);
    controls_.carm_cranial_deg =
        std::clamp(controls_.carm_cranial_deg - static_cast<float>(kCarmDegPerPixel * dy), -45.0f, 45.0f);
  }
}

void WindowInput::on_scroll(double dy, bool ctrl) {
  if (hud_has_mouse()) return;
  if (ctrl)
    tool_.scroll(dy);
  else
    camera_.scroll(dy);
}

bool WindowInput::tool_key(int key, bool pressed) {
  switch (key) {
    case GLFW_KEY_W:
    case GLFW_KEY_UP:
      tool_.set_key(ToolKey::insert, pressed);
      return true;
    case GLFW_KEY_S:
    case GLFW_KEY_DOWN:
      tool_.set_key(ToolKey::retract, pressed);
      return true;
    case GLFW_KEY_A:
    case GLFW_KEY_LEFT:
      tool_.set_key(ToolKey::twist_left, pressed);
      return true;
    case GLFW_KEY_D:
    case GLFW_KEY_RIGHT:
      tool_.set_key(ToolKey::twist_right, pressed);
      return true;
    default:
      return false;
  }
}

void WindowInput::on_key(int key, int action, int /*mods*/) {
  if (action == GLFW_RELEASE) {
    tool_key(key, false);  // always: a release must never be lost to the panel
    return;
  }
  if (action != GLFW_PRESS || (hud_ != nullptr && hud_->wants_keyboard())) return;
  if (tool_key(key, true)) return;
  switch (key) {
    case GLFW_KEY_ESCAPE:
      glfwSetWindowShouldClose(window_, GLFW_TRUE);
      break;
    case GLFW_KEY_F:
      toggle_mode(controls_);
      break;
    case GLFW_KEY_LEFT_BRACKET:
      controls_.carm_lao_deg = std::max(-90.0f, controls_.carm_lao_deg - kCarmKeyStepDeg);
      break;
    case GLFW_KEY_RIGHT_BRACKET:
      controls_.carm_lao_deg = std::min(90.0f, controls_.carm_lao_deg + kCarmKeyStepDeg);
      break;
    case GLFW_KEY_PAGE_UP:
      controls_.carm_cranial_deg = std::min(45.0f, controls_.carm_cranial_deg + kCarmKeyStepDeg);
      break;
    case GLFW_KEY_PAGE_DOWN:
      controls_.carm_cranial_deg = std::max(-45.0f, controls_.carm_cranial_deg - kCarmKeyStepDeg);
      break;
    case GLFW_KEY_SPACE:
      requests_.toggle_pause = true;
      break;
    case GLFW_KEY_N:
    case GLFW_KEY_PERIOD:
      requests_.step = true;
      break;
    case GLFW_KEY_BACKSPACE:
    case GLFW_KEY_F5:
      requests_.reset_scene = true;
      break;
    case GLFW_KEY_P:
    case GLFW_KEY_F12:
      requests_.screenshot = true;
      break;
    case GLFW_KEY_H:
      requests_.toggle_hud = true;
      break;
    case GLFW_KEY_C:
      controls_.colour_field = controls_.colour_field == render::ColourField::none
                                   ? render::ColourField::displacement
                                   : render::ColourField::none;
      break;
    case GLFW_KEY_R:
    case GLFW_KEY_HOME:
      orbit_.reset();
      break;
    default:
      break;
  }
}

}  // namespace vascsim::viewer
