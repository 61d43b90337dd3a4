#include "coupled_prolongator.h"

#include <MueLu_Level.hpp>
#include <MueLu_Monitor.hpp>
#include <MueLu_Utilities.hpp>

#include <Teuchos_CommHelpers.hpp>
#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_MapExtractor.hpp>
#include <Xpetra_MatrixFactory.hpp>
#include <Xpetra_MatrixMatrix.hpp>
#include <Xpetra_VectorFactory.hpp>

#include <cmath>
#include <set>
#include <sstream>
#include <vector>

namespace multigrid
{
  namespace
  {
    using Vector    = Xpetra::Vector<SC, LO, GO, NO>;
    using Utilities = MueLu::Utilities<SC, LO, GO, NO>;

    /// The stream Xpetra's matrix-matrix kernels write their diagnostics to: nowhere.
    Teuchos::FancyOStream& quiet_stream()
    {
      static Teuchos::FancyOStream quiet(Teuchos::rcp(new Teuchos::oblackholestream()));
      return quiet;
    }

    /// The entries of every block of M over all ranks, with one reduction for all blocks
    /// (counted here: MueLu's tentative prolongators are filled without Tpetra's global
    /// constants). entries[i][j] for block (i, j).
    std::vector<std::vector<long long>> block_entries(const BlockedCrsMatrix& M)
    {
      std::vector<long long> local(M.Rows() * M.Cols(), 0), total(local.size(), 0);
      for (std::size_t i = 0; i < M.Rows(); ++i)
        for (std::size_t j = 0; j < M.Cols(); ++j)
          if (const auto Mij = M.getMatrix(i, j); !Mij.is_null())
            local[i * M.Cols() + j] = Mij->getNodeNumEntries();
      Teuchos::reduceAll(*M.getRangeMap()->getComm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()),
                         local.data(), total.data());
      std::vector<std::vector<long long>> entries(M.Rows(), std::vector<long long>(M.Cols()));
      for (std::size_t i = 0; i < M.Rows(); ++i)
        for (std::size_t j = 0; j < M.Cols(); ++j)
          entries[i][j] = total[i * M.Cols() + j];
      return entries;
    }

    /// Which blocks of M have entries on some rank. filled[i][j] for block (i, j).
    std::vector<std::vector<bool>> filled_blocks(const BlockedCrsMatrix& M)
    {
      const auto                     entries = block_entries(M);
      std::vector<std::vector<bool>> filled(M.Rows(), std::vector<bool>(M.Cols()));
      for (std::size_t i = 0; i < M.Rows(); ++i)
        for (std::size_t j = 0; j < M.Cols(); ++j)
          filled[i][j] = entries[i][j] > 0;
      return filled;
    }

    bool is_block_diagonal(const std::vector<std::vector<long long>>& entries)
    {
      for (std::size_t i = 0; i < entries.size(); ++i)
        for (std::size_t j = 0; j < entries[i].size(); ++j)
          if (i != j && entries[i][j] > 0)
            return false;
      return true;
    }

    /// D_i^-1 of every diagonal block (MueLu's SaPFactory takes the same diag(A)^-1, with its
    /// zero-diagonal guard).
    std::vector<RCP<Vector>> inverse_diagonals(const BlockedCrsMatrix&               A,
                                               const std::vector<std::vector<bool>>& filled)
    {
      std::vector<RCP<Vector>> inverses;
      for (std::size_t i = 0; i < A.Rows(); ++i)
        {
          const auto Aii = A.getMatrix(i, i);
          if (!filled[i][i])
            throw InputError("CoupledSaPFactory: diagonal block " + std::to_string(i) +
                             " of the operator is empty");
          inverses.push_back(Utilities::GetMatrixDiagonalInverse(*Aii));
        }
      return inverses;
    }

