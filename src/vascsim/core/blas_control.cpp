#include "vascsim/core/blas_control.hpp"

#include <dlfcn.h>
#include <strings.h>
#include <unistd.h>

#include <climits>
#include <cstdlib>
#include <mutex>

namespace vascsim {

namespace {
// Symbols are looked up in everything the process has loaded (the BLAS comes in with libcholmod).
void* symbol(const char* name) {
  return dlsym(RTLD_DEFAULT, name);
}
}  // namespace

std::string blas_library() {
  void* f = symbol("dgemm_");
  Dl_info info;
  if (!f || !dladdr(f, &info) || !info.dli_fname) return {};
  char resolved[PATH_MAX];
  return realpath(info.dli_fname, resolved) ? std::string(resolved) : std::string(info.dli_fname);
}

std::string blas_config() {
  using Fn = char* (*)();
  auto f = reinterpret_cast<Fn>(symbol("openblas_get_config"));
  return f ? std::string(f()) : std::string();
}

bool set_blas_threads(int threads) {
  using Fn = void (*)(int);
  auto f = reinterpret_cast<Fn>(symbol("openblas_set_num_threads"));
  if (!f) return false;
  f(threads);
  return true;
}

int blas_threads() {
  using Fn = int (*)();
  auto f = reinterpret_cast<Fn>(symbol("openblas_get_num_threads"));
  return f ? f() : 1;
}

int apply_default_blas_threads() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (std::getenv("OPENBLAS_NUM_THREADS") == nullptr && std::getenv("OMP_NUM_THREADS") == nullptr)
      set_blas_threads(1);
  });
  return blas_threads();
}

std::string blas_core_override() {
#if defined(__x86_64__) && defined(__GNUC__)
  if (std::getenv("OPENBLAS_CORETYPE") != nullptr) return {};
  using Fn = char* (*)();
  auto f = reinterpret_cast<Fn>(symbol("openblas_get_corename"));
  const char* core = f ? f() : nullptr;
  if (core == nullptr || strcasecmp(core, "Prescott") != 0) return {};
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
      __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl"))
    return "SkylakeX";
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return "Haswell";
#endif
  return {};
}

void restart_with_blas_core(char** argv) {
  const std::string core = blas_core_override();
  if (core.empty() || setenv("OPENBLAS_CORETYPE", core.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
  unsetenv("OPENBLAS_CORETYPE");  // exec failed: run on as before
}

}  // namespace vascsim
