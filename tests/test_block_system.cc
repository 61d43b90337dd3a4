// BlockSystem and its files: round trip of the project's manifest format, the single-matrix
// convention of other codes' exports, and one-line errors for bad input.
#include "block_system_io.h"
#include "model_problems.h"
#include "presets.h"
#include "spatial_order.h"

#include <Tpetra_Core.hpp>
#include <Xpetra_IO.hpp>
#include <Xpetra_ImportFactory.hpp>
#include <Xpetra_MapFactory.hpp>
#include <Xpetra_MatrixUtils.hpp>
#include <Xpetra_MultiVectorFactory.hpp>
#include <gtest/gtest.h>

#include "test_helpers.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numeric>

using namespace multigrid;
using test_helpers::comm;
using test_helpers::error_of;
using test_helpers::peer;
namespace fs = std::filesystem;

namespace
{

  /// A directory every rank agrees on (rank 0's name), removed at the end of the test.
  std::string scratch(const std::string& name)
  {
    return (fs::temp_directory_path() /
            ("block_system_test_" + name + "_np" + std::to_string(comm()->getSize())))
        .string();
  }

  double norm(const MultiVector& v)
  {
    Teuchos::Array<double> n(1);
    v.norm2(n);
    return n[0];
  }

  /// How many values of `distributed` differ from the value stored under the same global id in
  /// `whole` (a copy that holds every id on this rank), beyond rounding in the last digits.
  int mismatches(const MultiVector& distributed, const MultiVector& whole)
  {
    int        bad = 0;
    const auto map = distributed.getMap();
    for (std::size_t j = 0; j < distributed.getNumVectors(); ++j)
      {
        const auto mine = distributed.getData(j), all = whole.getData(j);
        for (std::size_t i = 0; i < map->getNodeNumElements(); ++i)
          {
            const LO k = whole.getMap()->getLocalElement(map->getGlobalElement(i));
            if (k == Teuchos::OrdinalTraits<LO>::invalid() ||
                std::abs(all[k] - mine[i]) > 1e-14 * std::max(1.0, std::abs(mine[i])))
              ++bad;
          }
      }
    return bad;
  }

} // namespace

TEST(BlockSystemIO, ManifestRoundTripKeepsOperatorRhsNullspaceAndInterface)
{
  auto              system = tied_blocks_2d(comm(), {});
  const std::string dir    = scratch("roundtrip");
  write_block_system(system, dir);
  auto again = read_block_system(dir, comm());

  ASSERT_EQ(again.n_blocks(), 2u);
  for (std::size_t k = 0; k < 2; ++k)
    {
      EXPECT_EQ(again.block(k).global_size, system.block(k).global_size);
      EXPECT_EQ(again.block(k).dofs_per_node, system.block(k).dofs_per_node);
    }
  // Same operator: A x agrees for a random x (the distributions may differ).
  using MVF = Xpetra::MultiVectorFactory<SC, LO, GO, NO>;
  auto x    = MVF::Build(system.full_map(), 1);
  x->randomize();
  auto x2       = MVF::Build(again.full_map(), 1);
  auto importer = Xpetra::ImportFactory<LO, GO, NO>::Build(system.full_map(), again.full_map());
  x2->doImport(*x, *importer, Xpetra::INSERT);
  auto y  = MVF::Build(system.full_map(), 1);
  auto y2 = MVF::Build(again.full_map(), 1);
  system.merged_matrix()->apply(*x, *y);
  again.merged_matrix()->apply(*x2, *y2);
  EXPECT_NEAR(norm(*y), norm(*y2), 1e-12 * norm(*y));
  EXPECT_NEAR(norm(*system.rhs()), norm(*again.rhs()), 1e-14 * norm(*system.rhs()));
  ASSERT_FALSE(again.block(0).nullspace.is_null());
  EXPECT_EQ(again.block(0).nullspace->getNumVectors(), 3u);
  ASSERT_TRUE(again.has_interface());
  EXPECT_EQ(again.interface().primal_interface_dofs->getGlobalNumElements(),
            system.interface().primal_interface_dofs->getGlobalNumElements());
  EXPECT_EQ(again.interface().segregation_dofs->getGlobalNumElements(),
            system.interface().segregation_dofs->getGlobalNumElements());
  comm()->barrier();
  if (comm()->getRank() == 0)
    fs::remove_all(dir);
}