    /// lambda_max(D^-1 A) by the power method on the blocked operator without the blocks
    /// `left_out` (the rows kept tentative: a saddle-point field's D^-1 A would set omega for
    /// the others), the Rayleigh quotient of the last iterate (as MueLu's PowerMethod, which takes
    /// no blocked matrix): per block z_i = D_i^-1 sum_j A_ij q_j.
    double largest_eigenvalue(const BlockedCrsMatrix& A, const std::vector<std::vector<bool>>& filled,
                              const std::vector<RCP<Vector>>& inverse_diagonal, int iterations,
                              const std::set<std::size_t>& left_out)
    {
      const auto               n = A.Rows();
      std::vector<RCP<Vector>> q(n), z(n);
      for (std::size_t i = 0; i < n; ++i)
        {
          q[i] = Xpetra::VectorFactory<SC, LO, GO, NO>::Build(A.getMatrix(i, i)->getDomainMap());
          q[i]->setSeed(100 + i); // a fixed start: the same omega in every run on the same ranks
          q[i]->randomize();
          if (left_out.count(i))
            q[i]->putScalar(0.0);
          z[i] = Xpetra::VectorFactory<SC, LO, GO, NO>::Build(A.getMatrix(i, i)->getRangeMap());
        }
      auto norm = [&](const std::vector<RCP<Vector>>& v) {
        double s = 0;
        for (const auto& b : v)
          s += std::pow(b->norm2(), 2);
        return std::sqrt(s);
      };
      double lambda = 0;
      for (int k = 0; k < iterations; ++k)
        {
          const double scale = 1.0 / norm(q);
          for (auto& b : q)
            b->scale(scale);
          double rayleigh = 0;
          for (std::size_t i = 0; i < n; ++i)
            {
              z[i]->putScalar(0.0);
              if (left_out.count(i))
                continue;
              for (std::size_t j = 0; j < n; ++j)
                if (filled[i][j] && !left_out.count(j))
                  A.getMatrix(i, j)->apply(*q[j], *z[i], Teuchos::NO_TRANS, 1.0, 1.0);
              z[i]->elementWiseMultiply(1.0, *inverse_diagonal[i], *z[i], 0.0);
              rayleigh += z[i]->dot(*q[i]);
            }
          lambda = rayleigh;
          std::swap(q, z);
        }
      return lambda;
    }

    /// The diagonal block Pt_jj of a block-diagonal prolongator; throws if an off-diagonal block
    /// has entries.
    std::vector<RCP<Matrix>> diagonal_blocks(const BlockedCrsMatrix& Pt, std::size_t n)
    {
      if (Pt.Rows() != n || Pt.Cols() != n)
        {
          std::ostringstream message;
          message << "CoupledSaPFactory: the tentative prolongator has " << Pt.Rows() << " x " << Pt.Cols()
                  << " blocks, the operator " << n << " x " << n;
          throw InputError(message.str());
        }
      std::vector<RCP<Matrix>> blocks;
      const auto               filled = filled_blocks(Pt);
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
          if (i != j && filled[i][j])
            throw InputError("CoupledSaPFactory: 'P' must be block-diagonal (a BlockedPFactory of tentative "
                             "prolongators); block (" +
                             std::to_string(i) + ", " + std::to_string(j) + ") has entries");
      for (std::size_t i = 0; i < n; ++i)
        blocks.push_back(Pt.getMatrix(i, i));
      return blocks;
    }

    /// -omega D_i^-1 A_ij Pt_jj (+ Pt_ii where i == j).
    RCP<Matrix> smoothed_block(const Matrix& Aij, const RCP<Matrix>& Ptjj, const Vector& inverse_diagonal,
                               double omega, bool diagonal)
    {
      auto&                 quiet = quiet_stream();
      RCP<Matrix>           AP =
          Xpetra::MatrixMatrix<SC, LO, GO, NO>::Multiply(Aij, false, *Ptjj, false, quiet, true, true);
      // rows scaled by -omega D_i^-1 (Tpetra scales the values of a fill-complete matrix only row-wise)
      auto scaling = Xpetra::VectorFactory<SC, LO, GO, NO>::Build(inverse_diagonal.getMap());
      scaling->update(-omega, inverse_diagonal, 0.0);
      AP->leftScale(*scaling);
      if (!diagonal)
        return AP;
      RCP<Matrix> P;
      Xpetra::MatrixMatrix<SC, LO, GO, NO>::TwoMatrixAdd(*Ptjj, false, 1.0, *AP, false, 1.0, P, quiet);
      P->fillComplete(Ptjj->getDomainMap(), Ptjj->getRangeMap());
      return P;
    }

