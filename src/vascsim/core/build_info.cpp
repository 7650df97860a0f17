#include "vascsim/core/build_info.hpp"

#include <omp.h>

#include <cholmod.h>
#include <fmt/format.h>

#include "vascsim/core/blas_control.hpp"
#include "vascsim/core/bundled_files.hpp"

// Set by src/CMakeLists.txt.
#ifndef VASCSIM_VERSION
#define VASCSIM_VERSION "unknown"
#endif
#ifndef VASCSIM_BUILD_TYPE
#define VASCSIM_BUILD_TYPE ""
#endif
#ifndef VASCSIM_LIBRARY_TYPE
#define VASCSIM_LIBRARY_TYPE ""
#endif
#ifndef VASCSIM_SANITIZERS
#define VASCSIM_SANITIZERS ""
#endif

namespace vascsim {

namespace {

#if defined(__clang__)
constexpr const char* kCompiler = "clang " __clang_version__;
#elif defined(__GNUC__)
constexpr const char* kCompiler = "gcc " __VERSION__;
#else
constexpr const char* kCompiler = "unknown";
#endif

std::string blas_description() {
  const std::string lib = blas_library();
  if (lib.empty()) return "none loaded";
  const std::string config = blas_config();
  return config.empty() ? lib : fmt::format("{} ({})", lib, config);
}

}  // namespace

std::string version() {
  return VASCSIM_VERSION;
}

BuildInfo build_info() {
  BuildInfo b;
  b.version = version();
  b.build_type = VASCSIM_BUILD_TYPE;
  b.compiler = kCompiler;
  b.library = VASCSIM_LIBRARY_TYPE;
  b.sanitizers = VASCSIM_SANITIZERS;
  b.openmp = std::to_string(_OPENMP);
  b.omp_max_threads = omp_get_max_threads();
  b.blas = blas_description();
  b.cholmod = fmt::format("{}.{}.{}", CHOLMOD_MAIN_VERSION, CHOLMOD_SUB_VERSION, CHOLMOD_SUBSUB_VERSION);
  b.bundled_files = bundled_root().string();
  return b;
}

std::string format_build_info(const BuildInfo& b) {
  std::string s = fmt::format("vascsim {}\n", b.version);
  s += fmt::format("build type: {}\n", b.build_type.empty() ? "(none)" : b.build_type);
  s += fmt::format("compiler: {}\n", b.compiler);
  s += fmt::format("library: {}\n", b.library);
  s += fmt::format("sanitizers: {}\n", b.sanitizers.empty() ? "none" : b.sanitizers);
  s += fmt::format("OpenMP: {} ({} threads)\n", b.openmp, b.omp_max_threads);
  s += fmt::format("BLAS: {}\n", b.blas);
  s += fmt::format("CHOLMOD: {}\n", b.cholmod);
  s += fmt::format("bundled files: {}\n", b.bundled_files);
  return s;
}

}  // namespace vascsim
