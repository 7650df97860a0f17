#include "vascsim/core/bundled_files.hpp"

#include <dlfcn.h>

#include <cstdlib>

// Set by src/CMakeLists.txt; the defaults keep the file compilable on its own.
#ifndef VASCSIM_SOURCE_DIR
#define VASCSIM_SOURCE_DIR "."
#endif
#ifndef VASCSIM_BUILD_TREE_DIR
#define VASCSIM_BUILD_TREE_DIR ""
#endif
#ifndef VASCSIM_INSTALL_DATADIR
#define VASCSIM_INSTALL_DATADIR ""
#endif
#ifndef VASCSIM_DATADIR_FROM_OBJECT
#define VASCSIM_DATADIR_FROM_OBJECT "../share/vascsim"
#endif

namespace vascsim {

namespace fs = std::filesystem;

namespace {

// The file this code was loaded from: libvascsim.so when the library is shared, else the program (or Python
// module) it was linked into. Empty if the loader cannot say.
fs::path loaded_object() {
  Dl_info info;
  if (!dladdr(reinterpret_cast<void*>(&bundled_roots), &info) || !info.dli_fname) return {};
  std::error_code ec;
  const fs::path p = fs::canonical(info.dli_fname, ec);
  return ec ? fs::path(info.dli_fname) : p;
}

// True if `object` lies in `folder` or below it.
bool inside(const fs::path& object, const fs::path& folder) {
  if (folder.empty()) return false;
  std::error_code ec;
  const fs::path f = fs::weakly_canonical(folder, ec);
  if (ec) return false;
  const fs::path rel = object.lexically_relative(f);
  return !rel.empty() && *rel.begin() != "..";
}

}  // namespace

std::vector<fs::path> bundled_roots() {
  std::vector<fs::path> roots;
  if (const char* env = std::getenv("VASCSIM_DATA_DIR"); env && *env) roots.emplace_back(env);
  const fs::path object = loaded_object();
  const fs::path source(VASCSIM_SOURCE_DIR);
  if (!object.empty()) {
    roots.push_back((object.parent_path() / VASCSIM_DATADIR_FROM_OBJECT).lexically_normal());
    if (inside(object, VASCSIM_BUILD_TREE_DIR)) roots.push_back(source);
  }
  if (*VASCSIM_INSTALL_DATADIR) roots.emplace_back(VASCSIM_INSTALL_DATADIR);
  roots.push_back(source);
  return roots;
}

fs::path bundled_file(const std::string& relative) {
  const std::vector<fs::path> roots = bundled_roots();
  std::error_code ec;
  for (const fs::path& r : roots)
    if (fs::exists(r / relative, ec)) return r / relative;
  return bundled_root() / relative;
}

fs::path bundled_root() {
  const std::vector<fs::path> roots = bundled_roots();
  std::error_code ec;
  for (const fs::path& r : roots)
    if (fs::is_directory(r / "scenes", ec) && fs::is_directory(r / "scripts", ec)) return r;
  return roots.front();
}

}  // namespace vascsim
