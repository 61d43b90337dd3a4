// The one set of Trilinos template arguments the project uses (Debian's Tpetra is instantiated for
// double / int / long long on the Serial node only), and short names for the Xpetra types.
#pragma once

#include <Teuchos_RCP.hpp>
#include <Teuchos_Comm.hpp>
#include <Tpetra_Map.hpp>
#include <Xpetra_BlockedCrsMatrix_fwd.hpp>
#include <Xpetra_Map_fwd.hpp>
#include <Xpetra_MapExtractor_fwd.hpp>
#include <Xpetra_Matrix_fwd.hpp>
#include <Xpetra_CrsMatrix_fwd.hpp>
#include <Xpetra_MultiVector_fwd.hpp>
#include <Xpetra_StridedMap_fwd.hpp>

#include <stdexcept>
#include <string>

namespace multigrid
{
  using SC = double;
  using LO = int;
  using GO = long long;
  using NO = Tpetra::Map<LO, GO>::node_type;

  using Comm             = Teuchos::Comm<int>;
  using Map              = Xpetra::Map<LO, GO, NO>;
  using StridedMap       = Xpetra::StridedMap<LO, GO, NO>;
  using MapExtractor     = Xpetra::MapExtractor<SC, LO, GO, NO>;
  using Matrix           = Xpetra::Matrix<SC, LO, GO, NO>;
  using CrsMatrix        = Xpetra::CrsMatrix<SC, LO, GO, NO>;
  using BlockedCrsMatrix = Xpetra::BlockedCrsMatrix<SC, LO, GO, NO>;
  using MultiVector      = Xpetra::MultiVector<SC, LO, GO, NO>;

  using Teuchos::RCP;

  /// Every error that reaches a user: the message is one line naming the input, the value and
  /// what was expected. Apps turn it into a message on stderr and a non-zero exit.
  class InputError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };
} // namespace multigrid
