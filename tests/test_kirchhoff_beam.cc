// Torsion-free Kirchhoff-Love beam (physics/beam_solid/kirchhoff_beam.h) alone: AD derivatives
// against finite differences, invariance under rigid-body motions, the cantilever under a small
// tip load (P L^3 / (3 EI)), and the large-rotation end-moment case (a circular arc of radius
// EI / M) converging under refinement, with Newton converging quadratically.
#include "beam_solid/kirchhoff_beam.h"

#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/lac/vector.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

using namespace physics::beam_solid;
using dealii::Point;
using dealii::Tensor;

namespace
{
  const BeamSection section{10.0 * 7.854e-5, 10.0 * 4.909e-10}; // E_B = 10, fibre radius 0.005

  std::array<double, 12> element_unknowns(const BeamMesh& mesh, std::size_t e, const std::vector<double>& d)
  {
    std::array<double, 12> x{};
    for (int a = 0; a < 2; ++a)
      for (int k = 0; k < 6; ++k)
        x[6 * a + k] = d[6 * mesh.elements[e][a] + k];
    return x;
  }

  /// Static Newton solve of a cantilever clamped at node 0 (position and tangent), with a dead
  /// tip force and/or a planar tip moment, in `steps` load steps. Returns the Newton residual
  /// history of the last load step.
  std::vector<double> solve_cantilever(const BeamMesh& mesh, const Tensor<1, 3>& tip_force, double tip_moment,
                                       int steps, std::vector<double>& d)
  {
    const unsigned int n = mesh.n_dofs(), tip = static_cast<unsigned int>(mesh.nodes.size()) - 1;
    d.assign(n, 0.0);
    std::vector<double> history;
    for (int step = 1; step <= steps; ++step)
      {
        const double factor = static_cast<double>(step) / steps;
        history.clear();
        for (int it = 0; it < 30; ++it)
          {
            dealii::LAPACKFullMatrix<double> K(n, n);
            dealii::Vector<double>           r(n);
            for (std::size_t e = 0; e < mesh.elements.size(); ++e)
              {
                const auto ed = element_derivatives(mesh, e, section, element_unknowns(mesh, e, d));
                for (int i = 0; i < 12; ++i)
                  {
                    const unsigned int gi = 6 * mesh.elements[e][i / 6] + i % 6;
                    r(gi) += ed.gradient[i];
                    for (int j = 0; j < 12; ++j)
                      K(gi, 6 * mesh.elements[e][j / 6] + j % 6) += ed.hessian[12 * i + j];
                  }
              }
            for (int c = 0; c < 3; ++c)
              r(6 * tip + c) -= factor * tip_force[c];
            if (tip_moment != 0)
              {
                const auto m = planar_end_moment(mesh.tangents[tip], {{d[6 * tip + 3], d[6 * tip + 4], d[6 * tip + 5]}},
                                                 factor * tip_moment);
                for (int i = 0; i < 3; ++i)
                  {
                    r(6 * tip + 3 + i) += m.gradient[i];
                    for (int j = 0; j < 3; ++j)
                      K(6 * tip + 3 + i, 6 * tip + 3 + j) += m.hessian[3 * i + j];
                  }
              }
            for (unsigned int k = 0; k < 6; ++k) // clamped root
              {
                for (unsigned int j = 0; j < n; ++j)
                  K(k, j) = K(j, k) = 0;
                K(k, k) = 1;
                r(k)    = 0;
              }
            history.push_back(r.l2_norm());
            // relative 1e-10, above the round-off floor of the axial stiffness
            if (it > 0 &&
                history.back() < 1e-10 * *std::max_element(history.begin(), history.end()) + 1e-13 * section.EA)
              break;
            K.compute_lu_factorization();
            r *= -1.0;
            K.solve(r);
            for (unsigned int k = 0; k < n; ++k)
              d[k] += r(k);
          }
      }
    return history;
  }
} // namespace

