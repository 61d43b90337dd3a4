// MueLu pieces of the beam/solid preset `schur-sa-amg(spai)` (seed 001), built on
// inverse_approximation.h:
//   SpaiSchurComplementFactory  S = A11 - (1/omega) A10 Â A01 on every level, Â the sparse
//                               approximate inverse of A00 (spai, diagonal or lumping). MueLu
//                               13.2's SchurComplementFactory only knows diag(A00)^-1.
//   SpaiSmoother                x <- x + damping Â (b - A x), Â = SPAI of the level's matrix
//                               (Bröker & Grote 2002), or the Â the Schur complement factory of
//                               the same level computed ("Ainv"), so it is computed once.
// Both are registered by name in ProjectFactoryFactory, so preset XML files can use them.
#pragma once

#include "types.h"

#include <Teuchos_ParameterList.hpp>

#include <map>
#include <string>

namespace MueLu
{
  class FactoryBase;
}

namespace multigrid
{
  /// The MueLu factory for `name` configured from `list` (the XML sublist), or null if `name` is
  /// not one of the SPAI pieces. `factories`: those defined so far (SpaiSmoother's "Ainv" names
  /// one, usually the SpaiSchurComplementFactory, whose Â it then reuses).
  RCP<const MueLu::FactoryBase> build_spai_factory(const std::string& name, const Teuchos::ParameterList& list,
                                                   const std::map<std::string, RCP<const MueLu::FactoryBase>>& factories);
} // namespace multigrid
