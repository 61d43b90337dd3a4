// Start-up of Tpetra (and the Kokkos it initializes) for the project's apps. Kokkos reads the
// command line and answers --help with its own page before the app's usage; the apps' options
// are not Kokkos' business, so Kokkos sees the program name only. MPI is initialized here unless
// the caller (deal.II's MPI_InitFinalize) already has. It also sets the process's heap policy
// (keep_freed_memory_for_reuse below), which every app wants before its first large allocation.
#pragma once

#include <Tpetra_Core.hpp>

#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace multigrid
{
  /// Lets glibc serve large blocks from the heap and keep the ones freed there, instead of
  /// mapping every block above its mmap threshold fresh from the kernel, unmapping it on free,
  /// and trimming the heap's top whenever more than twice that threshold is free. Both
  /// thresholds adapt only up to 32 / 64 MB, and an AMG set-up allocates and frees blocks of
  /// that order many times (the merged matrix's values at 4.7 M nonzeros are 38 MB; the
  /// Galerkin products' arrays likewise): each time the pages were faulted in and zeroed again by
  /// the kernel, which on a virtual machine costs more than the arithmetic on them. Measured on
  /// the 3D contact benchmark's 66 k system (1 rank, solve_block_system,
  /// fully-coupled-sa-amg(simple), runs alternating): set-up 1.67 / 1.67 -> 0.92 s, peak memory
  /// 474 -> 522 MB. The contact app itself on 1 rank at that size was unchanged (49.1-51.6 s,
  /// 880 MB peak, either way). Pages stay with the process until freed memory is trimmed: the
  /// step driver's once-per-step malloc_trim (`Step control/Return free memory`) still gives
  /// them back between steps.
  inline void keep_freed_memory_for_reuse()
  {
#ifdef __GLIBC__
    constexpr int one_gigabyte = 1 << 30; // larger blocks are still mapped
    mallopt(M_MMAP_THRESHOLD, one_gigabyte);
    mallopt(M_TRIM_THRESHOLD, one_gigabyte);
#endif
  }

  class TrilinosScope
  {
  public:
    explicit TrilinosScope(char** argv)
        : argv_(argv)
        , guard_(&argc_, &argv_)
    {
      keep_freed_memory_for_reuse();
    }

  private:
    int                argc_ = 1; // declared before guard_: initialized first
    char**             argv_;
    Tpetra::ScopeGuard guard_;
  };
} // namespace multigrid