// Written on all ranks, read back by every rank alone: each value of the right-hand side, the
// nullspace and the coordinates is found under its own global id. (Written in rank order, as
// Tpetra's dense writer does, the 2-rank right-hand side would be a permutation: rank 0's rows of
// both blocks, then rank 1's.)
TEST(BlockSystemIO, VectorsAreWrittenInGlobalIdOrder)
{
  const auto        system = tied_blocks_2d(comm(), {});
  const std::string dir    = scratch("global_order");
  write_block_system(system, dir);
  const auto alone = read_block_system(dir, comm()->split(comm()->getRank(), 0));
  ASSERT_FALSE(alone.block(0).nullspace.is_null());
  ASSERT_FALSE(alone.block(0).coordinates.is_null());
  EXPECT_EQ(mismatches(*system.rhs(), *alone.rhs()), 0);
  EXPECT_EQ(mismatches(*system.block(0).nullspace, *alone.block(0).nullspace), 0);
  EXPECT_EQ(mismatches(*system.block(0).coordinates, *alone.block(0).coordinates), 0);
  comm()->barrier();
  if (comm()->getRank() == 0)
    fs::remove_all(dir);
}

// The partition written with a system decides the distribution on read: on the writer's number of
// ranks each rank gets exactly the nodes the file names (here an interleaved pattern that
// contiguous chunks of the ids would not give), the multipliers follow their primal node, and
// another number of ranks (each rank alone) gets whole sets. A partition naming a rank the
// writer did not have is a one-line error.
TEST(BlockSystemIO, PartitionFileDecidesTheDistribution)
{
  const auto        system = tied_blocks_2d(comm(), {});
  const std::string dir    = scratch("partition");
  write_block_system(system, dir);
  const int  size = comm()->getSize(), rank = comm()->getRank();
  const auto primal = system.block(0), dual = system.block(1);
  const GO   total           = primal.global_size + dual.global_size;
  auto       write_partition = [&](const std::string& bad_value) {
    if (rank == 0)
      {
        std::ofstream out(dir + "/partition.mm");
        out << "%%MatrixMarket matrix array real general\n" << total << " 1\n";
        for (GO g = 0; g < total; ++g)
          {
            const GO node = g < primal.global_size ? g / primal.dofs_per_node
                                                         : (g - primal.global_size) / dual.dofs_per_node;
            out << (g == 0 && !bad_value.empty() ? bad_value : std::to_string(node % size)) << "\n";
          }
      }
    comm()->barrier();
  };
  write_partition("");
  const auto again = read_block_system(dir, comm());
  const auto gids  = again.block(0).map->getNodeElementList();
  int        wrong = 0;
  for (auto g : gids)
    wrong += (g / primal.dofs_per_node) % size != rank;
  EXPECT_EQ(wrong, 0);
  GO owned = gids.size(), all = 0;
  Teuchos::reduceAll(*comm(), Teuchos::REDUCE_SUM, owned, Teuchos::outArg(all));
  EXPECT_EQ(all, primal.global_size);
  // Every owned multiplier node names an owned primal node, and the operator is the same.
  for (const auto& [d, p] : again.interface().dual_to_primal_node)
    EXPECT_LT(static_cast<std::size_t>(p), gids.size() / primal.dofs_per_node) << "dual node " << d;
  EXPECT_NEAR(again.merged_matrix()->getFrobeniusNorm(), system.merged_matrix()->getFrobeniusNorm(),
              1e-14 * system.merged_matrix()->getFrobeniusNorm());
  const auto alone = read_block_system(dir, comm()->split(rank, 0));
  EXPECT_EQ(static_cast<GO>(alone.block(0).map->getNodeNumElements()), primal.global_size);

  write_partition(std::to_string(size + 5));
  const auto bad = error_of([&] { read_block_system(dir, comm()); });
  EXPECT_NE(bad.find("partition.mm: row 0 has rank '" + std::to_string(size + 5) +
                     "', expected an integer 0.." + std::to_string(size - 1)),
            std::string::npos)
      << bad;
  EXPECT_EQ(bad.find('\n'), std::string::npos) << bad;
  comm()->barrier();
  if (rank == 0)
    fs::remove_all(dir);
}