TEST(KirchhoffBeam, DerivativesMatchFiniteDifferences)
{
  BeamMesh mesh;
  add_straight_fibre(mesh, Point<3>(0.1, 0.2, 0.3), Point<3>(0.5, 0.1, 0.6), 1);
  mesh.check_and_set_tangents("test");
  std::array<double, 12> d{{0.01, -0.02, 0.03, 0.1, -0.05, 0.08, -0.02, 0.04, 0.01, -0.06, 0.12, 0.03}};
  const auto             ed = element_derivatives(mesh, 0, section, d);
  const double           h  = 1e-6;
  for (int i = 0; i < 12; ++i)
    {
      auto plus = d, minus = d;
      plus[i] += h;
      minus[i] -= h;
      const auto   ep = element_derivatives(mesh, 0, section, plus), em = element_derivatives(mesh, 0, section, minus);
      const double scale = std::abs(ed.gradient[i]) + 1e-6;
      EXPECT_NEAR((ep.energy - em.energy) / (2 * h), ed.gradient[i], 1e-6 * scale) << "gradient " << i;
      for (int j = 0; j < 12; ++j)
        EXPECT_NEAR((ep.gradient[j] - em.gradient[j]) / (2 * h), ed.hessian[12 * j + i],
                    1e-5 * (std::abs(ed.hessian[12 * j + i]) + section.EA))
            << "hessian " << j << "," << i;
    }
}

TEST(KirchhoffBeam, RigidBodyMotionsStoreNoEnergy)
{
  BeamMesh mesh;
  add_straight_fibre(mesh, Point<3>(0, 0, 0), Point<3>(0.3, 0.4, 0.0), 1);
  mesh.check_and_set_tangents("test");
  // A finite rotation about the axis (1, 2, 2)/3 by 0.7 rad plus a translation.
  const Tensor<1, 3> axis({1.0 / 3, 2.0 / 3, 2.0 / 3});
  const double       angle = 0.7;
  auto               rotate = [&](const Tensor<1, 3>& v) {
    return v * std::cos(angle) + cross_product_3d(axis, v) * std::sin(angle) + axis * (axis * v) * (1 - std::cos(angle));
  };
  const Tensor<1, 3>     shift({0.2, -0.1, 0.5});
  std::array<double, 12> d{};
  for (int a = 0; a < 2; ++a)
    {
      const Tensor<1, 3> X(mesh.nodes[a]), T = mesh.tangents[a];
      const Tensor<1, 3> x = rotate(X) + shift, t = rotate(T);
      for (int c = 0; c < 3; ++c)
        {
          d[6 * a + c]     = x[c] - X[c];
          d[6 * a + 3 + c] = t[c] - T[c];
        }
    }
  const auto ed = element_derivatives(mesh, 0, section, d);
  EXPECT_NEAR(ed.energy, 0.0, 1e-14 * section.EA);
  for (int i = 0; i < 12; ++i)
    EXPECT_NEAR(ed.gradient[i], 0.0, 1e-10 * section.EA) << i;
}

TEST(KirchhoffBeam, CantileverUnderSmallTipLoad)
{
  // Deflection w = P L^3 / (3 EI); Hermite elements are nodally exact for the linear theory, so
  // every mesh matches to the geometric nonlinearity (w / L = 1e-3 here).
  const double L = 1.0, P = 3e-3 * section.EI / (L * L * L);
  for (const int n : {1, 2, 4, 8})
    {
      BeamMesh mesh;
      add_straight_fibre(mesh, Point<3>(0, 0, 0), Point<3>(L, 0, 0), n);
      mesh.check_and_set_tangents("test");
      std::vector<double> d;
      const auto          history = solve_cantilever(mesh, Tensor<1, 3>({0.0, -P, 0.0}), 0.0, 1, d);
      const double        w = -d[6 * n + 1], exact = P * L * L * L / (3 * section.EI);
      EXPECT_LT(std::abs(w - exact) / exact, 1e-2) << n << " elements";
      EXPECT_LT(history.size(), 6u);
      std::cout << n << " elements: tip deflection " << w << " (linear theory " << exact << "), Newton "
                << history.size() - 1 << " steps\n";
    }
}