    /// sum_l X_il Y_lj over the nonempty products, fill-complete (null if there is none).
    /// Xpetra 13.2's TwoMatrixMultiplyBlock adds a third product to an unfinished sum and fails,
    /// which a 3 x 3 Galerkin product with a coupled P reaches.
    RCP<Matrix> sum_of_products(const BlockedCrsMatrix& X, const std::vector<std::vector<bool>>& X_filled,
                                const BlockedCrsMatrix& Y, const std::vector<std::vector<bool>>& Y_filled,
                                std::size_t i, std::size_t j)
    {
      auto&                 quiet = quiet_stream();
      RCP<Matrix>           sum;
      for (std::size_t l = 0; l < X.Cols(); ++l)
        {
          if (!X_filled[i][l] || !Y_filled[l][j])
            continue;
          const auto Xil = X.getMatrix(i, l), Ylj = Y.getMatrix(l, j);
          auto product =
              Xpetra::MatrixMatrix<SC, LO, GO, NO>::Multiply(*Xil, false, *Ylj, false, quiet, true, true);
          if (sum.is_null())
            {
              sum = product;
              continue;
            }
          RCP<Matrix> next;
          Xpetra::MatrixMatrix<SC, LO, GO, NO>::TwoMatrixAdd(*product, false, 1.0, *sum, false, 1.0, next,
                                                             quiet);
          next->fillComplete(product->getDomainMap(), product->getRangeMap());
          sum = next;
        }
      return sum;
    }

    /// The blocked product X Y.
    RCP<BlockedCrsMatrix> blocked_product(const BlockedCrsMatrix& X, const BlockedCrsMatrix& Y)
    {
      auto rows    = X.getRangeMapExtractor();
      auto columns = Y.getDomainMapExtractor();
      auto XY      = Teuchos::rcp(new BlockedCrsMatrix(rows, columns, 10));
      const auto X_filled = filled_blocks(X), Y_filled = filled_blocks(Y);
      for (std::size_t i = 0; i < X.Rows(); ++i)
        for (std::size_t j = 0; j < Y.Cols(); ++j)
          if (auto block = sum_of_products(X, X_filled, Y, Y_filled, i, j); !block.is_null())
            XY->setMatrix(i, j, block);
      XY->fillComplete();
      return XY;
    }

