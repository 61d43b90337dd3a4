// Mortar integration of one slave face against one master face, in 2D and 3D, for any scalar
// type T (double, or Sacado's forward AD type to obtain the exact linearization).
//
// One algorithm serves both dimensions (Puso & Laursen 2004; Popp et al. 2010): the slave face
// defines an auxiliary plane (2D: the line of the straight slave segment) through its centre x0
// with unit normal n0. Both faces are projected onto that plane along n0, the master polygon is
// clipped against the slave polygon (2D: interval intersection; 3D: Sutherland-Hodgman), the clip
// polygon is split into triangles around its centroid and integrated with Gauss rules. Each
// Gauss point is mapped back to the slave and master parameter spaces by projection along n0,
// where the shape functions are evaluated:
//     D[j][k] += w Phi_j(xi) N_k(xi),      M[j][l] += w Phi_j(xi) N_l^m(eta).
// Phi are the multiplier shape functions: standard (Phi = N) or dual (Phi_j = sum_k A_jk N_k,
// A = D_e M_e^-1 on the whole slave face, which makes the face's D diagonal: biorthogonality).
//
// Faces are ordered so that the right-hand rule gives the OUTWARD normal of their body:
// 2D segment (a, b): n = (t_y, -t_x), t = b - a; 3D triangle/quadrilateral counterclockwise seen
// from outside: n = (x1 - x0) x (x2 - x0). Quadrilateral nodes are numbered around the face
// (reference corners (-1,-1), (1,-1), (1,1), (-1,1)); triangles have reference corners (0,0),
// (1,0), (0,1).
//
// Everything below is a plain function of the node positions, so with T = Sacado::Fad::DFad the
// derivatives of D and M with respect to all slave and master node positions come out exact,
// including the motion of the clip polygon's vertices (the "segment boundaries" of 2D mortar
// papers) and of the dual coefficients.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>
#include <vector>

namespace physics::mortar
{
  template <typename T, int dim>
  using Point = std::array<T, dim>;

  template <typename T>
  inline double value_of(const T& x)
  {
    if constexpr (std::is_same_v<T, double>)
      return x;
    else
      return x.val();
  }

  /// sqrt for double and for AD types (found by argument-dependent lookup).
  template <typename T>
  inline T sqrt_of(const T& x)
  {
    using std::sqrt;
    return sqrt(x);
  }

  template <typename T, int dim>
  T dot(const Point<T, dim>& a, const Point<T, dim>& b)
  {
    T s = a[0] * b[0];
    for (int d = 1; d < dim; ++d)
      s += a[d] * b[d];
    return s;
  }

  template <typename T>
  Point<T, 3> cross(const Point<T, 3>& a, const Point<T, 3>& b)
  {
    return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
  }