TEST(BlockSystemIO, ReadsThePeerSingleMatrixConvention)
{
  auto s = read_block_system(peer("meshtying2D_small"), comm());
  EXPECT_EQ(s.block(0).global_size, 78);
  EXPECT_EQ(s.block(1).global_size, 14);
  EXPECT_EQ(s.interface().primal_interface_dofs->getGlobalNumElements(), 14u);
  // Multipliers live on the rank of their slave node.
  long long local = s.interface().dual_to_primal_node.size(), total = 0;
  Teuchos::reduceAll(*comm(), Teuchos::REDUCE_SUM, local, Teuchos::outArg(total));
  EXPECT_EQ(total, 7);
}

TEST(BlockSystemIO, BadInputGivesOneLineErrorsNamingTheFile)
{
  const std::string dir = scratch("bad");
  if (comm()->getRank() == 0)
    {
      fs::remove_all(dir);
      fs::create_directories(dir);
      std::ofstream(dir + "/nan_matrix.mm")
          << "%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 1.0\n2 2 nan\n";
      std::ofstream(dir + "/nan_nullspace1.mm") << "%%MatrixMarket matrix array real general\n1 1\n1.0\n";
      std::ofstream(dir + "/nan_interface_dof_map_MPI1.mm")
          << "%%MatrixMarket matrix array integer general\n2 1\n0\n0\n";
      std::ofstream(dir + "/rect_matrix.mm")
          << "%%MatrixMarket matrix coordinate real general\n3 2 1\n1 1 1.0\n";
      std::ofstream(dir + "/rect_nullspace1.mm")
          << "%%MatrixMarket matrix array real general\n2 1\n1.0\n1.0\n";
      std::ofstream(dir + "/rect_interface_dof_map_MPI1.mm")
          << "%%MatrixMarket matrix array integer general\n2 1\n0\n0\n";
    }
  comm()->barrier();
  ReadOptions one;
  one.dofs_per_node = 1;

  const auto missing = error_of([&] { read_block_system(dir + "/nothing", comm()); });
  EXPECT_NE(missing.find("nothing"), std::string::npos) << missing;
  const auto nan = error_of([&] { read_block_system(dir + "/nan", comm(), one); });
  EXPECT_NE(nan.find("nan_matrix.mm:4"), std::string::npos) << nan;
  EXPECT_NE(nan.find("not a finite number"), std::string::npos) << nan;
  const auto rect = error_of([&] { read_block_system(dir + "/rect", comm(), one); });
  EXPECT_NE(rect.find("3 x 2"), std::string::npos) << rect;
  const auto preset = error_of([&] { load_preset("no-such-preset"); });
  EXPECT_NE(preset.find("unknown preset 'no-such-preset'"), std::string::npos) << preset;
  EXPECT_NE(preset.find("sa-amg(cheapsimple)"), std::string::npos) << preset; // lists the known ones
  for (const auto& e : {missing, nan, rect, preset})
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;

  {
    // The manifest format checks block sizes against the matrix.
    auto              system = tied_blocks_2d(comm(), {});
    const std::string good   = scratch("sizes");
    write_block_system(system, good);
    if (comm()->getRank() == 0)
      {
        std::ifstream in(good + "/manifest.txt");
        std::string   text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        text.replace(text.find("block displacement 956"), 22, "block displacement 958");
        std::ofstream(good + "/manifest.txt") << text;
      }
    comm()->barrier();
    const auto sizes = error_of([&] { read_block_system(good, comm()); });
    EXPECT_NE(sizes.find("blocks add up to"), std::string::npos) << sizes;
    comm()->barrier();
    if (comm()->getRank() == 0)
      fs::remove_all(good);
  }
  comm()->barrier();
  if (comm()->getRank() == 0)
    fs::remove_all(dir);
}

