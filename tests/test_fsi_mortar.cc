// The dual mortar weights of non-matching FSI interfaces (fsi/interface_nodes.h,
// interface_mortar.cc) on hand-made interface faces: a slave side (the fluid, outward normal
// down) and a master side (the structure, outward normal up) on the same line (2D) or plane
// (3D). P = D^-1 M must reproduce linear fields exactly (dual basis: int Phi_j x = D_jj x_j on a
// straight or flat interface), have rows summing to 1, be the node map on matching faces, and
// refuse surfaces that do not overlap.
#include "fsi/interface_nodes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
  using physics::GlobalIndex;
  using physics::fsi::InterfaceFaces;
  using physics::fsi::InterfacePartners;

  /// Segments along y = 0 through the breakpoints xs (2 DOFs per node: 2k, 2k + 1, plus `offset`),
  /// outward normal -y (slave) or +y (master).
  InterfaceFaces<2> line(const std::vector<double>& xs, bool slave, GlobalIndex offset)
  {
    InterfaceFaces<2> F;
    F.nodes.components = 2;
    for (std::size_t k = 0; k < xs.size(); ++k)
      {
        F.nodes.positions.emplace_back(xs[k], 0.0);
        F.nodes.dofs.push_back(offset + 2 * k);
        F.nodes.dofs.push_back(offset + 2 * k + 1);
      }
    for (unsigned k = 0; k + 1 < xs.size(); ++k)
      F.faces.push_back(slave ? std::vector<unsigned>{k, k + 1} : std::vector<unsigned>{k + 1, k});
    return F;
  }

  /// Quadrilaterals on z = 0 over the breakpoints xs x ys (3 DOFs per node), outward normal -z
  /// (slave) or +z (master): counterclockwise seen from outside.
  InterfaceFaces<3> plane(const std::vector<double>& xs, const std::vector<double>& ys, bool slave,
                          GlobalIndex offset)
  {
    InterfaceFaces<3> F;
    F.nodes.components = 3;
    const auto node = [&](std::size_t i, std::size_t j) { return static_cast<unsigned>(j * xs.size() + i); };
    for (std::size_t j = 0; j < ys.size(); ++j)
      for (std::size_t i = 0; i < xs.size(); ++i)
        {
          F.nodes.positions.emplace_back(xs[i], ys[j], 0.0);
          for (unsigned c = 0; c < 3; ++c)
            F.nodes.dofs.push_back(offset + 3 * node(i, j) + c);
        }
    for (std::size_t j = 0; j + 1 < ys.size(); ++j)
      for (std::size_t i = 0; i + 1 < xs.size(); ++i)
        {
          std::vector<unsigned> up = {node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)};
          F.faces.push_back(slave ? std::vector<unsigned>{up[0], up[3], up[2], up[1]} : up);
        }
    return F;
  }

  /// Applies P to the master field f(x) (per component c: f(x) + c) and returns the largest
  /// deviation from f at the slave nodes, and the largest |row sum - 1|.
  template <int dim, class Field>
  std::pair<double, double> reproduction_error(const InterfaceFaces<dim>& slave,
                                               const InterfaceFaces<dim>& master, const InterfacePartners& P,
                                               const Field& f)
  {
    std::map<GlobalIndex, double> master_value;
    for (std::size_t k = 0; k < master.nodes.positions.size(); ++k)
      for (unsigned c = 0; c < master.nodes.components; ++c)
        master_value[master.nodes.dofs[k * master.nodes.components + c]] = f(master.nodes.positions[k]) + c;
    double worst = 0, worst_sum = 0;
    for (std::size_t k = 0; k < slave.nodes.positions.size(); ++k)
      for (unsigned c = 0; c < slave.nodes.components; ++c)
        {
          const auto& row   = P.at(slave.nodes.dofs[k * slave.nodes.components + c]);
          double      value = 0, sum = 0;
          for (const auto& [s, w] : row)
            {
              value += w * master_value.at(s);
              sum += w;
            }
          worst     = std::max(worst, std::abs(value - f(slave.nodes.positions[k]) - c));
          worst_sum = std::max(worst_sum, std::abs(sum - 1));
        }
    return {worst, worst_sum};
  }
} // namespace

TEST(FsiMortar, NonMatchingLinesReproduceLinearFields)
{
  const auto slave  = line({0, 0.3, 0.55, 1.0}, true, 0);
  const auto master = line({0, 0.12, 0.2, 0.47, 0.61, 0.8, 1.0}, false, 100);
  const auto P      = physics::fsi::dual_mortar_partners(slave, master, 2, "test");
  const auto [error, sum] =
      reproduction_error(slave, master, P, [](const dealii::Point<2>& x) { return 3 * x[0] - 0.7; });
  EXPECT_LT(error, 1e-12);
  EXPECT_LT(sum, 1e-12);
  // Fine slave, coarse master: the same.
  const auto fine   = line({0, 0.12, 0.2, 0.47, 0.61, 0.8, 1.0}, true, 0);
  const auto coarse = line({0, 0.3, 0.55, 1.0}, false, 100);
  const auto P2     = physics::fsi::dual_mortar_partners(fine, coarse, 2, "test");
  EXPECT_LT(
      reproduction_error(fine, coarse, P2, [](const dealii::Point<2>& x) { return -2 * x[0] + 5; }).first,
      1e-12);
}

TEST(FsiMortar, MatchingLinesGiveTheNodeMap)
{
  const std::vector<double> xs = {0, 0.25, 0.4, 1.0};
  const auto P = physics::fsi::dual_mortar_partners(line(xs, true, 0), line(xs, false, 100), 2, "test");
  for (GlobalIndex k = 0; k < xs.size(); ++k)
    for (GlobalIndex c = 0; c < 2; ++c)
      {
        const auto& row = P.at(2 * k + c);
        ASSERT_EQ(row.size(), 1u) << "slave node " << k;
        EXPECT_EQ(row[0].first, 100 + 2 * k + c);
        EXPECT_NEAR(row[0].second, 1.0, 1e-13);
      }
}

TEST(FsiMortar, NonMatchingPlanesReproduceLinearFields)
{
  const auto slave        = plane({0, 0.4, 1.0}, {0, 0.5, 1.0}, true, 0);
  const auto master       = plane({0, 0.2, 0.45, 0.7, 1.0}, {0, 0.3, 0.65, 1.0}, false, 1000);
  const auto P            = physics::fsi::dual_mortar_partners(slave, master, 3, "test");
  const auto [error, sum] = reproduction_error(
      slave, master, P, [](const dealii::Point<3>& x) { return 2 * x[0] - 3 * x[1] + 0.5; });
  EXPECT_LT(error, 1e-11);
  EXPECT_LT(sum, 1e-11);
}

TEST(FsiMortar, SurfacesThatDoNotOverlapAreRefused)
{
  const auto slave = line({0, 0.5, 1.0}, true, 0);
  // The master covers only half of the slave's interface.
  try
    {
      physics::fsi::dual_mortar_partners(slave, line({0.5, 0.8, 1.5}, false, 100), 2, "Mesh file 'x.geo'");
      FAIL() << "no error";
    }
  catch (const std::invalid_argument& e)
    {
      const std::string what = e.what();
      EXPECT_NE(
          what.find("Mesh file 'x.geo': the fluid interface node at (0, 0) does not face the structure"),
          std::string::npos)
          << what;
    }
}