TEST(KirchhoffBeam, EndMomentBendsIntoACircle)
{
  // M = (pi/2) EI / L: a quarter circle of radius R = EI / M = 2 L / pi, tip at (R, R).
  const double L = 1.0, M = M_PI / 2 * section.EI / L, R = section.EI / M;
  double       previous = 1e300;
  for (const int n : {2, 4, 8, 16})
    {
      BeamMesh mesh;
      add_straight_fibre(mesh, Point<3>(0, 0, 0), Point<3>(L, 0, 0), n);
      mesh.check_and_set_tangents("test");
      std::vector<double> d;
      const auto          history = solve_cantilever(mesh, Tensor<1, 3>(), M, 4, d);
      const double        x = L + d[6 * n], y = d[6 * n + 1];
      const double        error = std::hypot(x - R, y - R) / L;
      std::cout << n << " elements: tip (" << x << ", " << y << "), exact (" << R << ", " << R << "), error " << error
                << ", Newton residuals";
      for (double h : history)
        std::cout << " " << h;
      std::cout << "\n";
      EXPECT_LT(error, previous) << n << " elements";
      previous = error;
      // Newton converges in a few steps per load step
      EXPECT_LE(history.size(), 8u);
      EXPECT_LT(history.back(), 1e-10 * *std::max_element(history.begin(), history.end()) + 1e-13 * section.EA);
    }
  EXPECT_LT(previous, 1e-3);
}

TEST(BeamMesh, OrientsFibresAndRejectsBranchesKinksAndLooseNodes)
{
  auto message = [](BeamMesh mesh) {
    try
      {
        mesh.check_and_set_tangents("fibres.msh");
      }
    catch (const std::invalid_argument& e)
      {
        return std::string(e.what());
      }
    return std::string("no error");
  };
  // A straight fibre whose elements gmsh listed in both directions: reoriented head to tail,
  // one tangent per node shared by both elements.
  BeamMesh backwards;
  add_straight_fibre(backwards, Point<3>(0, 0, 0), Point<3>(0.3, 0.6, 0.9), 4);
  std::swap(backwards.elements[1][0], backwards.elements[1][1]);
  std::swap(backwards.elements[2][0], backwards.elements[2][1]);
  EXPECT_EQ(message(backwards), "no error");
  backwards.check_and_set_tangents("test");
  const Tensor<1, 3> along = (backwards.nodes[4] - backwards.nodes[0]) / backwards.nodes[4].distance(backwards.nodes[0]);
  for (std::size_t e = 0; e < 4; ++e)
    EXPECT_EQ(backwards.elements[e][0] + 1, backwards.elements[e][1]);
  for (const auto& t : backwards.tangents)
    EXPECT_LT((t - along).norm(), 1e-14);

  BeamMesh corner; // a right angle: a curved reference, which the torsion-free model excludes
  add_straight_fibre(corner, Point<3>(0, 0, 0), Point<3>(1, 0, 0), 1);
  corner.nodes.emplace_back(1.0, 1.0, 0.0);
  corner.elements.push_back({{1, 2}});
  EXPECT_EQ(message(corner), "fibres.msh: beam kinks by 90 degrees at node 1 (1 0 0) (the torsion-free beam needs straight "
                             "reference fibres: elements collinear where they meet; curved fibres need a rod with "
                             "torsional stiffness, not implemented)");
  BeamMesh branch;
  add_straight_fibre(branch, Point<3>(0, 0, 0), Point<3>(1, 0, 0), 2);
  branch.nodes.emplace_back(0.5, 1.0, 0.0);
  branch.elements.push_back({{1, 3}});
  EXPECT_EQ(message(branch), "fibres.msh: beam branches at node 1 (0.5 0 0): 3 elements meet there (every fibre must be a "
                             "simple line)");
  BeamMesh loose;
  add_straight_fibre(loose, Point<3>(0, 0, 0), Point<3>(1, 0, 0), 1);
  loose.nodes.emplace_back(2.0, 2.0, 0.0);
  EXPECT_EQ(message(loose), "fibres.msh: beam node 2 (2 2 0) belongs to no element");
}