// The project's Matrix Market reader against Tpetra's (through Xpetra::IO) on a file written by
// Xpetra (the coupled-fields model, 3 blocks) and on a hand-written one with entries out of order
// and a duplicate (summed): the same column map in the same order, and the same entries in every
// local row, on any rank count.
TEST(BlockSystemIO, ReaderIsTpetras)
{
  const std::string dir    = scratch("reader");
  auto              system = builtin_system("coupled-fields-2d:1", comm());
  if (comm()->getRank() == 0)
    {
      fs::remove_all(dir);
      fs::create_directories(dir);
      std::ofstream(dir + "/small.mm")
          << "%%MatrixMarket matrix coordinate real general\n% a comment\n4 4 7\n"
             "3 1 -1.5\n1 1 2.0\n4 4 1e-3\n2 3 0.25\n1 1 0.5\n2 2 +3\n3 3 7\n";
    }
  comm()->barrier();
  Xpetra::IO<SC, LO, GO, NO>::Write(dir + "/model.mm", *system.merged_matrix());
  comm()->barrier();
  const RCP<const Map> small_map = Xpetra::MapFactory<LO, GO, NO>::Build(Xpetra::UseTpetra, 4, 0, comm());
  for (const auto& [file, map] : {std::pair{dir + "/model.mm", system.merged_matrix()->getRowMap()},
                                  std::pair{dir + "/small.mm", small_map}})
    {
      const auto own    = read_sparse_matrix_market(file, map);
      const auto tpetra = Xpetra::IO<SC, LO, GO, NO>::Read(file, map);
      const auto ca = own->getColMap()->getNodeElementList(), cb = tpetra->getColMap()->getNodeElementList();
      EXPECT_TRUE(std::equal(ca.begin(), ca.end(), cb.begin(), cb.end())) << file;
      ASSERT_EQ(own->getNodeNumRows(), tpetra->getNodeNumRows());
      int differing_rows = 0;
      for (LO i = 0; i < static_cast<LO>(own->getNodeNumRows()); ++i)
        {
          Teuchos::ArrayView<const LO> ja, jb;
          Teuchos::ArrayView<const SC> va, vb;
          own->getLocalRowView(i, ja, va);
          tpetra->getLocalRowView(i, jb, vb);
          if (!std::equal(ja.begin(), ja.end(), jb.begin(), jb.end()) ||
              !std::equal(va.begin(), va.end(), vb.begin(), vb.end()))
            ++differing_rows;
        }
      EXPECT_EQ(differing_rows, 0) << file;
      EXPECT_EQ(own->getGlobalNumEntries(), file == dir + "/small.mm" ? 6u : tpetra->getGlobalNumEntries());
    }
  comm()->barrier();
  if (comm()->getRank() == 0)
    fs::remove_all(dir);
}

// from_merged gives SplitMatrix the column maps of the blocks' id ranges (Xpetra would gather
// every rank's off-rank columns to find them): the blocks must be the ones Xpetra's own search
// finds, the same column maps in the same order and the same entries, for 2 and 3 blocks.
TEST(BlockSystem, SplitGivesXpetrasBlocks)
{
  for (const std::string spec : {"tied-blocks-2d:1", "coupled-fields-2d:1"})
    {
      auto       system = builtin_system(spec, comm());
      const auto own    = system.blocked_matrix();
      const auto xpetra = Xpetra::MatrixUtils<SC, LO, GO, NO>::SplitMatrix(
          *system.merged_matrix(), system.map_extractor(), system.map_extractor());
      ASSERT_EQ(own->Rows(), system.n_blocks());
      for (std::size_t i = 0; i < own->Rows(); ++i)
        for (std::size_t j = 0; j < own->Cols(); ++j)
          {
            const auto a = own->getMatrix(i, j), b = xpetra->getMatrix(i, j);
            const auto ca = a->getColMap()->getNodeElementList(), cb = b->getColMap()->getNodeElementList();
            EXPECT_TRUE(std::equal(ca.begin(), ca.end(), cb.begin(), cb.end()))
                << spec << " block " << i << j;
            using MVF = Xpetra::MultiVectorFactory<SC, LO, GO, NO>;
            auto x    = MVF::Build(a->getDomainMap(), 1);
            x->randomize();
            auto ya = MVF::Build(a->getRangeMap(), 1), yb = MVF::Build(b->getRangeMap(), 1);
            a->apply(*x, *ya);
            b->apply(*x, *yb);
            yb->update(-1.0, *ya, 1.0);
            EXPECT_LE(norm(*yb), 1e-14 * std::max(1.0, norm(*ya))) << spec << " block " << i << j;
          }
    }
}

