// Every shipped preset is a fixed linear operator (what right-preconditioned GMRES relies on):
// M(x + 2y) = M x + 2 M y to rounding. Each preset is applied to the kind of system it is made
// for:
//  - the contact presets to the tied-blocks saddle-point system (displacements, multipliers);
//  - the beam/solid presets to a two-field system without multipliers, like beam/solid
//    meshtying: the two bodies of tied-blocks as two fields coupled by a penalty eps B^T B
//    (B: the mortar constraint rows), each field with its rigid-body modes;
//  - the single-field AMG presets to the same penalty system as one field;
//  - the n x n block (FSI) presets to the 3-block coupled-fields model system.
// A last test checks that these lists cover every shipped preset.
#include "block_preconditioner.h"
#include "coupled_fields.h"
#include "model_problems.h"
#include "presets.h"

#include <Tpetra_Core.hpp>
#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_MatrixMatrix.hpp>
#include <Xpetra_MultiVectorFactory.hpp>
#include <gtest/gtest.h>

#include "test_helpers.h"

#include <algorithm>
#include <iostream>

using namespace multigrid;
using test_helpers::comm;

namespace
{
  const std::vector<std::string> beam_solid_presets   = {"schur-sa-amg(spai)", "spai-simple(schur-sa-amg)",
                                                         "block-diagonal-sa-amg"};
  const std::vector<std::string> single_field_presets = {"pa-amg", "sa-amg"};
  /// The n x n block presets (FSI), applied to the 3-block model system.
  const std::vector<std::string> nxn_presets = {"fully-coupled-sa-amg(bgs)", "fully-coupled-pa-amg(bgs)",
                                                "bgs(amg)", "block-jacobi(amg)"};

  /// K + eps B^T B on the primal DOFs of tied-blocks: the bodies tied by a penalty instead of
  /// multipliers (eps of the order of the stiffness entries).
  RCP<Matrix> penalty_operator(const BlockSystem& tied)
  {
    const auto  blocked = tied.blocked_matrix();
    RCP<Matrix> K = blocked->getMatrix(0, 0), B = blocked->getMatrix(1, 0);
    auto        out = Teuchos::fancyOStream(Teuchos::rcpFromRef(std::cerr));
    RCP<Matrix> BtB = Xpetra::MatrixMatrix<SC, LO, GO, NO>::Multiply(*B, true, *B, false, *out);
    RCP<Matrix> A;
    Xpetra::MatrixMatrix<SC, LO, GO, NO>::TwoMatrixAdd(*K, false, 1.0, *BtB, false, 10.0, A, *out);
    A->fillComplete(K->getDomainMap(), K->getRangeMap());
    return A;
  }

  /// The penalty system with the primal DOFs split into `n_fields` fields: 1 (one displacement
  /// field) or 2 (body 1, body 2: the beam/solid-like case). Nullspaces: rigid-body modes.
  BlockSystem penalty_system(int n_fields)
  {
    const auto  tied    = tied_blocks_2d(comm(), {});
    const auto& primal  = tied.block(0);
    const GO    n_body2 = static_cast<GO>(tied.interface().segregation_dofs->getGlobalNumElements());
    const GO    n_body1 = primal.global_size - n_body2; // body 1's DOFs come first
    std::vector<BlockInfo> blocks(n_fields);
    std::vector<std::vector<GO>>     owned(n_fields);
    std::vector<std::vector<double>> xy(n_fields);
    const auto gids = primal.map->getNodeElementList();
    const auto x = primal.coordinates->getData(0), y = primal.coordinates->getData(1);
    for (decltype(gids.size()) i = 0; i < gids.size(); i += 2)
      {
        const int k = (n_fields == 2 && gids[i] >= n_body1) ? 1 : 0;
        owned[k].insert(owned[k].end(), {gids[i], gids[i + 1]});
        xy[k].insert(xy[k].end(), {x[i / 2], y[i / 2]});
      }
    for (int k = 0; k < n_fields; ++k)
      {
        blocks[k].name          = n_fields == 1 ? "displacement" : "body " + std::to_string(k + 1);
        blocks[k].dofs_per_node = 2;
        blocks[k].global_size   = n_fields == 1 ? primal.global_size : (k == 0 ? n_body1 : n_body2);
      }
    auto A   = penalty_operator(tied);
    auto rhs = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(A->getRowMap(), 1);
    rhs->randomize();
    auto system = BlockSystem::from_merged(comm(), blocks, owned, A, rhs);
    for (int k = 0; k < n_fields; ++k)
      system.block(k).nullspace = rigid_body_modes(system.block(k).map, 2, xy[k]);
    system.validate("penalty-tied blocks");
    return system;
  }