    /// "0 2" -> {0, 2}: the block numbers of "tentative blocks".
    std::set<std::size_t> block_numbers(const std::string& text)
    {
      std::set<std::size_t> numbers;
      std::istringstream    items(text);
      std::string           item;
      while (items >> item)
        {
          if (item.find_first_not_of("0123456789") != std::string::npos)
            throw InputError("CoupledSaPFactory: 'tentative blocks' = '" + text +
                             "': expected block numbers (0, 1, ...) separated by spaces");
          numbers.insert(std::stoul(item));
        }
      return numbers;
    }
  } // namespace

  RCP<BlockedCrsMatrix> coupled_smoothed_prolongator(const BlockedCrsMatrix& A, const BlockedCrsMatrix& Pt,
                                                     const CoupledSmoothing& settings)
  {
    const auto n     = A.Rows();
    const auto Pdiag = diagonal_blocks(Pt, n);
    const auto filled = filled_blocks(A);
    const auto Dinv   = inverse_diagonals(A, filled);
    for (const auto i : settings.tentative_rows)
      if (i >= n)
        throw InputError("CoupledSaPFactory: tentative block " + std::to_string(i) + " of a " +
                         std::to_string(n) + " x " + std::to_string(n) + " operator");
    const double lambda =
        largest_eigenvalue(A, filled, Dinv, settings.power_iterations, settings.tentative_rows);
    const double omega  = lambda > 0 ? settings.damping / lambda : 0.0;

    auto rows    = A.getRangeMapExtractor(); // the constructor takes non-const references
    auto columns = Pt.getDomainMapExtractor();
    auto P       = Teuchos::rcp(new BlockedCrsMatrix(rows, columns, 10));
    for (std::size_t i = 0; i < n; ++i)
      {
        if (omega == 0.0 || settings.tentative_rows.count(i))
          {
            P->setMatrix(i, i, Pdiag[i]);
            continue;
          }
        for (std::size_t j = 0; j < n; ++j)
          if (i == j || filled[i][j])
            P->setMatrix(i, j, smoothed_block(*A.getMatrix(i, j), Pdiag[j], *Dinv[i], omega, i == j));
      }
    P->fillComplete();
    return P;
  }

  RCP<BlockedCrsMatrix> blocked_galerkin_product(const BlockedCrsMatrix& R, const BlockedCrsMatrix& A,
                                                 const BlockedCrsMatrix& P)
  {
    const auto P_entries = block_entries(P);
    if (!is_block_diagonal(P_entries) || !is_block_diagonal(block_entries(R)))
      return blocked_product(R, *blocked_product(A, P));
    // Block-diagonal transfers: Ac_ij = R_ii A_ij P_jj, associated per block. A sparse product
    // X Y costs about (entries of X) x (entries per row of Y), and A_ij has far more entries than
    // either intermediate result, so the first product decides: A_ij goes first with the sparser
    // transfer, P_jj from the right (entries per row of P_jj) or R_ii = P_ii^T from the left
    // (entries per column of R_ii, i.e. per row of P_ii). The FSI's fluid rows keep the
    // tentative prolongator (one entry per row), the ALE's is smoothed (about 20 per row in 3D):
    // the fluid's shape-derivative block A_fa, a quarter of the tube's nonzeros, is restricted
    // first instead of prolongated first.
    const auto per_row = [&](std::size_t k) {
      const auto rows = P.getMatrix(k, k)->getRangeMap()->getGlobalNumElements();
      return rows > 0 ? static_cast<double>(P_entries[k][k]) / static_cast<double>(rows) : 0.0;
    };
    auto& quiet         = quiet_stream();
    using MM            = Xpetra::MatrixMatrix<SC, LO, GO, NO>;
    const auto A_filled = filled_blocks(A);
    auto       rows     = R.getRangeMapExtractor();
    auto       columns  = P.getDomainMapExtractor();
    auto       Ac       = Teuchos::rcp(new BlockedCrsMatrix(rows, columns, 10));
    for (std::size_t i = 0; i < A.Rows(); ++i)
      for (std::size_t j = 0; j < A.Cols(); ++j)
        {
          if (!A_filled[i][j] || P_entries[i][i] == 0 || P_entries[j][j] == 0)
            continue;
          const auto Rii = R.getMatrix(i, i), Aij = A.getMatrix(i, j), Pjj = P.getMatrix(j, j);
          if (per_row(i) < per_row(j))
            Ac->setMatrix(i, j,
                          MM::Multiply(*MM::Multiply(*Rii, false, *Aij, false, quiet, true, true), false,
                                       *Pjj, false, quiet, true, true));
          else
            Ac->setMatrix(i, j,
                          MM::Multiply(*Rii, false,
                                       *MM::Multiply(*Aij, false, *Pjj, false, quiet, true, true), false,
                                       quiet, true, true));
        }
    Ac->fillComplete();
    return Ac;
  }

  RCP<BlockedCrsMatrix> blocked_transpose(const BlockedCrsMatrix& P)
  {
    auto rows    = P.getDomainMapExtractor();
    auto columns = P.getRangeMapExtractor();
    auto R       = Teuchos::rcp(new BlockedCrsMatrix(rows, columns, 10));
    const auto filled  = filled_blocks(P);
    for (std::size_t i = 0; i < P.Rows(); ++i)
      for (std::size_t j = 0; j < P.Cols(); ++j)
        if (filled[i][j])
          R->setMatrix(j, i, Utilities::Transpose(*P.getMatrix(i, j), true));
    R->fillComplete();
    return R;
  }

  RCP<const Teuchos::ParameterList> CoupledSaPFactory::GetValidParameterList() const
  {
    auto list = Teuchos::rcp(new Teuchos::ParameterList());
    list->set<RCP<const MueLu::FactoryBase>>("A", Teuchos::null,
                                             "Generating factory of the blocked operator");
    list->set<RCP<const MueLu::FactoryBase>>(
        "P", Teuchos::null, "Generating factory of the block-diagonal tentative prolongator");
    list->set<double>("sa: damping factor", 4.0 / 3.0, "damping of the Jacobi step, over lambda_max(D^-1 A)");
    list->set<int>("sa: eigenvalue estimate num iterations", 10, "power iterations for lambda_max(D^-1 A)");
    list->set<std::string>("tentative blocks", "",
                           "block rows kept tentative (block numbers separated by spaces)");
    return list;
  }

  void CoupledSaPFactory::DeclareInput(MueLu::Level& fine, MueLu::Level& coarse) const
  {
    Input(fine, "A");
    Input(coarse, "P");
  }

  void CoupledSaPFactory::Build(MueLu::Level& fine, MueLu::Level& coarse) const
  {
    BuildP(fine, coarse);
  }

  void CoupledSaPFactory::BuildP(MueLu::Level& fine, MueLu::Level& coarse) const
  {
    MueLu::FactoryMonitor m(*this, "Prolongator smoothing across the blocks", coarse);
    const auto            A  = Teuchos::rcp_dynamic_cast<BlockedCrsMatrix>(Get<RCP<Matrix>>(fine, "A"));
    const auto            Pt = Teuchos::rcp_dynamic_cast<BlockedCrsMatrix>(Get<RCP<Matrix>>(coarse, "P"));
    if (A.is_null() || Pt.is_null())
      throw InputError(
          "CoupledSaPFactory: 'A' and 'P' must be blocked operators (BlockedRAPFactory, BlockedPFactory)");
    const auto&      list = GetParameterList();
    CoupledSmoothing settings;
    settings.damping          = list.get<double>("sa: damping factor");
    settings.power_iterations = list.get<int>("sa: eigenvalue estimate num iterations");
    settings.tentative_rows   = block_numbers(list.get<std::string>("tentative blocks"));
    const auto P              = coupled_smoothed_prolongator(*A, *Pt, settings);
    if (restrictionMode_)
      Set<RCP<Matrix>>(coarse, "R", blocked_transpose(*P));
    else
      Set<RCP<Matrix>>(coarse, "P", P);
  }

  RCP<const Teuchos::ParameterList> BlockedTransposeFactory::GetValidParameterList() const
  {
    auto list = Teuchos::rcp(new Teuchos::ParameterList());
    list->set<RCP<const MueLu::FactoryBase>>("P", Teuchos::null,
                                             "Generating factory of the blocked prolongator");
    return list;
  }

  void BlockedTransposeFactory::DeclareInput(MueLu::Level& /*fine*/, MueLu::Level& coarse) const
  {
    Input(coarse, "P");
  }

  void BlockedTransposeFactory::Build(MueLu::Level& /*fine*/, MueLu::Level& coarse) const
  {
    MueLu::FactoryMonitor m(*this, "Blocked transpose", coarse);
    const auto            P = Teuchos::rcp_dynamic_cast<BlockedCrsMatrix>(Get<RCP<Matrix>>(coarse, "P"));
    if (P.is_null())
      throw InputError("BlockedTransposeFactory: 'P' must be a blocked prolongator");
    Set<RCP<Matrix>>(coarse, "R", blocked_transpose(*P));
  }

  RCP<const Teuchos::ParameterList> BlockedGalerkinFactory::GetValidParameterList() const
  {
    auto list = Teuchos::rcp(new Teuchos::ParameterList());
    list->set<RCP<const MueLu::FactoryBase>>("A", Teuchos::null,
                                             "Generating factory of the fine blocked operator");
    list->set<RCP<const MueLu::FactoryBase>>("P", Teuchos::null,
                                             "Generating factory of the blocked prolongator");
    list->set<RCP<const MueLu::FactoryBase>>("R", Teuchos::null,
                                             "Generating factory of the blocked restriction");
    return list;
  }

  void BlockedGalerkinFactory::DeclareInput(MueLu::Level& fine, MueLu::Level& coarse) const
  {
    Input(fine, "A");
    Input(coarse, "P");
    Input(coarse, "R");
    for (const auto& transfer : transfers_)
      transfer->CallDeclareInput(coarse);
  }

  void BlockedGalerkinFactory::Build(MueLu::Level& fine, MueLu::Level& coarse) const
  {
    MueLu::FactoryMonitor m(*this, "Blocked Galerkin product R A P", coarse);
    const auto            A = Teuchos::rcp_dynamic_cast<BlockedCrsMatrix>(Get<RCP<Matrix>>(fine, "A"));
    const auto            P = Teuchos::rcp_dynamic_cast<BlockedCrsMatrix>(Get<RCP<Matrix>>(coarse, "P"));
    const auto            R = Teuchos::rcp_dynamic_cast<BlockedCrsMatrix>(Get<RCP<Matrix>>(coarse, "R"));
    if (A.is_null() || P.is_null() || R.is_null())
      throw InputError("BlockedGalerkinFactory: 'A', 'P' and 'R' must be blocked operators");
    Set<RCP<Matrix>>(coarse, "A", blocked_galerkin_product(*R, *A, *P));
    for (const auto& transfer : transfers_)
      {
        transfer->CallBuild(coarse);
        coarse.Release(*transfer); // as BlockedRAPFactory does: no product of it left requested
      }
  }
} // namespace multigrid
