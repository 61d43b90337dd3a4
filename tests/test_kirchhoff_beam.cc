// Torsion-free Kirchhoff-Love beam (physics/beam_solid/kirchhoff_beam.h) alone: AD derivatives
// against finite differences, invariance under rigid-body motions, the cantilever under a small
// tip load (P L^3 / (3 EI)), and the large-rotation end-moment case (a circular arc of radius
// EI / M) converging under refinement, with Newton converging quadratically. Curved reference
// beams (polylines along circles): exact nodal tangents, a stress-free and objective reference,
// the quarter-circle cantilever against Castigliano's solution, and an end moment that closes a
// quarter circle into a full one; polylines with branches or corners are input errors.
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

  /// Polyline on the circle of radius R about the origin in the x-y plane, nodes at the angles
  /// `angles` (counter-clockwise).
  BeamMesh arc(double R, const std::vector<double>& angles)
  {
    BeamMesh mesh;
    for (const double a : angles)
      mesh.nodes.emplace_back(R * std::cos(a), R * std::sin(a), 0.0);
    for (std::size_t i = 0; i + 1 < angles.size(); ++i)
      mesh.elements.push_back({{static_cast<int>(i), static_cast<int>(i + 1)}});
    return mesh;
  }

  std::vector<double> uniform_angles(double from, double to, int n)
  {
    std::vector<double> a;
    for (int i = 0; i <= n; ++i)
      a.push_back(from + (to - from) * i / n);
    return a;
  }

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
  mesh.set_reference_geometry("test");
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
  mesh.set_reference_geometry("test");
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
      mesh.set_reference_geometry("test");
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
      mesh.set_reference_geometry("test");
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

TEST(CurvedBeam, PolylineTangentsConvergeAtFourthOrder)
{
  // Helix of radius R and pitch c (per radian) with unequally spaced nodes and every other
  // element listed backwards (gmsh may do that): the elements are reoriented, and the nodal
  // tangents, the Hermite reference curve (distance from the helix axis) and the arc length
  // approach the helix's at fourth order.
  const double        R = 0.7, c = 0.2, turn = 2 * M_PI, exact_length = turn * std::hypot(R, c);
  std::vector<double> tangent_error, radial, length;
  for (const int n : {16, 32, 64, 128})
    {
      BeamMesh            mesh;
      std::vector<double> phi;
      for (int i = 0; i <= n; ++i)
        {
          const double u = static_cast<double>(i) / n;
          phi.push_back(turn * (u + 0.15 * std::sin(M_PI * u) * u)); // graded towards the end
          mesh.nodes.emplace_back(R * std::cos(phi.back()), R * std::sin(phi.back()), c * phi.back());
          if (i > 0)
            mesh.elements.push_back(i % 2 ? std::array<int, 2>{{i - 1, i}} : std::array<int, 2>{{i, i - 1}});
        }
      mesh.set_reference_geometry("test");
      double worst = 0, deviation = 0, total = 0;
      for (int i = 0; i <= n; ++i)
        {
          Tensor<1, 3> exact({-R * std::sin(phi[i]), R * std::cos(phi[i]), c});
          worst = std::max(worst, (mesh.tangents[i] - exact / exact.norm()).norm());
        }
      for (int e = 0; e < n; ++e)
        {
          EXPECT_EQ(mesh.elements[e][0] + 1, mesh.elements[e][1]);
          total += mesh.element_length(e);
          for (int k = 0; k <= 20; ++k)
            {
              const Point<3> x = mesh.reference_position(e, -1 + 0.1 * k);
              deviation        = std::max(deviation, std::abs(std::hypot(x[0], x[1]) - R) / R);
            }
        }
      tangent_error.push_back(worst);
      radial.push_back(deviation);
      length.push_back(std::abs(total - exact_length) / exact_length);
      std::cout << n << " elements: tangent error " << worst << ", radial deviation " << deviation
                << ", arc length error " << length.back() << "\n";
    }
  for (std::size_t k = 1; k < radial.size(); ++k)
    {
      EXPECT_GT(tangent_error[k - 1] / tangent_error[k], 12.0) << k;
      EXPECT_GT(radial[k - 1] / radial[k], 12.0) << k;
      EXPECT_GT(length[k - 1] / length[k], 12.0) << k;
    }
  // Three nodes: at the middle one the tangent of the circle through them, exact on circles.
  BeamMesh three = arc(R, {0.1, 0.3, 0.75});
  three.set_reference_geometry("test");
  EXPECT_LT((three.tangents[1] - Tensor<1, 3>({-std::sin(0.3), std::cos(0.3), 0.0})).norm(), 1e-13);
}

