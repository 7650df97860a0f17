#pragma once
// A linked GLSL program (RAII) with uniform setters that look the location up by name once.
// Compile or link failures are bugs in the renderer: std::logic_error with the driver's log.

#include <string>
#include <unordered_map>

#include <Eigen/Core>

namespace vascsim::render {

class GlProgram {
 public:
  GlProgram() = default;
  GlProgram(const std::string& name, const std::string& vertex_source, const std::string& fragment_source);
  ~GlProgram();
  GlProgram(GlProgram&& other) noexcept;
  GlProgram& operator=(GlProgram&& other) noexcept;
  GlProgram(const GlProgram&) = delete;
  GlProgram& operator=(const GlProgram&) = delete;

  void use() const;
  unsigned id() const { return id_; }

  void set(const char* name, int value);
  void set(const char* name, unsigned value);
  void set(const char* name, float value);
  void set(const char* name, const Eigen::Vector2f& value);
  void set(const char* name, const Eigen::Vector3f& value);
  void set(const char* name, const Eigen::Vector4f& value);
  void set(const char* name, const Eigen::Matrix4f& value);

 private:
  int location(const char* name);
  unsigned id_ = 0;
  std::string name_;
  std::unordered_map<std::string, int> locations_;
};

}  // namespace vascsim::render
