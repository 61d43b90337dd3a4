// The mortar integration kernel on its own: biorthogonality of the dual shape functions, the
// partition-of-unity property sum_l M_jl = sum_k D_jk on covered faces, exact areas of
// partial overlaps, and the AD linearization against central finite differences.
#include "common/mortar_integration.h"

#include <Sacado.hpp>
#include <gtest/gtest.h>

#include <random>

using namespace physics::mortar;
using AD = Sacado::Fad::DFad<double>;

namespace
{
  template <int dim>
  using Face = std::vector<Point<double, dim>>;

  /// A flat parallelogram at z = 0.5 (counterclockwise seen from above): on it the projected
  /// integrands are polynomials and the quadrature is exact.
  Face<3> parallelogram()
  {
    return {{{0.1, 0.2, 0.5}}, {{0.6, 0.25, 0.5}}, {{0.7, 0.75, 0.5}}, {{0.2, 0.7, 0.5}}};
  }
  /// A distorted, slightly warped quadrilateral.
  Face<3> slave_quad()
  {
    return {{{0.1, 0.2, 0.5}}, {{0.6, 0.15, 0.5}}, {{0.65, 0.7, 0.52}}, {{0.05, 0.6, 0.5}}};
  }
  /// Large master face below (master body below: outward normal +z, counterclockwise from above).
  Face<3> master_quad(double size = 2.0)
  {
    return {{{-size, -size, 0.49}}, {{size, -size, 0.49}}, {{size, size, 0.49}}, {{-size, size, 0.49}}};
  }
  /// Slave body above: outward normal -z, so the slave face runs clockwise seen from above.
  template <class F>
  F reversed(F f)
  {
    std::reverse(f.begin(), f.end());
    return f;
  }

  template <int dim>
  double row_sum(const std::vector<std::vector<double>>& A, int j)
  {
    double s = 0;
    for (double v : A[j])
      s += v;
    return s;
  }
} // namespace

TEST(MortarIntegration, DualShapeFunctionsMakeDDiagonal3D)
{
  for (bool tri : {false, true})
    {
      Face<3> xs = reversed(parallelogram());
      if (tri)
        xs.pop_back();
      const auto pair = integrate_pair<double, 3>(xs, master_quad(), true);
      ASSERT_TRUE(pair.overlap);
      double area = 0;
      for (std::size_t j = 0; j < xs.size(); ++j)
        for (std::size_t k = 0; k < xs.size(); ++k)
          {
            if (j != k)
              {
                EXPECT_NEAR(pair.D[j][k], 0.0, 1e-12) << "tri " << tri << " j " << j << " k " << k;
              }
            area += pair.D[j][k];
          }
      for (std::size_t j = 0; j < xs.size(); ++j)
        EXPECT_NEAR(row_sum<3>(pair.M, j), row_sum<3>(pair.D, j), 1e-12);
      const auto pair_std = integrate_pair<double, 3>(xs, master_quad(), false);
      double     area_std = 0;
      for (auto& r : pair_std.D)
        for (double v : r)
          area_std += v;
      EXPECT_NEAR(area, area_std, 1e-12);
      EXPECT_GT(area, 0.0);
    }
}

TEST(MortarIntegration, DualShapeFunctionsMakeDDiagonal2D)
{
  const Face<2> xs{{{0.7, 0.5}}, {{0.1, 0.52}}}; // body above: outward normal points down
  const Face<2> xm{{{-1.0, 0.49}}, {{2.0, 0.49}}};
  const auto    pair = integrate_pair<double, 2>(xs, xm, true);
  ASSERT_TRUE(pair.overlap);
  EXPECT_NEAR(pair.D[0][1], 0.0, 1e-14);
  EXPECT_NEAR(pair.D[1][0], 0.0, 1e-14);
  const double length = std::hypot(0.6, 0.02);
  EXPECT_NEAR(pair.D[0][0], length / 2, 1e-12);
  EXPECT_NEAR(row_sum<2>(pair.M, 0), pair.D[0][0], 1e-12);
}