TEST(Presets, OverridesAreTypedAndChecked)
{
  auto p = load_preset("cheapsimple(sa-amg)");
  apply_overrides(p, {"sweeps=3", "primal solver/max levels=2", "damping=0.5"});
  EXPECT_EQ(p.parameters.get<int>("sweeps"), 3);
  EXPECT_EQ(p.parameters.sublist("primal solver").get<int>("max levels"), 2);
  const auto bad_type = error_of([&] { apply_overrides(p, {"sweeps=many"}); });
  EXPECT_NE(bad_type.find("does not fit the type"), std::string::npos) << bad_type;
  const auto bad_list = error_of([&] { apply_overrides(p, {"nowhere/x=1"}); });
  EXPECT_NE(bad_list.find("no sublist 'nowhere'"), std::string::npos) << bad_list;
  // Every shipped preset loads, and every saddle-point template is fully substituted.
  for (const auto& name : available_presets())
    {
      const auto preset = load_preset(name);
      if (preset.kind == "saddle-point-amg")
        {
          EXPECT_NO_THROW(expand_template(preset, 2, 2)) << name;
        }
    }
}

TEST(Presets, BasedOnMergesTheBasePresetsEntries)
{
  // fully-coupled-pa-amg(bgs) states only its prolongator; the rest comes from its base.
  const auto pa = load_preset("fully-coupled-pa-amg(bgs)");
  const auto sa = load_preset("fully-coupled-sa-amg(bgs)");
  EXPECT_EQ(pa.kind, "fully-coupled-amg");
  EXPECT_FALSE(pa.parameters.isParameter("based on"));
  EXPECT_EQ(pa.parameters.get<std::string>("prolongator"), "tentative");
  EXPECT_EQ(sa.parameters.get<std::string>("prolongator"), "smoothed");
  EXPECT_EQ(pa.parameters.get<int>("smoother: sweeps"), 3);
  EXPECT_EQ(pa.parameters.get<int>("coarse: max size"), 6500);
  // Sublists are merged entry by entry, not replaced.
  EXPECT_EQ(pa.parameters.sublist("block smoothers").sublist("fluid").get<std::string>("type"), "ILU(0)");
  EXPECT_EQ(pa.parameters.sublist("block prolongators").get<std::string>("fluid"), "tentative");

  // A user's file may be based on a shipped preset, and replace one entry of a sublist.
  // One directory per rank: every rank writes and reads its own files.
  const fs::path dir = scratch("based_on_rank" + std::to_string(comm()->getRank()));
  fs::create_directories(dir);
  auto write = [&](const std::string& file, const std::string& body) {
    std::ofstream((dir / file).string()) << "<ParameterList name=\"x\">\n" << body << "</ParameterList>\n";
    return (dir / file).string();
  };
  const auto user = load_preset_file(write(
      "user.xml", "  <Parameter name=\"based on\" type=\"string\" value=\"fully-coupled-pa-amg(bgs)\"/>\n"
                  "  <ParameterList name=\"block smoothers\"><ParameterList name=\"fluid\">\n"
                  "    <Parameter name=\"type\" type=\"string\" value=\"RILUK\"/>\n"
                  "  </ParameterList></ParameterList>\n"));
  EXPECT_EQ(user.kind, "fully-coupled-amg");
  EXPECT_EQ(user.parameters.get<std::string>("prolongator"), "tentative");
  EXPECT_EQ(user.parameters.sublist("block smoothers").sublist("fluid").get<std::string>("type"), "RILUK");
  EXPECT_EQ(user.parameters.sublist("block smoothers").sublist("ale").get<std::string>("type"), "CHEBYSHEV");

  const auto unknown = error_of([&] {
    load_preset_file(
        write("unknown.xml", "  <Parameter name=\"based on\" type=\"string\" value=\"no-such-preset\"/>\n"));
  });
  EXPECT_NE(unknown.find("unknown.xml: parameter 'based on' is 'no-such-preset', expected a shipped preset"),
            std::string::npos)
      << unknown;
  const auto cycle = error_of([&] {
    load_preset_file(write("cycle.xml",
                           "  <Parameter name=\"name\" type=\"string\" value=\"sa-amg\"/>\n"
                           "  <Parameter name=\"based on\" type=\"string\" value=\"sa-amg\"/>\n"));
  });
  EXPECT_NE(cycle.find("(a cycle)"), std::string::npos) << cycle;
  fs::remove_all(dir);
}