TEST(CurvedBeam, ReferenceIsStressFreeAndObjective)
{
  // Zero displacement: no energy and no force; a finite rotation plus translation of the
  // curved element: the same (the energy depends on stretch and |kappa| only).
  BeamMesh mesh = arc(0.5, {0.2, 0.6, 1.1});
  mesh.nodes[2][2] += 0.1; // out of plane: a helix-like, non-planar reference
  mesh.set_reference_geometry("test");
  const Tensor<1, 3> axis({1.0 / 3, 2.0 / 3, 2.0 / 3}), shift({0.2, -0.1, 0.5});
  const double       angle = 1.3;
  auto               rotate = [&](const Tensor<1, 3>& v) {
    return v * std::cos(angle) + cross_product_3d(axis, v) * std::sin(angle) + axis * (axis * v) * (1 - std::cos(angle));
  };
  for (std::size_t e = 0; e < 2; ++e)
    {
      const auto at_rest = element_derivatives(mesh, e, section, {});
      std::array<double, 12> d{};
      for (int a = 0; a < 2; ++a)
        {
          const int          n = mesh.elements[e][a];
          const Tensor<1, 3> X(mesh.nodes[n]), T = mesh.tangents[n];
          const Tensor<1, 3> x = rotate(X) + shift, t = rotate(T);
          for (int c = 0; c < 3; ++c)
            {
              d[6 * a + c]     = x[c] - X[c];
              d[6 * a + 3 + c] = t[c] - T[c];
            }
        }
      const auto moved = element_derivatives(mesh, e, section, d);
      EXPECT_NEAR(at_rest.energy, 0.0, 1e-16 * section.EA);
      EXPECT_NEAR(moved.energy, 0.0, 1e-14 * section.EA);
      for (int i = 0; i < 12; ++i)
        {
          EXPECT_NEAR(at_rest.gradient[i], 0.0, 1e-12 * section.EA) << i;
          EXPECT_NEAR(moved.gradient[i], 0.0, 1e-10 * section.EA) << i;
        }
      // ... while bending it stores energy (kappa_0 enters: the reference is not straight).
      d.fill(0.0);
      d[9] = 0.05;
      EXPECT_GT(element_derivatives(mesh, e, section, d).energy, 1e-6 * section.EI);
    }
}

TEST(CurvedBeam, DerivativesMatchFiniteDifferences)
{
  BeamMesh mesh = arc(0.4, {0.0, 0.5, 0.9});
  mesh.set_reference_geometry("test");
  std::array<double, 12> d{{0.01, -0.02, 0.03, 0.1, -0.05, 0.08, -0.02, 0.04, 0.01, -0.06, 0.12, 0.03}};
  const auto             ed = element_derivatives(mesh, 1, section, d);
  const double           h  = 1e-6;
  for (int i = 0; i < 12; ++i)
    {
      auto plus = d, minus = d;
      plus[i] += h;
      minus[i] -= h;
      const auto ep = element_derivatives(mesh, 1, section, plus), em = element_derivatives(mesh, 1, section, minus);
      EXPECT_NEAR((ep.energy - em.energy) / (2 * h), ed.gradient[i], 1e-6 * (std::abs(ed.gradient[i]) + 1e-6));
      for (int j = 0; j < 12; ++j)
        EXPECT_NEAR((ep.gradient[j] - em.gradient[j]) / (2 * h), ed.hessian[12 * j + i],
                    1e-5 * (std::abs(ed.hessian[12 * j + i]) + section.EA))
            << "hessian " << j << "," << i;
    }
}