// On a distorted, warped face the projected integrands are rational: D is diagonal up to the
// quadrature error only.
TEST(MortarIntegration, DualShapeFunctionsOnDistortedFace)
{
  const Face<3> xs   = reversed(slave_quad());
  const auto    pair = integrate_pair<double, 3>(xs, master_quad(), true);
  double        diag = 0, off = 0;
  for (std::size_t j = 0; j < 4; ++j)
    for (std::size_t k = 0; k < 4; ++k)
      (j == k ? diag : off) += std::abs(pair.D[j][k]);
  EXPECT_LT(off, 1e-3 * diag);
  for (std::size_t j = 0; j < 4; ++j)
    EXPECT_NEAR(row_sum<3>(pair.M, j), row_sum<3>(pair.D, j), 1e-12);
}

TEST(MortarIntegration, PartialOverlapArea3D)
{
  // Unit square slave at z = 0 (facing -z), master square shifted by (0.5, 0.25): overlap 0.5 x 0.75.
  const Face<3> xs = reversed(Face<3>{{{0, 0, 0}}, {{1, 0, 0}}, {{1, 1, 0}}, {{0, 1, 0}}});
  const Face<3> xm{{{0.5, 0.25, -0.01}}, {{1.5, 0.25, -0.01}}, {{1.5, 1.25, -0.01}}, {{0.5, 1.25, -0.01}}};
  const auto    pair = integrate_pair<double, 3>(xs, xm, false);
  ASSERT_TRUE(pair.overlap);
  double total = 0;
  for (auto& r : pair.M)
    for (double v : r)
      total += v;
  EXPECT_NEAR(total, 0.375, 1e-12);
}

template <int dim>
void check_linearization(const Face<dim>& xs, const Face<dim>& xm, bool dual)
{
  const int ns = xs.size(), nm = xm.size(), n = (ns + nm) * dim;
  std::vector<Point<AD, dim>> as(ns), am(nm);
  for (int i = 0; i < ns; ++i)
    for (int d = 0; d < dim; ++d)
      as[i][d] = AD(n, i * dim + d, xs[i][d]);
  for (int i = 0; i < nm; ++i)
    for (int d = 0; d < dim; ++d)
      am[i][d] = AD(n, (ns + i) * dim + d, xm[i][d]);
  const auto ad = integrate_pair<AD, dim>(as, am, dual);
  ASSERT_TRUE(ad.overlap);
  const double h = 1e-7;
  double       worst = 0, scale = 0;
  for (int v = 0; v < n; ++v)
    {
      auto ps = xs, pm = xm, ms = xs, mm = xm;
      const int node = v / dim, d = v % dim;
      (node < ns ? ps[node][d] : pm[node - ns][d]) += h;
      (node < ns ? ms[node][d] : mm[node - ns][d]) -= h;
      const auto plus = integrate_pair<double, dim>(ps, pm, dual), minus = integrate_pair<double, dim>(ms, mm, dual);
      for (int j = 0; j < ns; ++j)
        {
          for (int k = 0; k < ns; ++k)
            {
              const double fd = (plus.D[j][k] - minus.D[j][k]) / (2 * h);
              worst           = std::max(worst, std::abs(fd - ad.D[j][k].dx(v)));
              scale           = std::max(scale, std::abs(fd));
            }
          for (int l = 0; l < nm; ++l)
            {
              const double fd = (plus.M[j][l] - minus.M[j][l]) / (2 * h);
              worst           = std::max(worst, std::abs(fd - ad.M[j][l].dx(v)));
              scale           = std::max(scale, std::abs(fd));
            }
        }
    }
  EXPECT_LT(worst, 1e-6 * scale) << "largest |AD - FD| " << worst << ", largest derivative " << scale;
}

TEST(MortarIntegration, LinearizationMatchesFiniteDifferences)
{
  // Partial overlaps (clip polygon vertices move with the nodes), distorted faces.
  check_linearization<2>({{{0.7, 0.5}}, {{0.1, 0.53}}}, {{{0.3, 0.49}}, {{0.9, 0.47}}}, true);
  check_linearization<2>({{{0.7, 0.5}}, {{0.1, 0.53}}}, {{{0.3, 0.49}}, {{0.9, 0.47}}}, false);
  const Face<3> xs = reversed(slave_quad());
  const Face<3> xm{{{0.3, 0.35, 0.49}}, {{0.9, 0.3, 0.47}}, {{0.95, 0.9, 0.5}}, {{0.25, 0.85, 0.48}}};
  check_linearization<3>(xs, xm, true);
  check_linearization<3>(xs, xm, false);
  Face<3> tri = xs;
  tri.pop_back();
  check_linearization<3>(tri, xm, true);
}

