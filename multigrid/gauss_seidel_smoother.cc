#include "gauss_seidel_smoother.h"

#include "row_product.h"

#include <Teuchos_ParameterList.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_BlockedMultiVector.hpp>
#include <Xpetra_MatrixMatrix.hpp>
#include <Xpetra_TpetraMultiVector.hpp>

#include <cmath>
#include <type_traits>

namespace multigrid
{
  GaussSeidelSettings gauss_seidel_settings(const Teuchos::ParameterList& settings,
                                            const std::string& sublist, const std::string& where)
  {
    GaussSeidelSettings s;
    if (!settings.isSublist(sublist))
      return s;
    const Teuchos::ParameterList& list = settings.sublist(sublist);
    const std::string             type = "relaxation: type", sweeps = "relaxation: sweeps",
                      damping = "relaxation: damping factor";
    for (auto entry = list.begin(); entry != list.end(); ++entry)
      {
        const std::string& name = list.name(entry);
        if (name != type && name != sweeps && name != damping)
          throw InputError(where + ": SGS has no parameter '" + name + "' (expected '" + type + "', '" +
                           sweeps + "' or '" + damping + "')");
      }
    if (list.isParameter(type) &&
        (!list.isType<std::string>(type) || list.get<std::string>(type) != "Symmetric Gauss-Seidel"))
      throw InputError(
          where + ": SGS's '" + type +
          "' must be 'Symmetric Gauss-Seidel' (Ifpack2's other types: smoother type RELAXATION)");
    if (list.isParameter(sweeps))
      {
        if (!list.isType<int>(sweeps) || list.get<int>(sweeps) < 1)
          throw InputError(where + ": SGS's '" + sweeps + "' must be an integer >= 1");
        s.sweeps = list.get<int>(sweeps);
      }
    if (list.isParameter(damping))
      {
        if (list.isType<double>(damping))
          s.damping = list.get<double>(damping);
        else if (list.isType<int>(damping))
          s.damping = list.get<int>(damping);
        else
          throw InputError(where + ": SGS's '" + damping + "' is not a number");
        if (s.damping == 0.0 || !std::isfinite(s.damping))
          throw InputError(where + ": SGS's '" + damping + "' must be a finite number other than 0");
      }
    return s;
  }

  SymmetricGaussSeidel::SymmetricGaussSeidel(const RCP<const Matrix>& A, const GaussSeidelSettings& settings)
      : A_(A)
      , settings_(settings)
  {
    if (Teuchos::rcp_dynamic_cast<const BlockedCrsMatrix>(A).get() != nullptr)
      throw InputError("SGS: the matrix is blocked; it smooths single blocks only");
    const auto& tA = Xpetra::Helpers<SC, LO, GO, NO>::Op2TpetraCrs(*A);
    if (!tA.getRowMap()->isSameAs(*tA.getDomainMap()) || !tA.getRowMap()->isSameAs(*tA.getRangeMap()))
      throw std::logic_error("SGS: the matrix's row, domain and range maps differ");
    // The local arrays stay A's own (no copy): A_ keeps them alive, and a smoother is set up
    // again whenever its level's matrix changes.
    const auto local = tA.getLocalMatrixHost();
    static_assert(
        std::is_same_v<std::remove_const_t<typename decltype(local.graph.row_map)::value_type>, std::size_t>);
    rows_     = tA.getNodeNumRows();
    offsets_  = local.graph.row_map.data();
    columns_  = local.graph.entries.data();
    values_   = local.values.data();
    importer_ = tA.getGraph()->getImporter();

    // Row i's x lies at column index i: Tpetra's column map begins with the domain map's own
    // indices in their order, and every row holds its diagonal (checked below), so that every
    // own index appears among the columns.
    const auto& rows    = *tA.getRowMap();
    const auto& columns = *tA.getColMap();
    scaled_inverse_diagonal_.assign(rows_, 0.0);
    for (std::size_t i = 0; i < rows_; ++i)
      for (auto k = offsets_[i]; k < offsets_[i + 1]; ++k)
        if (static_cast<std::size_t>(columns_[k]) == i)
          scaled_inverse_diagonal_[i] = values_[k];
    for (std::size_t i = 0; i < rows_; ++i)
      {
        const double d = scaled_inverse_diagonal_[i];
        if (d == 0.0 || !std::isfinite(d))
          throw InputError("SGS: diagonal entry " + std::to_string(d) + " in local row " + std::to_string(i) +
                           " of " + std::to_string(rows_) + " (zero, missing or not finite)");
        if (columns.getGlobalElement(static_cast<LO>(i)) != rows.getGlobalElement(static_cast<LO>(i)))
          throw std::logic_error("SGS: the column map does not begin with the row map's indices");
        // omega * (1 / a_ii), rounded as Ifpack2 rounds it
        scaled_inverse_diagonal_[i] = settings_.damping * (1.0 / d);
      }

    // Where each row's strictly lower part ends, if every row lists it first (Tpetra sorts the
    // local columns; the other ranks' columns come after this rank's own).
    lower_ends_.resize(rows_);
    for (std::size_t i = 0; i < rows_ && !lower_ends_.empty(); ++i)
      {
        auto k = offsets_[i];
        while (k < offsets_[i + 1] && static_cast<std::size_t>(columns_[k]) < i)
          ++k;
        lower_ends_[i] = k;
        for (; k < offsets_[i + 1]; ++k)
          if (static_cast<std::size_t>(columns_[k]) < i)
            {
              lower_ends_.clear(); // unsorted: every sweep runs over whole rows
              break;
            }
      }
  }

