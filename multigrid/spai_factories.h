// MueLu pieces of the beam/solid preset `schur-sa-amg(spai)` (seed 001: "special MueLu
// factories"), built on inverse_approximation.h, for what MueLu 13.2 lacks:
//   InverseApproximationFactory  "Ainv" = Â ≈ A^-1 of its "A": diagonal, row-sum,
//                                absolute-row-sum (lumping) or spai (min ||A Â - I||_F over the
//                                pattern of A^k, drop tolerance).
//   SpaiSchurComplementFactory   S = A11 - (1/omega) A10 Â A01 on every level with Â = "Ainv"
//                                (MueLu 13.2's SchurComplementFactory only knows diag(A00)^-1).
//   SpaiSmoother                 x <- x + damping Â (b - A x) with Â = "Ainv" (Bröker & Grote
//                                2002); sharing the Schur complement's Â computes it once.
//   SpaiSimpleSmoother           (spai_simple_smoother.h) SIMPLE with Â also in the final update.
// Registered by name in ProjectFactoryFactory; in the XML, "A" and "Ainv" name the factories
// that produce them (defined earlier in the list).
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
