#include "vascsim/render/gl_program.hpp"

#include <epoxy/gl.h>
#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace vascsim::render {

namespace {

GLuint compile(GLenum type, const std::string& source, const std::string& name) {
  const GLuint shader = glCreateShader(type);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok == GL_FALSE) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    glDeleteShader(shader);
    throw std::logic_error(fmt::format("shader {} ({}) does not compile: {}", name,
                                       type == GL_VERTEX_SHADER ? "vertex" : "fragment", log));
  }
  return shader;
}

}  // namespace

GlProgram::GlProgram(const std::string& name, const std::string& vertex_source,
                     const std::string& fragment_source)
    : name_(name) {
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex_source, name);
  GLuint fs = 0;
  try {
    fs = compile(GL_FRAGMENT_SHADER, fragment_source, name);
  } catch (...) {
    glDeleteShader(vs);
    throw;
  }
  id_ = glCreateProgram();
  glAttachShader(id_, vs);
  glAttachShader(id_, fs);
  glLinkProgram(id_);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (ok == GL_FALSE) {
    GLint length = 0;
    glGetProgramiv(id_, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    glGetProgramInfoLog(id_, length, nullptr, log.data());
    glDeleteProgram(id_);
    id_ = 0;
    throw std::logic_error(fmt::format("shader program {} does not link: {}", name, log));
  }
}

GlProgram::~GlProgram() {
  if (id_ != 0) glDeleteProgram(id_);
}

GlProgram::GlProgram(GlProgram&& other) noexcept
    : id_(std::exchange(other.id_, 0)),
      name_(std::move(other.name_)),
      locations_(std::move(other.locations_)) {}

GlProgram& GlProgram::operator=(GlProgram&& other) noexcept {
  if (this != &other) {
    if (id_ != 0) glDeleteProgram(id_);
    id_ = std::exchange(other.id_, 0);
    name_ = std::move(other.name_);
    locations_ = std::move(other.locations_);
  }
  return *this;
}

void GlProgram::use() const {
  glUseProgram(id_);
}

int GlProgram::location(const char* name) {
  auto it = locations_.find(name);
  if (it == locations_.end()) it = locations_.emplace(name, glGetUniformLocation(id_, name)).first;
  return it->second;  // -1 (ignored by glUniform*) if the compiler removed an unused uniform
}

void GlProgram::set(const char* name, int value) {
  glUniform1i(location(name), value);
}
void GlProgram::set(const char* name, unsigned value) {
  glUniform1ui(location(name), value);
}
void GlProgram::set(const char* name, float value) {
  glUniform1f(location(name), value);
}
void GlProgram::set(const char* name, const Eigen::Vector2f& v) {
  glUniform2f(location(name), v.x(), v.y());
}
void GlProgram::set(const char* name, const Eigen::Vector3f& v) {
  glUniform3f(location(name), v.x(), v.y(), v.z());
}
void GlProgram::set(const char* name, const Eigen::Vector4f& v) {
  glUniform4f(location(name), v.x(), v.y(), v.z(), v.w());
}
void GlProgram::set(const char* name, const Eigen::Matrix4f& m) {
  glUniformMatrix4fv(location(name), 1, GL_FALSE, m.data());
}

}  // namespace vascsim::render
