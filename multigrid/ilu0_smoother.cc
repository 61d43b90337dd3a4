#include "ilu0_smoother.h"

#include "row_product.h"

#include <Tpetra_CrsMatrix.hpp>
#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_BlockedMultiVector.hpp>
#include <Xpetra_MatrixMatrix.hpp>
#include <Xpetra_MultiVectorFactory.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

namespace multigrid
{
  namespace
  {
    /// The rank-local block of A in compressed rows sorted by column, with the position of every
    /// row's diagonal (inserted as an explicit zero where A has none).
    struct LocalRows
    {
      std::vector<std::size_t> offsets;
      std::vector<LO>          columns;
      std::vector<double>      values;
      std::vector<std::size_t> diagonal;
    };

    LocalRows local_rows(const Matrix& A_matrix)
    {
      if (dynamic_cast<const BlockedCrsMatrix*>(&A_matrix) != nullptr)
        throw InputError("ILU(0): the matrix is blocked; it factorizes single blocks only");
      const auto& A     = Xpetra::Helpers<SC, LO, GO, NO>::Op2TpetraCrs(A_matrix);
      const auto  local = A.getLocalMatrixHost();
      const auto& rows  = *A.getRowMap();
      const auto& cols  = *A.getColMap();
      const LO    n     = static_cast<LO>(rows.getNodeNumElements());

      // Column -> row index of this rank (invalid for another rank's DOF).
      const auto      n_cols = static_cast<LO>(cols.getNodeNumElements());
      std::vector<LO> row_of_column(n_cols);
      const LO        invalid = Teuchos::OrdinalTraits<LO>::invalid();
      for (LO c = 0; c < n_cols; ++c)
        row_of_column[c] = rows.getLocalElement(cols.getGlobalElement(c));

      LocalRows                      r;
      std::vector<std::pair<LO, SC>> row;
      r.offsets.reserve(n + 1);
      r.offsets.push_back(0);
      r.columns.reserve(local.nnz() + n);
      r.values.reserve(local.nnz() + n);
      r.diagonal.resize(n);
      for (LO i = 0; i < n; ++i)
        {
          row.clear();
          bool has_diagonal = false;
          for (auto k = local.graph.row_map(i); k < local.graph.row_map(i + 1); ++k)
            {
              const LO j = row_of_column[local.graph.entries(k)];
              if (j == invalid)
                continue;
              row.emplace_back(j, local.values(k));
              has_diagonal = has_diagonal || j == i;
            }
          if (!has_diagonal)
            row.emplace_back(i, 0.0);
          std::sort(row.begin(), row.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
          for (const auto& [j, v] : row)
            {
              if (j == i)
                r.diagonal[i] = r.columns.size();
              r.columns.push_back(j);
              r.values.push_back(v);
            }
          r.offsets.push_back(r.columns.size());
        }
      return r;
    }
  } // namespace

  Ilu0Factors::Ilu0Factors(const RCP<const Matrix>& A, const Ilu0Thresholds& thresholds)
      : A_(A)
  {
    LocalRows  a = local_rows(*A);
    const auto n = a.diagonal.size();
    // Ifpack2's perturbation of the diagonal before the factorization (identity by default);
    // a diagonal missing from A's pattern becomes the absolute threshold.
    for (std::size_t i = 0; i < n; ++i)
      {
        double& d = a.values[a.diagonal[i]];
        d         = thresholds.relative * d + (d < 0.0 ? -thresholds.absolute : thresholds.absolute);
      }

    // Elimination row by row; position[j] is the place of column j in the current row i (or -1).
    inverse_diagonal_.resize(n);
    std::vector<long> position(n, -1);
    for (std::size_t i = 0; i < n; ++i)
      {
        for (auto p = a.offsets[i]; p < a.offsets[i + 1]; ++p)
          position[a.columns[p]] = static_cast<long>(p);
        for (auto p = a.offsets[i]; p < a.diagonal[i]; ++p)
          {
            const auto   k = static_cast<std::size_t>(a.columns[p]);
            const double l = a.values[p] * inverse_diagonal_[k];
            a.values[p]    = l;
            for (auto q = a.diagonal[k] + 1; q < a.offsets[k + 1]; ++q)
              if (const long at = position[a.columns[q]]; at >= 0)
                a.values[at] -= l * a.values[q];
          }
        const double pivot = a.values[a.diagonal[i]];
        if (pivot == 0.0 || !std::isfinite(pivot))
          throw InputError("ILU(0): pivot " + std::to_string(pivot) + " in local row " + std::to_string(i) +
                           " of " + std::to_string(n) +
                           "; set 'fact: absolute threshold' > 0 or choose another sub-smoother");
        inverse_diagonal_[i] = 1.0 / pivot;
        for (auto p = a.offsets[i]; p < a.offsets[i + 1]; ++p)
          position[a.columns[p]] = -1;
      }

    // Split into the strict triangles.
    lower_.offsets.assign(1, 0);
    upper_.offsets.assign(1, 0);
    for (std::size_t i = 0; i < n; ++i)
      {
        for (auto p = a.offsets[i]; p < a.offsets[i + 1]; ++p)
          {
            if (p == a.diagonal[i])
              continue;
            Triangle& t = p < a.diagonal[i] ? lower_ : upper_;
            t.columns.push_back(a.columns[p]);
            t.values.push_back(a.values[p]);
          }
        lower_.offsets.push_back(lower_.columns.size());
        upper_.offsets.push_back(upper_.columns.size());
      }
  }

