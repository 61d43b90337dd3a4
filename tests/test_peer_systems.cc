// Validation against another code's saddle-point systems (tests/data/peer, MueLu's test data):
//  - meshtying2D_small: the peer reports 16 GMRES iterations with its saddle-point AMG at a
//    per-block relative tolerance of 1e-4; ours must need no more.
//  - segregatedAgg: our segregated ("filtered") matrix equals the peer's, and no aggregate of the
//    primal block contains nodes of both bodies.
#include "block_preconditioner.h"
#include "block_system_io.h"
#include "krylov_solver.h"
#include "presets.h"
#include "project_factories.h"

#include <Tpetra_Core.hpp>
#include <Xpetra_IO.hpp>
#include <Xpetra_MapFactory.hpp>
#include <Xpetra_MatrixMatrix.hpp>
#include <Xpetra_MultiVectorFactory.hpp>
#include <gtest/gtest.h>

#include "test_helpers.h"

#include <fstream>
#include <queue>
#include <set>
#include <sstream>

using namespace multigrid;
using test_helpers::comm;
using test_helpers::peer;

namespace
{

  /// Global graph of a Matrix Market file (small files only), 0-based.
  std::vector<std::set<long long>> graph_of(const std::string& file)
  {
    std::ifstream                    in(file);
    std::string                      line;
    long long                        n = 0, m = 0, nnz = 0;
    std::vector<std::set<long long>> g;
    bool                             header = false;
    while (std::getline(in, line))
      {
        if (line.empty() || line[0] == '%')
          continue;
        std::istringstream s(line);
        if (!header)
          {
            s >> n >> m >> nnz;
            g.resize(n);
            header = true;
            continue;
          }
        long long i, j;
        s >> i >> j;
        g[i - 1].insert(j - 1);
      }
    return g;
  }

  /// The body containing `seed`: DOFs reachable from it in the graph.
  std::set<long long> component(const std::vector<std::set<long long>>& g, long long seed)
  {
    std::set<long long>   seen{seed};
    std::queue<long long> todo;
    todo.push(seed);
    while (!todo.empty())
      {
        const long long i = todo.front();
        todo.pop();
        for (long long j : g[i])
          if (seen.insert(j).second)
            todo.push(j);
      }
    return seen;
  }
} // namespace

TEST(PeerSystems, Meshtying2DNeedsNoMoreIterationsThanThePeerCode)
{
  auto                system = read_block_system(peer("meshtying2D_small"), comm());
  auto                preset = load_preset_file(std::string(TEST_DATA_DIR) + "/peer_meshtying2D.xml");
  BlockPreconditioner M(system, preset);
  SolveOptions        options;
  options.tolerance = 1e-4;
  options.per_block = true;
  auto       x      = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(system.full_map(), 1);
  const auto report = solve(system, M, *x, options);
  if (comm()->getRank() == 0)
    std::cout << "meshtying2D_small on " << comm()->getSize() << " rank(s): " << report.iterations
              << " GMRES iterations (peer code: 16 on 1 rank)\n";
  EXPECT_TRUE(report.converged);
  EXPECT_LE(report.iterations, 16);
  EXPECT_EQ(report.preconditioner.levels.size(), 2u);
  for (double r : report.block_relative_residuals)
    EXPECT_LE(r, 1e-4);
}

TEST(PeerSystems, SegregatedMatrixEqualsThePeersFilteredMatrix)
{
  using IO = Xpetra::IO<SC, LO, GO, NO>;
  // The slave body: everything connected to slave interface DOF 42 once the interface couplings
  // are cut, i.e. a connected component of the peer's filtered graph.
  const auto body = component(graph_of(peer("segregatedAgg_filtered_matrix.mm")), 42);
  ASSERT_GT(body.size(), 6u);
  ASSERT_LT(body.size(), 54u);

  auto            map = Xpetra::MapFactory<LO, GO, NO>::Build(Xpetra::UseTpetra, 54, 0, comm());
  auto            A   = IO::Read(peer("segregatedAgg_matrix.mm"), map);
  auto            F   = IO::Read(peer("segregatedAgg_filtered_matrix.mm"), map);
  std::vector<GO> mine;
  for (GO g : map->getNodeElementList())
    if (body.count(g))
      mine.push_back(g);
  auto set = Xpetra::MapFactory<LO, GO, NO>::Build(Xpetra::UseTpetra, body.size(),
                                                   Teuchos::ArrayView<const GO>(mine), 0, comm());
  auto S   = segregated_matrix(*A, *set);
  EXPECT_EQ(S->getGlobalNumEntries(), F->getGlobalNumEntries());
  RCP<Matrix> D;
  auto        out = Teuchos::fancyOStream(Teuchos::rcpFromRef(std::cerr));
  Xpetra::MatrixMatrix<SC, LO, GO, NO>::TwoMatrixAdd(*S, false, 1.0, *F, false, -1.0, D, *out);
  D->fillComplete();
  EXPECT_LT(D->getFrobeniusNorm(), 1e-14 * F->getFrobeniusNorm());
}

TEST(PeerSystems, NoPrimalAggregateContainsNodesOfBothBodies)
{
  auto            system = read_block_system(peer("segregatedAgg"), comm());
  const auto      body   = component(graph_of(peer("segregatedAgg_filtered_matrix.mm")), 42);
  InterfaceInfo   info   = system.interface();
  std::vector<GO> mine;
  for (GO g : system.block(0).map->getNodeElementList())
    if (body.count(g))
      mine.push_back(g);
  info.segregation_dofs = Xpetra::MapFactory<LO, GO, NO>::Build(
      Xpetra::UseTpetra, body.size(), Teuchos::ArrayView<const GO>(mine), 0, comm());
  system.set_interface(info);

  auto                preset = load_preset_file(std::string(TEST_DATA_DIR) + "/peer_meshtying2D.xml");
  BlockPreconditioner M(system, preset);
  auto                P = M.prolongator_block(0, 0);

  // Every coarse DOF (column of P) takes fine rows from one body only.
  const GO         n_coarse = P->getDomainMap()->getMaxAllGlobalIndex() + 1;
  std::vector<int> local(n_coarse, 0), global(n_coarse, 0);
  for (std::size_t i = 0; i < P->getNodeNumRows(); ++i)
    {
      Teuchos::ArrayView<const LO> cols;
      Teuchos::ArrayView<const SC> vals;
      P->getLocalRowView(i, cols, vals);
      const int bit = body.count(P->getRowMap()->getGlobalElement(i)) ? 1 : 2;
      for (LO k = 0; k < cols.size(); ++k)
        if (vals[k] != 0.0)
          local[P->getColMap()->getGlobalElement(cols[k])] |= bit;
    }
  Teuchos::reduceAll(*comm(), Teuchos::REDUCE_BOR, static_cast<int>(n_coarse), local.data(), global.data());
  int both = 0, used = 0;
  for (int f : global)
    {
      both += (f == 3);
      used += (f != 0);
    }
  EXPECT_GT(used, 0);
  EXPECT_EQ(both, 0) << both << " coarse DOFs interpolate from both bodies";
}
