// Every preset is a fixed linear operator (what right-preconditioned GMRES relies on):
// M(x + 2y) = M x + 2 M y to rounding.
#include "block_preconditioner.h"
#include "model_problems.h"
#include "presets.h"

#include <Tpetra_Core.hpp>
#include <Xpetra_MultiVectorFactory.hpp>
#include <gtest/gtest.h>

#include "test_helpers.h"

using namespace multigrid;
using test_helpers::comm;

class PresetLinearity : public ::testing::TestWithParam<std::string>
{
};

TEST_P(PresetLinearity, IsLinear)
{
  auto comm   = Tpetra::getDefaultComm();
  auto system = tied_blocks_2d(comm, {});
  auto preset = load_preset(GetParam());
  if (preset.kind == "saddle-point-amg")
    preset.parameters.sublist("template parameters").set("COARSE_MAX_SIZE", std::string("100"));
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
  EXPECT_LT(diff[0], 1e-10 * ref[0]) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(AllContactPresets, PresetLinearity,
                         ::testing::ValuesIn(test_helpers::contact_presets), test_helpers::PresetName());
