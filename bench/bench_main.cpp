// vascsim_bench's entry point: Google Benchmark's, after OpenBLAS has been given the kernels of the CPU it
// runs on (core/blas_control.hpp, restart_with_blas_core), as the vascsim program does, so that the figures
// are the program's.
#include <benchmark/benchmark.h>

#include "vascsim/core/blas_control.hpp"

int main(int argc, char** argv) {
  vascsim::restart_with_blas_core(argv);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