  /// Number of face nodes -> reference element: 2 = segment, 3 = triangle, 4 = quadrilateral.
  /// Shape functions N and their parameter derivatives dN[i][r] at reference point xi.
  template <typename T>
  void face_shape_functions(int n, const std::array<T, 2>& xi, std::array<T, 4>& N,
                            std::array<std::array<T, 2>, 4>& dN)
  {
    if (n == 2)
      {
        N[0]     = (1.0 - xi[0]) / 2.0;
        N[1]     = (1.0 + xi[0]) / 2.0;
        dN[0][0] = -0.5;
        dN[1][0] = 0.5;
        dN[0][1] = dN[1][1] = 0.0;
      }
    else if (n == 3)
      {
        N[0]  = 1.0 - xi[0] - xi[1];
        N[1]  = xi[0];
        N[2]  = xi[1];
        dN[0] = {{-1.0, -1.0}};
        dN[1] = {{1.0, 0.0}};
        dN[2] = {{0.0, 1.0}};
      }
    else
      {
        static const double c[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
        for (int a = 0; a < 4; ++a)
          {
            N[a]     = (1.0 + c[a][0] * xi[0]) * (1.0 + c[a][1] * xi[1]) / 4.0;
            dN[a][0] = c[a][0] * (1.0 + c[a][1] * xi[1]) / 4.0;
            dN[a][1] = c[a][1] * (1.0 + c[a][0] * xi[0]) / 4.0;
          }
      }
  }

  /// Reference-element centre (where the auxiliary plane's normal is taken).
  inline std::array<double, 2> face_centre_parameter(int n)
  {
    return n == 3 ? std::array<double, 2>{{1.0 / 3.0, 1.0 / 3.0}} : std::array<double, 2>{{0.0, 0.0}};
  }

  /// Position x(xi) and the tangents dx/dxi_0, dx/dxi_1 at xi of a face.
  template <typename T, int dim>
  void face_point_and_tangents(const std::vector<Point<T, dim>>& x, const std::array<T, 2>& xi,
                               Point<T, dim>& position, Point<T, dim>& g0, Point<T, dim>& g1)
  {
    const int                       n = static_cast<int>(x.size());
    std::array<T, 4>                N;
    std::array<std::array<T, 2>, 4> dN;
    face_shape_functions<T>(n, xi, N, dN);
    for (int d = 0; d < dim; ++d)
      {
        position[d] = 0.0;
        g0[d]       = 0.0;
        g1[d]       = 0.0;
        for (int a = 0; a < n; ++a)
          {
            position[d] += N[a] * x[a][d];
            g0[d] += dN[a][0] * x[a][d];
            g1[d] += dN[a][1] * x[a][d];
          }
      }
  }

  /// Position x(xi) and the (unnormalized, outward) normal at xi of a face.
  template <typename T, int dim>
  void face_geometry(const std::vector<Point<T, dim>>& x, const std::array<T, 2>& xi, Point<T, dim>& position,
                     Point<T, dim>& normal)
  {
    Point<T, dim> g0, g1;
    face_point_and_tangents<T, dim>(x, xi, position, g0, g1);
    if constexpr (dim == 2)
      normal = {{g0[1], -g0[0]}};
    else
      normal = cross<T>(g0, g1);
  }

  /// Unit outward normal of a face at its reference centre.
  template <typename T, int dim>
  Point<T, dim> face_unit_normal(const std::vector<Point<T, dim>>& x)
  {
    const auto             c = face_centre_parameter(static_cast<int>(x.size()));
    const std::array<T, 2> xi{{c[0], c[1]}};
    Point<T, dim>          p, n;
    face_geometry<T, dim>(x, xi, p, n);
    const T len = sqrt_of(dot<T, dim>(n, n));
    for (int d = 0; d < dim; ++d)
      n[d] /= len;
    return n;
  }

  /// Parameter coordinates xi of the point of face x hit by the line p + alpha n0:
  /// solves x(xi) - alpha n0 = p by Newton's method (exact in one step for affine faces).
  template <typename T, int dim>
  std::array<T, 2> project_along(const std::vector<Point<T, dim>>& x, const Point<T, dim>& n0,
                                 const Point<T, dim>& p)
  {
    const int        n = static_cast<int>(x.size());
    const auto       c = face_centre_parameter(n);
    std::array<T, 2> xi{{c[0], c[1]}};
    T                alpha = 0.0;
    for (int it = 0; it < 20; ++it)
      {
        // Residual r = x(xi) - alpha n0 - p and its Jacobian columns [dx/dxi_0, dx/dxi_1, -n0].
        Point<T, dim> r, g0, g1;
        face_point_and_tangents<T, dim>(x, xi, r, g0, g1);
        for (int d = 0; d < dim; ++d)
          r[d] -= alpha * n0[d] + p[d];
        if constexpr (dim == 2)
          {
            // [g0 -n0] (dxi, dalpha) = -r
            const T det = -g0[0] * n0[1] + n0[0] * g0[1];
            const T dxi = (-r[0] * -n0[1] + n0[0] * -r[1]) / det;
            const T dal = (g0[0] * -r[1] - g0[1] * -r[0]) / det;
            xi[0] += dxi;
            alpha += dal;
            if (std::abs(value_of(dxi)) < 1e-14)
              break;
          }
        else
          {
            // Cramer's rule for the 3x3 system [g0 g1 -n0] delta = -r.
            const Point<T, 3> m{{-n0[0], -n0[1], -n0[2]}}, b{{-r[0], -r[1], -r[2]}};
            const T           det = dot<T, 3>(g0, cross<T>(g1, m));
            const T           d0  = dot<T, 3>(b, cross<T>(g1, m)) / det;
            const T           d1  = dot<T, 3>(g0, cross<T>(b, m)) / det;
            const T           d2  = dot<T, 3>(g0, cross<T>(g1, b)) / det;
            xi[0] += d0;
            xi[1] += d1;
            alpha += d2;
            if (std::abs(value_of(d0)) + std::abs(value_of(d1)) < 1e-14)
              break;
          }
      }
    return xi;
  }

  /// Gauss rule on the reference element of a face with n nodes, exact for polynomials of degree
  /// 5 (segment: 3 points on [-1,1]; triangle: 7 points on the unit triangle, weights summing to
  /// 1/2; quadrilateral: 3 x 3 points on [-1,1]^2).
  struct FaceQuadrature
  {
    std::vector<std::array<double, 2>> points;
    std::vector<double>                weights;
    explicit FaceQuadrature(int n);
  };

  inline FaceQuadrature::FaceQuadrature(int n)
  {
    const double g[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, w[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
    if (n == 2)
      for (int i = 0; i < 3; ++i)
        {
          points.push_back({{g[i], 0.0}});
          weights.push_back(w[i]);
        }
    else if (n == 4)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          {
            points.push_back({{g[i], g[j]}});
            weights.push_back(w[i] * w[j]);
          }
    else
      {
        // Radon's 7-point rule (degree 5).
        const double s = std::sqrt(15.0);
        const double a1 = (6.0 - s) / 21.0, a2 = (6.0 + s) / 21.0;
        const double w1 = (155.0 - s) / 2400.0, w2 = (155.0 + s) / 2400.0;
        points  = {{{1.0 / 3.0, 1.0 / 3.0}}, {{a1, a1}}, {{1 - 2 * a1, a1}}, {{a1, 1 - 2 * a1}},
                   {{a2, a2}},               {{1 - 2 * a2, a2}}, {{a2, 1 - 2 * a2}}};
        weights = {9.0 / 80.0, w1, w1, w1, w2, w2, w2};
      }
  }

  /// Multiplier shape-function coefficients A (Phi_j = sum_k A[j][k] N_k) of a slave face.
  /// Dual: A = D_e M_e^-1 with D_e = diag(int N_j), M_e = int N_j N_k over the face.
  template <typename T, int dim>
  std::vector<std::vector<T>> multiplier_coefficients(const std::vector<Point<T, dim>>& x, bool dual)
  {
    const int                   n = static_cast<int>(x.size());
    std::vector<std::vector<T>> A(n, std::vector<T>(n, T(0.0)));
    for (int j = 0; j < n; ++j)
      A[j][j] = 1.0;
    if (!dual)
      return A;
    std::vector<std::vector<T>> Me(n, std::vector<T>(n, T(0.0)));
    std::vector<T>              De(n, T(0.0));
    const FaceQuadrature        q(n);
    for (std::size_t i = 0; i < q.points.size(); ++i)
      {
        const std::array<T, 2>          xi{{q.points[i][0], q.points[i][1]}};
        std::array<T, 4>                N;
        std::array<std::array<T, 2>, 4> dN;
        face_shape_functions<T>(n, xi, N, dN);
        Point<T, dim> p, nrm;
        face_geometry<T, dim>(x, xi, p, nrm);
        const T J = sqrt_of(dot<T, dim>(nrm, nrm)) * q.weights[i];
        for (int j = 0; j < n; ++j)
          {
            De[j] += N[j] * J;
            for (int k = 0; k < n; ++k)
              Me[j][k] += N[j] * N[k] * J;
          }
      }
    // A = De Me^-1: solve Me^T A^T = De column by column (Me symmetric) by Gauss-Jordan.
    std::vector<std::vector<T>> inv(n, std::vector<T>(n, T(0.0)));
    for (int j = 0; j < n; ++j)
      inv[j][j] = 1.0;
    for (int c = 0; c < n; ++c)
      {
        const T pivot = Me[c][c];
        for (int k = 0; k < n; ++k)
          {
            Me[c][k] /= pivot;
            inv[c][k] /= pivot;
          }
        for (int r = 0; r < n; ++r)
          if (r != c)
            {
              const T f = Me[r][c];
              for (int k = 0; k < n; ++k)
                {
                  Me[r][k] -= f * Me[c][k];
                  inv[r][k] -= f * inv[c][k];
                }
            }
      }
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k)
        A[j][k] = De[j] * inv[j][k];
    return A;
  }

  /// Result of integrating one slave/master face pair: D is n_s x n_s, M is n_s x n_m.
  template <typename T>
  struct MortarPair
  {
    bool                        overlap = false;
    std::vector<std::vector<T>> D, M;
  };

  /// Clip polygon in auxiliary-plane coordinates (3D): Sutherland-Hodgman of `subject` against
  /// the convex counterclockwise polygon `clip`.
  template <typename T>
  std::vector<std::array<T, 2>> clip_polygon(std::vector<std::array<T, 2>> subject,
                                             const std::vector<std::array<T, 2>>& clip)
  {
    const std::size_t nc = clip.size();
    for (std::size_t e = 0; e < nc && !subject.empty(); ++e)
      {
        const auto& a = clip[e];
        const auto& b = clip[(e + 1) % nc];
        // inside: left of a->b (counterclockwise clip polygon)
        auto side = [&](const std::array<T, 2>& p) -> T {
          return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        };
        // Points within a roundoff band of the edge count as inside: master and slave edges
        // that coincide (aligned meshes, symmetry planes) then produce no intersection, whose
        // parameter t = sp / (sp - sq) would be 0/0 with meaningless derivatives.
        const double eps = 1e-10 * value_of((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]));
        std::vector<std::array<T, 2>> out;
        for (std::size_t i = 0; i < subject.size(); ++i)
          {
            const auto& p = subject[i];
            const auto& q = subject[(i + 1) % subject.size()];
            const T     sp = side(p), sq = side(q);
            const bool  ip = value_of(sp) >= -eps, iq = value_of(sq) >= -eps;
            if (ip)
              out.push_back(p);
            if (ip != iq)
              {
                const T t = sp / (sp - sq);
                out.push_back({{p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])}});
              }
          }
        subject = std::move(out);
      }
    return subject;
  }

  /// Integrates D and M for one slave face xs against one master face xm.
  /// `relative_tolerance`: overlaps smaller than this fraction of the slave face are ignored.
  template <typename T, int dim>
  MortarPair<T> integrate_pair(const std::vector<Point<T, dim>>& xs, const std::vector<Point<T, dim>>& xm,
                               bool dual, double relative_tolerance = 1e-12)
  {
    const int     ns = static_cast<int>(xs.size()), nm = static_cast<int>(xm.size());
    MortarPair<T> result;

    // Auxiliary plane: slave centre x0, unit normal n0, in-plane orthonormal basis e1 (, e2).
    Point<T, dim> x0, n0;
    {
      const auto             c = face_centre_parameter(ns);
      const std::array<T, 2> xi{{c[0], c[1]}};
      face_geometry<T, dim>(xs, xi, x0, n0);
      const T len = sqrt_of(dot<T, dim>(n0, n0));
      for (int d = 0; d < dim; ++d)
        n0[d] /= len;
    }
    // Only faces that look at each other interact (master normal against the slave normal).
    if (value_of(dot<T, dim>(face_unit_normal<T, dim>(xm), n0)) >= 0.0)
      return result;

    Point<T, dim> e1, e2{};
    for (int d = 0; d < dim; ++d)
      e1[d] = xs[1][d] - xs[0][d];
    {
      const T along = dot<T, dim>(e1, n0);
      for (int d = 0; d < dim; ++d)
        e1[d] -= along * n0[d];
      const T len = sqrt_of(dot<T, dim>(e1, e1));
      for (int d = 0; d < dim; ++d)
        e1[d] /= len;
      if constexpr (dim == 3)
        e2 = cross<T>(n0, e1);
    }
    auto to_plane = [&](const Point<T, dim>& p) {
      Point<T, dim> r;
      for (int d = 0; d < dim; ++d)
        r[d] = p[d] - x0[d];
      std::array<T, 2> s{{dot<T, dim>(r, e1), T(0.0)}};
      if constexpr (dim == 3)
        s[1] = dot<T, dim>(r, e2);
      return s;
    };
    auto from_plane = [&](const std::array<T, 2>& s) {
      Point<T, dim> p;
      for (int d = 0; d < dim; ++d)
        {
          p[d] = x0[d] + s[0] * e1[d];
          if constexpr (dim == 3)
            p[d] += s[1] * e2[d];
        }
      return p;
    };

    // Integration cells on the plane: a list of (point, weight) pairs.
    std::vector<std::array<T, 2>> qp;
    std::vector<T>                qw;
    T                             slave_measure;
    if constexpr (dim == 2)
      {
        const T s0 = to_plane(xs[0])[0], s1 = to_plane(xs[1])[0];
        const T m0 = to_plane(xm[0])[0], m1 = to_plane(xm[1])[0];
        slave_measure = s1 - s0; // > 0: e1 points from node 0 to node 1
        const T lo = value_of(m0) < value_of(m1) ? m0 : m1;
        const T hi = value_of(m0) < value_of(m1) ? m1 : m0;
        const T a  = value_of(lo) > value_of(s0) ? lo : s0;
        const T b  = value_of(hi) < value_of(s1) ? hi : s1;
        if (value_of(b - a) <= relative_tolerance * value_of(slave_measure))
          return result;
        const FaceQuadrature q(2);
        for (std::size_t i = 0; i < q.points.size(); ++i)
          {
            qp.push_back({{(a + b) / 2.0 + (b - a) / 2.0 * q.points[i][0], T(0.0)}});
            qw.push_back((b - a) / 2.0 * q.weights[i]);
          }
      }
    else
      {
        std::vector<std::array<T, 2>> slave_poly, master_poly;
        for (const auto& p : xs)
          slave_poly.push_back(to_plane(p));
        for (const auto& p : xm)
          master_poly.push_back(to_plane(p));
        auto signed_area = [](const std::vector<std::array<T, 2>>& poly) {
          T a = 0.0;
          for (std::size_t i = 0; i < poly.size(); ++i)
            {
              const auto& p = poly[i];
              const auto& q = poly[(i + 1) % poly.size()];
              a += (p[0] * q[1] - q[0] * p[1]) / 2.0;
            }
          return a;
        };
        slave_measure = signed_area(slave_poly);
        // The master face is numbered counterclockwise around ITS outward normal, which points
        // against n0: seen on the plane it runs clockwise. Reverse it for the clipping.
        if (value_of(signed_area(master_poly)) < 0.0)
          std::reverse(master_poly.begin(), master_poly.end());
        const auto poly = clip_polygon<T>(master_poly, slave_poly);
        if (poly.size() < 3 || value_of(signed_area(poly)) <= relative_tolerance * value_of(slave_measure))
          return result;
        std::array<T, 2> c{{T(0.0), T(0.0)}};
        for (const auto& p : poly)
          {
            c[0] += p[0] / static_cast<double>(poly.size());
            c[1] += p[1] / static_cast<double>(poly.size());
          }
        const FaceQuadrature q(3);
        for (std::size_t t = 0; t < poly.size(); ++t)
          {
            const auto& p  = poly[t];
            const auto& r  = poly[(t + 1) % poly.size()];
            const T     a2 = (p[0] - c[0]) * (r[1] - c[1]) - (p[1] - c[1]) * (r[0] - c[0]); // 2 x area
            for (std::size_t i = 0; i < q.points.size(); ++i)
              {
                const double u = q.points[i][0], v = q.points[i][1];
                qp.push_back({{c[0] + u * (p[0] - c[0]) + v * (r[0] - c[0]),
                              c[1] + u * (p[1] - c[1]) + v * (r[1] - c[1])}});
                qw.push_back(a2 * q.weights[i]);
              }
          }
      }

    const auto A = multiplier_coefficients<T, dim>(xs, dual);
    result.overlap = true;
    result.D.assign(ns, std::vector<T>(ns, T(0.0)));
    result.M.assign(ns, std::vector<T>(nm, T(0.0)));
    for (std::size_t i = 0; i < qp.size(); ++i)
      {
        const Point<T, dim>             p   = from_plane(qp[i]);
        const std::array<T, 2>          xis = project_along<T, dim>(xs, n0, p);
        const std::array<T, 2>          xim = project_along<T, dim>(xm, n0, p);
        std::array<T, 4>                Ns, Nm, Phi;
        std::array<std::array<T, 2>, 4> dN;
        face_shape_functions<T>(ns, xis, Ns, dN);
        face_shape_functions<T>(nm, xim, Nm, dN);
        for (int j = 0; j < ns; ++j)
          {
            Phi[j] = 0.0;
            for (int k = 0; k < ns; ++k)
              Phi[j] += A[j][k] * Ns[k];
          }
        for (int j = 0; j < ns; ++j)
          {
            for (int k = 0; k < ns; ++k)
              result.D[j][k] += qw[i] * Phi[j] * Ns[k];
            for (int l = 0; l < nm; ++l)
              result.M[j][l] += qw[i] * Phi[j] * Nm[l];
          }
      }
    return result;
  }

  /// Which Cartesian component of a node's multiplier row holds which constraint of the frame
  /// (normal first, then the tangents): the normal takes the component it is most aligned with,
  /// each tangent the best remaining one. The rows' diagonals (and those of the Schur complement
  /// the block smoothers build) are then nonzero, which pointwise smoothers (SGS, ILU) need.
  template <typename T, int dim>
  std::array<int, dim> constraint_components(const std::array<Point<T, dim>, dim>& frame)
  {
    std::array<int, dim>  component{};
    std::array<bool, dim> taken{};
    for (int m = 0; m < dim; ++m)
      {
        int best = -1;
        for (int c = 0; c < dim; ++c)
          if (!taken[c] && (best < 0 || std::abs(value_of(frame[m][c])) > std::abs(value_of(frame[m][best]))))
            best = c;
        taken[best]  = true;
        component[m] = best;
      }
    return component;
  }

  /// Unit normal and dim-1 unit tangents at a slave node from its adjacent faces (outward unit
  /// normals at the face centres, averaged), for any scalar type.
  ///
  /// A tangent's sign is free (tau . lambda = 0 and Coulomb's law hold for -tau as well), and it
  /// is fixed here so that each tangent points along the positive Cartesian axis of the row that
  /// holds it (constraint_components()): every frictionless tangential row then has a positive
  /// diagonal entry in the multiplier block. Otherwise the sign flips wherever the axis least
  /// aligned with n changes (every 45 degrees around a torus' contact circle), and the AMG's
  /// tentative multiplier transfer, which sums a component over the nodes of an aggregate, adds
  /// +1 and -1 into a coarse tangential row with a (near) zero diagonal: a near-singular coarse
  /// operator, a preconditioner of norm ~1e10, and GMRES whose true residual stalls at 1e-3 while
  /// its implicit one reaches the tolerance.
  template <typename T, int dim>
  std::array<Point<T, dim>, dim> nodal_frame(const std::vector<std::vector<Point<T, dim>>>& faces)
  {
    Point<T, dim> n;
    for (int d = 0; d < dim; ++d)
      n[d] = 0.0;
    for (const auto& f : faces)
      {
        const auto nf = face_unit_normal<T, dim>(f);
        for (int d = 0; d < dim; ++d)
          n[d] += nf[d];
      }
    const T len = sqrt_of(dot<T, dim>(n, n));
    for (int d = 0; d < dim; ++d)
      n[d] /= len;
    std::array<Point<T, dim>, dim> frame;
    frame[0] = n;
    if constexpr (dim == 2)
      frame[1] = {{-n[1], n[0]}};
    else
      {
        // First tangent: the coordinate axis least aligned with n, made orthogonal to n.
        int axis = 0;
        for (int d = 1; d < 3; ++d)
          if (std::abs(value_of(n[d])) < std::abs(value_of(n[axis])))
            axis = d;
        Point<T, 3> t;
        for (int d = 0; d < 3; ++d)
          t[d] = (d == axis ? 1.0 : 0.0) - n[axis] * n[d];
        const T tl = sqrt_of(dot<T, 3>(t, t));
        for (int d = 0; d < 3; ++d)
          t[d] /= tl;
        frame[1] = t;
        frame[2] = cross<T>(n, t);
      }
    const auto component = constraint_components<T, dim>(frame);
    for (int m = 1; m < dim; ++m)
      if (value_of(frame[m][component[m]]) < 0)
        for (int d = 0; d < dim; ++d)
          frame[m][d] = -frame[m][d];
    return frame;
  }
} // namespace physics::mortar
