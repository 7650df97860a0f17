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

/// The OPENBLAS_CORETYPE this process should have started with: OpenBLAS chooses its kernels from a table of
/// CPU models when it loads and, for a model newer than the table, falls back to its generic "Prescott"
/// (SSE3) kernels. OpenBLAS 0.3.21 (Debian 12's) does so on an Intel Xeon of family 6, model 207, where the
/// wall multigrid's coarse solves then run 1.2x and its level builds 1.4x slower (docs/performance.md, "Real
/// time at hand speed"). Returns "SkylakeX" (AVX-512 F, BW, DQ, VL) or "Haswell" (AVX2, FMA) when OpenBLAS
/// runs Prescott on such a CPU; empty when OpenBLAS chose its own core, OPENBLAS_CORETYPE is set, or the BLAS
/// is not OpenBLAS.
std::string blas_core_override();

/// When blas_core_override() names a core: sets OPENBLAS_CORETYPE to it and executes this program again
/// (/proc/self/exe) with the same arguments, because OpenBLAS reads the variable only when it loads. Returns
/// when there is nothing to do or the exec failed (the program then runs on with the generic kernels). Call
/// it first thing in main, before any thread starts.
void restart_with_blas_core(char** argv);

}  // namespace vascsim