TEST(CurvedBeam, QuarterCircleCantileverMatchesCastigliano)
{
  // Quarter circle of radius R clamped at (R, 0) (tangent +y), free at (0, R), dead tip load
  // (0, -P). Castigliano with M = P R cos(theta), N = -P cos(theta):
  //   u_x = -P R^3 / (2 EI) + P R / (2 EA),   u_y = -pi P R^3 / (4 EI) - pi P R / (4 EA).
  const double R = 1.0, P = 1e-4 * section.EI / (R * R * R);
  const double ux = -P * R * R * R / (2 * section.EI) + P * R / (2 * section.EA);
  const double uy = -M_PI * P * R * R * R / (4 * section.EI) - M_PI * P * R / (4 * section.EA);
  double       previous = 1e300;
  for (const int n : {2, 4, 8, 16})
    {
      BeamMesh mesh = arc(R, uniform_angles(0, M_PI / 2, n));
      mesh.set_reference_geometry("test");
      std::vector<double> d;
      const auto          history = solve_cantilever(mesh, Tensor<1, 3>({0.0, -P, 0.0}), 0.0, 1, d);
      const double        error   = std::hypot(d[6 * n] - ux, d[6 * n + 1] - uy) / std::hypot(ux, uy);
      std::cout << n << " elements: tip displacement (" << d[6 * n] << ", " << d[6 * n + 1] << "), Castigliano ("
                << ux << ", " << uy << "), relative error " << error << ", Newton " << history.size() - 1
                << " steps\n";
      EXPECT_LT(error, previous) << n << " elements";
      EXPECT_LT(history.size(), 6u);
      previous = error;
    }
  EXPECT_LT(previous, 1e-2);
}

TEST(CurvedBeam, EndMomentClosesAQuarterCircle)
{
  // A moment M = 3 EI / R at the tip of a quarter circle of radius R raises the curvature from
  // 1/R to 4/R (pure bending, no stretch): the arc of length pi R / 2 becomes a full circle and
  // the tip returns to the clamped root with the root's tangent (large rotation: the tip tangent
  // turns by 3 pi / 2).
  const double R = 1.0, M = 3 * section.EI / R;
  double       previous = 1e300;
  for (const int n : {4, 8, 16, 32})
    {
      BeamMesh mesh = arc(R, uniform_angles(0, M_PI / 2, n));
      mesh.set_reference_geometry("test");
      std::vector<double> d;
      const auto          history = solve_cantilever(mesh, Tensor<1, 3>(), M, 12, d);
      const Point<3>      tip     = mesh.nodes[n] + Tensor<1, 3>({d[6 * n], d[6 * n + 1], d[6 * n + 2]});
      const Tensor<1, 3>  t({d[6 * n + 3] + mesh.tangents[n][0], d[6 * n + 4] + mesh.tangents[n][1], d[6 * n + 5]});
      const double        error = tip.distance(mesh.nodes[0]) / R;
      std::cout << n << " elements: tip (" << tip[0] << ", " << tip[1] << "), exact (" << R << ", 0), error " << error
                << ", tip tangent (" << t[0] / t.norm() << ", " << t[1] / t.norm() << "), Newton steps (last load step) "
                << history.size() - 1 << "\n";
      EXPECT_LT(error, previous) << n << " elements";
      EXPECT_LE(history.size(), 10u);
      previous = error;
      if (n == 32)
        EXPECT_NEAR(t[1] / t.norm(), 1.0, 1e-4);
    }
  EXPECT_LT(previous, 1e-3);
}

TEST(CurvedBeam, BranchesAndCornersAreInputErrors)
{
  auto message = [](BeamMesh mesh) {
    try
      {
        mesh.set_reference_geometry("fibres.msh");
      }
    catch (const std::invalid_argument& e)
      {
        return std::string(e.what());
      }
    return std::string("no error");
  };
  BeamMesh corner; // a right angle
  add_straight_fibre(corner, Point<3>(0, 0, 0), Point<3>(1, 0, 0), 1);
  corner.nodes.emplace_back(1.0, 1.0, 0.0);
  corner.elements.push_back({{1, 2}});
  EXPECT_EQ(message(corner), "fibres.msh: beam turns by 90 degrees at node 1 (at most 60; a C1 beam needs a smooth "
                             "curve: refine the curve's mesh)");
  BeamMesh branch = arc(1.0, {0.0, 0.2, 0.4});
  branch.nodes.emplace_back(2.0, 2.0, 0.0);
  branch.elements.push_back({{1, 3}});
  EXPECT_EQ(message(branch), "fibres.msh: beam branches at node 1 (3 elements meet there; every fibre must be a simple curve)");
  BeamMesh lonely = arc(1.0, {0.0, 0.2});
  lonely.nodes.emplace_back(2.0, 2.0, 0.0);
  EXPECT_EQ(message(lonely), "fibres.msh: beam node 2 belongs to no element");
}
