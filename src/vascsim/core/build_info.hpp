#pragma once
// The version of this library (project(VERSION ...) in CMakeLists.txt) and how it was built, for
// `vascsim --version`, the Python module's build_info() and bug reports.

#include <string>

namespace vascsim {

/// "MAJOR.MINOR.PATCH" of the library this code runs in.
std::string version();

struct BuildInfo {
  std::string version;     ///< as version()
  std::string build_type;  ///< CMAKE_BUILD_TYPE (Release, Debug, ...)
  std::string compiler;    ///< e.g. "gcc 12.2.0"
  std::string library;     ///< "shared" or "static" libvascsim
  std::string sanitizers;  ///< VASCSIM_SANITIZE ("" : none)
  std::string openmp;      ///< the OpenMP specification date the compiler implements (_OPENMP), e.g. "201511"
  int omp_max_threads = 0;  ///< threads an OpenMP region would use now
  std::string blas;     ///< the BLAS library loaded at run time (blas_control.hpp), with OpenBLAS's config
  std::string cholmod;  ///< the CHOLMOD version compiled against
  std::string
      bundled_files;  ///< the folder bundled scenes, data and scripts are read from (bundled_files.hpp)
};

/// The build of this library and the run-time libraries it found.
BuildInfo build_info();

/// build_info() as "key: value" lines, one per field, after a first line "vascsim VERSION".
std::string format_build_info(const BuildInfo& info);

}  // namespace vascsim
