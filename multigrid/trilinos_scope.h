// Start-up of Tpetra (and the Kokkos it initializes) for the project's apps. Kokkos reads the
// command line and answers --help with its own page before the app's usage; the apps' options
// are not Kokkos' business, so Kokkos sees the program name only. MPI is initialized here unless
// the caller (deal.II's MPI_InitFinalize) already has.
#pragma once

#include <Tpetra_Core.hpp>

namespace multigrid
{
  class TrilinosScope
  {
  public:
    explicit TrilinosScope(char** argv)
        : argv_(argv)
        , guard_(&argc_, &argv_)
    {
    }

  private:
    int                argc_ = 1; // declared before guard_: initialized first
    char**             argv_;
    Tpetra::ScopeGuard guard_;
  };
} // namespace multigrid