TEST(BlockSystemIO, MortonKeysCutEveryFieldAcrossTheLongestDirection)
{
  // Two fields on a 4 x 1 strip (a 20 x 5 grid and a 40 x 10 grid of nodes, shuffled): sorted by
  // their keys and cut into halves, each field's first half lies in x < 2 and its second in
  // x > 2, the same side in both fields; a 1D field and a field without coordinates pass.
  std::vector<std::vector<double>> xyz(4);
  std::vector<int>                 dims = {2, 2, 1, 0};
  auto                             grid = [](int nx, int ny) {
    std::vector<std::pair<double, double>> p;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        p.emplace_back(4.0 * (i + 0.5) / nx, (j + 0.5) / ny);
    std::reverse(p.begin(), p.end());
    std::rotate(p.begin(), p.begin() + p.size() / 3, p.end());
    std::vector<double> columns(2 * p.size());
    for (std::size_t i = 0; i < p.size(); ++i)
      {
        columns[i]            = p[i].first;
        columns[p.size() + i] = p[i].second;
      }
    return columns;
  };
  xyz[0]          = grid(20, 5);
  xyz[1]          = grid(40, 10);
  xyz[2]          = {3.5, 0.5, 2.5, 1.5};
  const auto keys = morton_keys(xyz, dims);
  ASSERT_EQ(keys.size(), 4u);
  for (int k = 0; k < 2; ++k)
    {
      const std::size_t n = xyz[k].size() / 2;
      ASSERT_EQ(keys[k].size(), n);
      std::vector<std::size_t> order(n);
      std::iota(order.begin(), order.end(), 0);
      std::sort(order.begin(), order.end(), [&](auto a, auto b) { return keys[k][a] < keys[k][b]; });
      for (std::size_t r = 0; r < n; ++r)
        EXPECT_EQ(xyz[k][order[r]] < 2.0, r < n / 2) << "field " << k << " position " << r;
    }
  EXPECT_LT(keys[2][1], keys[2][3]);
  EXPECT_LT(keys[2][3], keys[2][2]);
  EXPECT_LT(keys[2][2], keys[2][0]);
  EXPECT_TRUE(keys[3].empty());
}

TEST(SpatialOrder, SamePositionsMatchesEveryNodeOfAShuffledGridAndNoOther)
{
  // The follower: a 7 x 5 grid in shuffled order, moved by less than the tolerance (also across
  // the rounding cells' boundaries) and with two nodes that have no partner; the leader: the
  // 7 x 6 grid in order.
  const double        h = 0.1, tolerance = 1e-9;
  std::vector<double> leader, follower;
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 7; ++i)
      leader.insert(leader.end(), {i * h, j * h});
  std::vector<int> order(35);
  std::iota(order.begin(), order.end(), 0);
  std::reverse(order.begin() + 3, order.end());
  std::rotate(order.begin(), order.begin() + 11, order.end());
  for (std::size_t k = 0; k < order.size(); ++k)
    {
      const int    n     = order[k];
      const double shift = (k % 3 == 0 ? 0.4 : k % 3 == 1 ? -0.5 : 0.0) * tolerance;
      follower.insert(follower.end(), {(n % 7) * h + shift, (n / 7) * h - shift});
    }
  follower.insert(follower.end(), {0.05, 0.05, 0.0, 0.7});

  const auto match = same_positions(follower, leader, 2, tolerance);
  ASSERT_EQ(match.size(), 37u);
  for (std::size_t k = 0; k < order.size(); ++k)
    EXPECT_EQ(match[k], order[k]) << "follower node " << k;
  EXPECT_EQ(match[35], -1);
  EXPECT_EQ(match[36], -1);
  // 3D, and a position farther than the tolerance is no match
  const auto far = same_positions({0.0, 0.0, 2.5e-9}, {0.0, 0.0, 0.0}, 3, tolerance);
  EXPECT_EQ(far, std::vector<long>{-1});
  EXPECT_EQ(same_positions({0.0, 0.0, 0.9e-9}, {0.0, 0.0, 0.0}, 3, tolerance), std::vector<long>{0});
}