  /// ||M(x + 2y) - M x - 2 M y|| / ||M x|| for random x, y.
  double nonlinearity(const BlockSystem& system, Preset preset)
  {
    if (preset.kind == "saddle-point-amg")
      preset.parameters.sublist("template parameters").set("COARSE_MAX_SIZE", std::string("100"));
    if (preset.kind == "fully-coupled-amg")
      preset.parameters.set("coarse: max size", 300);
    BlockPreconditioner M(system, preset);
    using MVF = Xpetra::MultiVectorFactory<SC, LO, GO, NO>;
    auto x = MVF::Build(system.full_map(), 1), y = MVF::Build(system.full_map(), 1);
    x->randomize();
    y->randomize();
    auto xy = MVF::Build(system.full_map(), 1);
    xy->update(1.0, *x, 2.0, *y, 0.0);
    auto Mx = MVF::Build(system.full_map(), 1), My = MVF::Build(system.full_map(), 1),
         Mxy = MVF::Build(system.full_map(), 1);
    M.op()->apply(*x, *Mx);
    M.op()->apply(*y, *My);
    M.op()->apply(*xy, *Mxy);
    Mxy->update(-1.0, *Mx, -2.0, *My, 1.0);
    Teuchos::Array<double> diff(1), ref(1);
    Mxy->norm2(diff);
    Mx->norm2(ref);
    return diff[0] / ref[0];
  }
} // namespace

class PresetLinearity : public ::testing::TestWithParam<std::string>
{
};

TEST_P(PresetLinearity, IsLinear)
{
  const std::string& name = GetParam();
  const auto         in   = [&](const std::vector<std::string>& list) {
    return std::find(list.begin(), list.end(), name) != list.end();
  };
  const BlockSystem system = in(beam_solid_presets)   ? penalty_system(2)
                             : in(single_field_presets) ? penalty_system(1)
                             : in(nxn_presets)          ? coupled_fields_2d(comm(), {1, false})
                                                        : tied_blocks_2d(comm(), {});
  EXPECT_LT(nonlinearity(system, load_preset(name)), 1e-10) << name;
}

INSTANTIATE_TEST_SUITE_P(AllContactPresets, PresetLinearity,
                         ::testing::ValuesIn(test_helpers::contact_presets), test_helpers::PresetName());
INSTANTIATE_TEST_SUITE_P(SingleFieldPresets, PresetLinearity, ::testing::ValuesIn(single_field_presets),
                         test_helpers::PresetName());
INSTANTIATE_TEST_SUITE_P(BeamSolidPresets, PresetLinearity, ::testing::ValuesIn(beam_solid_presets),
                         test_helpers::PresetName());
INSTANTIATE_TEST_SUITE_P(NxnPresets, PresetLinearity, ::testing::ValuesIn(nxn_presets), test_helpers::PresetName());

TEST(PresetLinearity, CoversEveryShippedPreset)
{
  std::vector<std::string> covered = test_helpers::contact_presets;
  covered.insert(covered.end(), beam_solid_presets.begin(), beam_solid_presets.end());
  covered.insert(covered.end(), single_field_presets.begin(), single_field_presets.end());
  covered.insert(covered.end(), nxn_presets.begin(), nxn_presets.end());
  for (const auto& name : available_presets())
    EXPECT_NE(std::find(covered.begin(), covered.end(), name), covered.end())
        << "preset '" << name << "' is shipped but not in the linearity test's lists";
}