  void SymmetricGaussSeidel::sweep(const double* b, double* x, bool forward, bool from_zero) const
  {
    // From zero, x_j = 0 for j >= i (and for the other ranks' columns) when row i is reached:
    // only the strictly lower part contributes, about half of the entries.
    const bool lower = from_zero && !lower_ends_.empty();
    const auto step  = [&](std::size_t i) {
      const auto start = offsets_[i];
      const auto end   = lower ? lower_ends_[i] : offsets_[i + 1];
      x[i] += scaled_inverse_diagonal_[i] *
              (b[i] - row_product(columns_ + start, values_ + start, end - start, x));
    };
    if (forward)
      for (std::size_t i = 0; i < rows_; ++i)
        step(i);
    else
      for (std::size_t i = rows_; i-- > 0;)
        step(i);
  }

  void SymmetricGaussSeidel::apply(MultiVector& X, const MultiVector& B, bool zero_start) const
  {
    using Blocked = Xpetra::BlockedMultiVector<SC, LO, GO, NO>;
    if (dynamic_cast<Blocked*>(&X) != nullptr || dynamic_cast<const Blocked*>(&B) != nullptr)
      throw std::logic_error("SGS: applied to a blocked vector; it smooths single blocks only");
    if (X.getLocalLength() != rows_ || B.getLocalLength() != rows_ || X.getNumVectors() != B.getNumVectors())
      throw std::logic_error("SGS: vectors of " + std::to_string(X.getLocalLength()) + " and " +
                             std::to_string(B.getLocalLength()) + " local rows, the matrix has " +
                             std::to_string(rows_));
    const auto columns = X.getNumVectors();

    // One rank (or no coupling to others): the sweeps run on X itself.
    if (importer_.is_null())
      {
        if (zero_start)
          X.putScalar(0.0);
        for (std::size_t j = 0; j < columns; ++j)
          {
            const auto b = B.getData(j);
            auto       x = X.getDataNonConst(j);
            for (int s = 0; s < settings_.sweeps; ++s)
              {
                sweep(b.get(), x.get(), true, s == 0 && zero_start);
                sweep(b.get(), x.get(), false, false);
              }
          }
        return;
      }

    // Several ranks: X on the column map, whose first rows_ entries are this rank's own; the other
    // ranks' values are imported before every sweep but a first one from zero.
    auto&       tX = Xpetra::toTpetra(X);
    const auto& tB = Xpetra::toTpetra(B);
    if (x_columns_.is_null() || x_columns_->getNumVectors() != columns)
      x_columns_ = Teuchos::rcp(new TpetraMultiVector(importer_->getTargetMap(), columns));
    auto own = x_columns_->offsetViewNonConst(tX.getMap(), 0);
    if (zero_start)
      x_columns_->putScalar(0.0);
    else
      x_columns_->doImport(tX, *importer_, Tpetra::INSERT);
    for (int s = 0; s < settings_.sweeps; ++s)
      {
        if (s > 0)
          x_columns_->doImport(*own, *importer_, Tpetra::INSERT);
        for (std::size_t j = 0; j < columns; ++j)
          {
            const auto b = tB.getData(j);
            auto       x = x_columns_->getDataNonConst(j);
            sweep(b.get(), x.get(), true, s == 0 && zero_start);
            sweep(b.get(), x.get(), false, false);
          }
      }
    Tpetra::deep_copy(tX, *own);
  }
} // namespace multigrid