namespace
{
  /// A small square face (3D) or segment (2D) through the origin whose unit normal (face_unit_normal's
  /// orientation) is n.
  template <int dim>
  Face<dim> face_with_normal(const Point<double, dim>& n)
  {
    if constexpr (dim == 2)
      return {{{0.1 * n[1], -0.1 * n[0]}}, {{-0.1 * n[1], 0.1 * n[0]}}};
    else
      {
        // u, v orthonormal to n; the face's orientation is fixed against face_unit_normal below.
        Point<double, 3> u{{std::abs(n[0]) < 0.9 ? 1.0 : 0.0, std::abs(n[0]) < 0.9 ? 0.0 : 1.0, 0.0}};
        const double     along = dot<double, 3>(u, n);
        for (int d = 0; d < 3; ++d)
          u[d] -= along * n[d];
        const double len = std::sqrt(dot<double, 3>(u, u));
        for (int d = 0; d < 3; ++d)
          u[d] /= len;
        const Point<double, 3> v = cross<double>(n, u);
        Face<3>                f;
        for (const auto& ab :
             std::array<std::array<double, 2>, 4>{{{{-1, -1}}, {{1, -1}}, {{1, 1}}, {{-1, 1}}}})
          f.push_back({{0.1 * (ab[0] * u[0] + ab[1] * v[0]), 0.1 * (ab[0] * u[1] + ab[1] * v[1]),
                        0.1 * (ab[0] * u[2] + ab[1] * v[2])}});
        return f;
      }
  }

  /// The frame at a node whose one adjacent face has normal n: orthonormal, normal n itself, and
  /// every tangent with a positive entry in the Cartesian component of the multiplier row that
  /// holds it, in double and in AD arithmetic alike.
  template <int dim>
  void check_frame(const Point<double, dim>& n)
  {
    Face<dim> face = face_with_normal<dim>(n);
    if (dot<double, dim>(face_unit_normal<double, dim>(face), n) < 0)
      std::reverse(face.begin(), face.end());
    const auto frame = nodal_frame<double, dim>({face});
    const auto row   = constraint_components<double, dim>(frame);
    for (int d = 0; d < dim; ++d)
      EXPECT_NEAR(frame[0][d], n[d], 1e-12);
    for (int a = 0; a < dim; ++a)
      for (int b = 0; b < dim; ++b)
        EXPECT_NEAR((dot<double, dim>(frame[a], frame[b])), (a == b ? 1.0 : 0.0), 1e-12);
    for (int m = 1; m < dim; ++m)
      EXPECT_GT(frame[m][row[m]], 0.0) << "tangent " << m << " at normal " << n[0] << " " << n[1];

    std::vector<Point<AD, dim>> ad_face;
    for (const auto& p : face)
      {
        Point<AD, dim> q;
        for (int d = 0; d < dim; ++d)
          q[d] = AD(dim * face.size(), dim * ad_face.size() + d, p[d]);
        ad_face.push_back(q);
      }
    const auto ad_frame = nodal_frame<AD, dim>({ad_face});
    for (int m = 0; m < dim; ++m)
      for (int d = 0; d < dim; ++d)
        EXPECT_NEAR(ad_frame[m][d].val(), frame[m][d], 1e-12);
  }
} // namespace

// The tangents' signs: without a fixed orientation a frictionless row tau . lambda = 0 had the
// diagonal entry +1 at some nodes and -1 at their neighbours (where the axis least aligned with
// n changes), and the AMG's tentative multiplier transfer summed them to a zero coarse diagonal.
TEST(MortarIntegration, TangentsPointAlongTheAxisOfTheirRows)
{
  for (int k = 0; k < 72; ++k)
    {
      const double phi = 2 * M_PI * (k + 0.5) / 72;
      check_frame<2>({{std::cos(phi), std::sin(phi)}});
      // Around a torus' top circle: n close to -z with a radial tilt, and a full sphere sweep.
      const double tilt = 0.1;
      check_frame<3>({{tilt * std::cos(phi) / std::sqrt(1 + tilt * tilt),
                       tilt * std::sin(phi) / std::sqrt(1 + tilt * tilt), -1 / std::sqrt(1 + tilt * tilt)}});
      for (int l = 1; l < 12; ++l)
        {
          const double theta = M_PI * l / 12;
          check_frame<3>(
              {{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)}});
        }
    }
}