  void Ilu0Factors::solve(const double* b, double* x) const
  {
    const std::size_t n = rows();
    // L y = b (y in x)
    for (std::size_t i = 0; i < n; ++i)
      {
        const auto start = lower_.offsets[i];
        x[i]             = b[i] - row_product(lower_.columns.data() + start, lower_.values.data() + start,
                                              lower_.offsets[i + 1] - start, x);
      }
    // U x = y
    for (std::size_t i = n; i-- > 0;)
      {
        const auto start = upper_.offsets[i];
        x[i]             = (x[i] - row_product(upper_.columns.data() + start, upper_.values.data() + start,
                                               upper_.offsets[i + 1] - start, x)) *
               inverse_diagonal_[i];
      }
  }

  void Ilu0Factors::apply(MultiVector& X, const MultiVector& B, bool zero_start) const
  {
    using Blocked = Xpetra::BlockedMultiVector<SC, LO, GO, NO>;
    if (dynamic_cast<Blocked*>(&X) != nullptr || dynamic_cast<const Blocked*>(&B) != nullptr)
      throw std::logic_error("ILU(0): applied to a blocked vector; it smooths single blocks only");
    if (X.getLocalLength() != rows() || B.getLocalLength() != rows())
      throw std::logic_error("ILU(0): vector length " + std::to_string(X.getLocalLength()) +
                             " on this rank, the factors have " + std::to_string(rows()) + " rows");
    if (zero_start)
      {
        for (std::size_t j = 0; j < X.getNumVectors(); ++j)
          solve(B.getData(j).get(), X.getDataNonConst(j).get());
        return;
      }
    // x += (L U)^-1 (b - A x)
    auto r = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(X.getMap(), X.getNumVectors(), false);
    A_->apply(X, *r);
    r->update(1.0, B, -1.0);
    for (std::size_t j = 0; j < X.getNumVectors(); ++j)
      {
        auto data = r->getDataNonConst(j);
        solve(data.get(), data.get());
      }
    X.update(1.0, *r, 1.0);
  }

  Ilu0Thresholds ilu0_thresholds(const Teuchos::ParameterList& settings, const std::string& sublist,
                                 const std::string& where)
  {
    Ilu0Thresholds t;
    if (!settings.isSublist(sublist))
      return t;
    const Teuchos::ParameterList& list = settings.sublist(sublist);
    for (auto entry = list.begin(); entry != list.end(); ++entry)
      {
        const std::string& name = list.name(entry);
        if (name == "fact: iluk level-of-fill" && list.isType<int>(name) && list.get<int>(name) == 0)
          continue; // RILUK's settings with level of fill 0 carry over
        if (name != "fact: absolute threshold" && name != "fact: relative threshold")
          throw InputError(where + ": ILU(0) has no parameter '" + name +
                           "' (expected 'fact: absolute threshold', 'fact: relative threshold' or "
                           "'fact: iluk level-of-fill' = 0)");
      }
    const auto number = [&](const std::string& name, double fallback) {
      if (!list.isParameter(name))
        return fallback;
      if (list.isType<double>(name))
        return list.get<double>(name);
      if (list.isType<int>(name))
        return static_cast<double>(list.get<int>(name));
      throw InputError(where + ": ILU(0)'s '" + name + "' is not a number");
    };
    t.absolute = number("fact: absolute threshold", t.absolute);
    t.relative = number("fact: relative threshold", t.relative);
    if (!(t.absolute >= 0.0) || !(t.relative > 0.0))
      throw InputError(where + ": ILU(0) expects 'fact: absolute threshold' >= 0 and "
                               "'fact: relative threshold' > 0");
    return t;
  }
} // namespace multigrid
