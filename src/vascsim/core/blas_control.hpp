#pragma once
// Which BLAS the process runs (CHOLMOD's supernodal factorisation spends its time in it) and how many
// threads it may use. Debian selects the BLAS behind libblas.so.3 with update-alternatives: the reference
// BLAS (package libblas3, single-threaded, unblocked loops) or OpenBLAS (libopenblas0-pthread: threaded
// with its own pthread pool; libopenblas0-openmp: threaded with OpenMP). The calls below find out at run
// time, so the same binary works with either.
//
// Threads: an OpenBLAS pthread pool spins on every core it owns while it has work, which starves a haptic
// thread on a 2-core machine. Give a factorisation one thread (set_blas_threads(1), or the environment
// variable OPENBLAS_NUM_THREADS=1 before the process starts) when another thread owns the other core.

#include <string>

namespace vascsim {

/// The shared library that provides the BLAS routine dgemm_ to this process, with symbolic links resolved
/// (e.g. ".../openblas-pthread/libblas.so.3"); empty if no BLAS is loaded.
std::string blas_library();

/// OpenBLAS's build description (openblas_get_config: version, target CPU, threading), or empty if the
/// BLAS is not OpenBLAS.
std::string blas_config();

/// Sets the thread count of an OpenBLAS BLAS (openblas_set_num_threads). Returns false if the BLAS has no
/// such control (the reference BLAS, which is always single-threaded).
bool set_blas_threads(int threads);

/// The thread count the BLAS will use: OpenBLAS's openblas_get_num_threads, else 1.
int blas_threads();

/// vascsim's default, applied once per process by the first sparse factorisation: one BLAS thread, unless the
/// environment asks for a count (OPENBLAS_NUM_THREADS or OMP_NUM_THREADS set). Measured on 2 cores: the
/// supernodal factors of the equilibrium solvers took 1.0-1.9x longer with 2 OpenBLAS threads than with 1
/// (bench/results), and with another process on the machine the pool's spinning turned a 20 s run into 46 s
/// (30 s of it in the kernel's sched_yield). Returns the thread count in force afterwards.
int apply_default_blas_threads();

}  // namespace vascsim
