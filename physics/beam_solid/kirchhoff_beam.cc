#include "beam_solid/kirchhoff_beam.h"

#include <deal.II/base/quadrature_lib.h>

#include <Sacado.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace physics::beam_solid
{
  using dealii::Point;
  using dealii::Tensor;

  namespace
  {
    /// Reference nodal vectors (X1, (l/2) T1, X2, (l/2) T2) of element e for arc length l.
    std::array<Tensor<1, 3>, 4> reference_vectors(const BeamMesh& mesh, std::size_t e, double l)
    {
      const auto n0 = mesh.elements[e][0], n1 = mesh.elements[e][1];
      return {{Tensor<1, 3>(mesh.nodes[n0]), 0.5 * l * mesh.tangents[n0], Tensor<1, 3>(mesh.nodes[n1]),
               0.5 * l * mesh.tangents[n1]}};
    }

    /// dX/dxi and d2X/dxi2 of the reference centreline.
    std::pair<Tensor<1, 3>, Tensor<1, 3>> reference_derivatives(const std::array<Tensor<1, 3>, 4>& v, double xi)
    {
      const auto   h = hermite(xi);
      Tensor<1, 3> d1, d2;
      for (int a = 0; a < 4; ++a)
        {
          d1 += h.d1[a] * v[a];
          d2 += h.d2[a] * v[a];
        }
      return {d1, d2};
    }

    /// Arc length of the Hermite curve through the element's nodes with its nodal unit tangents:
    /// the fixed point of l = int_{-1}^{1} |X_xi(l)| dxi (the tangents are scaled by l/2, so l
    /// enters the curve). The chord for straight elements; a contraction for curves whose turn
    /// per element is bounded (max_turn_angle).
    double arc_length(const BeamMesh& mesh, std::size_t e)
    {
      const dealii::QGauss<1> gauss(8);
      const double            chord = mesh.nodes[mesh.elements[e][1]].distance(mesh.nodes[mesh.elements[e][0]]);
      double                  l     = chord;
      for (int it = 0; it < 100; ++it)
        {
          const auto v    = reference_vectors(mesh, e, l);
          double     next = 0;
          for (unsigned int q = 0; q < gauss.size(); ++q)
            next += 2 * gauss.weight(q) * reference_derivatives(v, 2 * gauss.point(q)[0] - 1).first.norm();
          const bool converged = std::abs(next - l) <= 1e-15 * chord;
          l                    = next;
          if (converged)
            break;
        }
      return l;
    }

    /// Unit tangent at node i of a polyline (the nodes of one fibre in order) through points on a
    /// smooth curve: the derivative at node i of the polynomial through up to 5 consecutive nodes
    /// (centred where the fibre allows, wrapping around closed loops), parametrized by cumulative
    /// chord length. Its direction is that of the curve's tangent to O(h^4) (the parametrization
    /// only changes the length of the derivative); with 3 nodes it is the tangent of the circle
    /// through them, |b|^2 a + |a|^2 b for the chords a, b; with 2 the chord.
    Tensor<1, 3> polyline_tangent(const std::vector<Point<3>>& nodes, const std::vector<int>& chain, bool closed, int i)
    {
      const int m     = static_cast<int>(chain.size()) - (closed ? 1 : 0);
      const int width = std::min(5, m);
      // Stencil positions k = first .. first + width - 1 (indices into the chain, modulo m when
      // closed), and the chord-length parameter s_k with s_i = 0.
      const int first = closed ? i - width / 2 : std::clamp(i - width / 2, 0, m - width);
      auto      node  = [&](int k) { return nodes[chain[((k % m) + m) % m]]; };
      std::vector<double> s(width, 0.0);
      for (int k = i - first + 1; k < width; ++k)
        s[k] = s[k - 1] + node(first + k).distance(node(first + k - 1));
      for (int k = i - first - 1; k >= 0; --k)
        s[k] = s[k + 1] - node(first + k + 1).distance(node(first + k));
      // d/ds of the Lagrange basis at s_i = 0: L_i' = sum_{j != i} 1 / (s_i - s_j) and, for k != i,
      // L_k' = 1 / (s_k - s_i) prod_{j != i, k} (s_i - s_j) / (s_k - s_j).
      const int    c = i - first;
      Tensor<1, 3> t;
      for (int k = 0; k < width; ++k)
        {
          double weight = 0;
          if (k == c)
            for (int j = 0; j < width; ++j)
              weight += j == c ? 0.0 : 1.0 / (s[c] - s[j]);
          else
            {
              weight = 1.0 / (s[k] - s[c]);
              for (int j = 0; j < width; ++j)
                if (j != c && j != k)
                  weight *= (s[c] - s[j]) / (s[k] - s[j]);
            }
          t += weight * Tensor<1, 3>(node(first + k));
        }
      return t / t.norm();
    }
  } // namespace

  Point<3> BeamMesh::reference_position(std::size_t e, double xi) const
  {
    const auto w = centreline_weights(xi, element_length(e));
    const auto n = elements[e];
    return Point<3>(w[0] * nodes[n[0]] + w[1] * tangents[n[0]] + w[2] * nodes[n[1]] + w[3] * tangents[n[1]]);
  }

  double BeamMesh::reference_jacobian(std::size_t e, double xi) const
  {
    return reference_derivatives(reference_vectors(*this, e, element_length(e)), xi).first.norm();
  }

  void BeamMesh::set_reference_geometry(const std::string& source)
  {
    auto fail = [&](const std::string& what) { throw std::invalid_argument(source + ": " + what); };
    // Elements at each node; a fibre is a simple chain.
    std::vector<std::vector<std::size_t>> at_node(nodes.size());
    for (std::size_t e = 0; e < elements.size(); ++e)
      {
        for (const int n : elements[e])
          if (n < 0 || n >= static_cast<int>(nodes.size()))
            fail("beam element " + std::to_string(e) + " refers to node " + std::to_string(n) + ", but there are " +
                 std::to_string(nodes.size()));
        if (!(nodes[elements[e][1]].distance(nodes[elements[e][0]]) > 1e-12))
          fail("beam element " + std::to_string(e) + " has zero length");
        for (const int n : elements[e])
          at_node[n].push_back(e);
      }
    for (std::size_t n = 0; n < nodes.size(); ++n)
      if (at_node[n].empty())
        fail("beam node " + std::to_string(n) + " belongs to no element");
      else if (at_node[n].size() > 2)
        fail("beam branches at node " + std::to_string(n) + " (" + std::to_string(at_node[n].size()) +
             " elements meet there; every fibre must be a simple curve)");

    // Orient every fibre head to tail (gmsh may list a curve's elements in either direction):
    // walk each chain from an end node (open fibres first, then closed loops from any node),
    // collecting its nodes in order (a closed loop repeats its first node at the end).
    std::vector<bool>             oriented(elements.size(), false);
    std::vector<std::vector<int>> fibres;
    auto                          walk = [&](int n) {
      std::vector<int> chain{n};
      while (true)
        {
          const auto next = std::find_if(at_node[n].begin(), at_node[n].end(), [&](std::size_t k) { return !oriented[k]; });
          if (next == at_node[n].end())
            break;
          const std::size_t e = *next;
          if (elements[e][0] != n)
            std::swap(elements[e][0], elements[e][1]);
          oriented[e] = true;
          n           = elements[e][1];
          chain.push_back(n);
        }
      fibres.push_back(chain);
    };
    for (std::size_t n = 0; n < nodes.size(); ++n)
      if (at_node[n].size() == 1 && !oriented[at_node[n][0]])
        walk(static_cast<int>(n));
    for (std::size_t e = 0; e < elements.size(); ++e)
      if (!oriented[e])
        walk(elements[e][0]);

    tangents.assign(nodes.size(), Tensor<1, 3>());
    for (const auto& chain : fibres)
      {
        const bool closed = chain.size() > 2 && chain.front() == chain.back();
        const int  m      = static_cast<int>(chain.size()) - (closed ? 1 : 0); // distinct nodes
        for (int i = 0; i < m; ++i)
          {
            if (closed || (i > 0 && i + 1 < m))
              {
                const int          p = chain[(i + m - 1) % m], q = chain[(i + 1) % m], n = chain[i];
                const Tensor<1, 3> a = nodes[n] - nodes[p], b = nodes[q] - nodes[n];
                const double angle = std::acos(std::clamp(a * b / (a.norm() * b.norm()), -1.0, 1.0)) * 180 / M_PI;
                if (angle > max_turn_angle)
                  fail("beam turns by " + std::to_string(static_cast<int>(std::round(angle))) + " degrees at node " +
                       std::to_string(n) + " (at most " + std::to_string(static_cast<int>(max_turn_angle)) +
                       "; a C1 beam needs a smooth curve: refine the curve's mesh)");
              }
            tangents[chain[i]] = polyline_tangent(nodes, chain, closed, i);
          }
      }
    lengths.resize(elements.size());
    for (std::size_t e = 0; e < elements.size(); ++e)
      lengths[e] = arc_length(*this, e);
  }

  BeamMesh read_beam_mesh(const std::string& file)
  {
    std::ifstream in(file);
    if (!in)
      throw std::invalid_argument(file + ": cannot open the beam mesh");
    BeamMesh                mesh;
    std::map<long, int>     index_of_node;
    std::string             line;
    auto fail = [&](const std::string& what) { throw std::invalid_argument(file + ": " + what); };
    while (std::getline(in, line))
      {
        if (line.rfind("$MeshFormat", 0) == 0)
          {
            double version = 0;
            in >> version;
            if (version < 2 || version >= 3)
              fail("expected the msh 2.2 ASCII format (gmsh -format msh22), got version " + std::to_string(version));
          }
        else if (line.rfind("$Nodes", 0) == 0)
          {
            long n = 0;
            in >> n;
            for (long i = 0; i < n; ++i)
              {
                long     id;
                Point<3> x;
                if (!(in >> id >> x[0] >> x[1] >> x[2]))
                  fail("unreadable node " + std::to_string(i));
                index_of_node[id] = static_cast<int>(mesh.nodes.size());
                mesh.nodes.push_back(x);
              }
          }
        else if (line.rfind("$Elements", 0) == 0)
          {
            long n = 0;
            in >> n;
            std::getline(in, line);
            for (long i = 0; i < n && std::getline(in, line); ++i)
              {
                std::istringstream fields(line);
                long               id, type, n_tags, tag;
                if (!(fields >> id >> type >> n_tags))
                  fail("unreadable element line '" + line + "'");
                for (long t = 0; t < n_tags; ++t)
                  fields >> tag;
                if (type != 1)
                  continue;
                long a, b;
                if (!(fields >> a >> b) || !index_of_node.count(a) || !index_of_node.count(b))
                  fail("line element " + std::to_string(id) + " refers to unknown nodes");
                mesh.elements.push_back({index_of_node[a], index_of_node[b]});
              }
          }
      }
    if (mesh.elements.empty())
      fail("no 2-node line elements (beams)");
    // Keep only the nodes the beams use (gmsh also writes the geometry's other points).
    std::vector<int> renumber(mesh.nodes.size(), -1);
    BeamMesh         used;
    for (auto& element : mesh.elements)
      for (int& n : element)
        {
          if (renumber[n] < 0)
            {
              renumber[n] = static_cast<int>(used.nodes.size());
              used.nodes.push_back(mesh.nodes[n]);
            }
          n = renumber[n];
        }
    used.elements = mesh.elements;
    used.set_reference_geometry(file);
    return used;
  }

  void add_straight_fibre(BeamMesh& mesh, const Point<3>& a, const Point<3>& b, int n_elements)
  {
    const int first = static_cast<int>(mesh.nodes.size());
    for (int i = 0; i <= n_elements; ++i)
      mesh.nodes.push_back(a + (b - a) * (static_cast<double>(i) / n_elements));
    for (int i = 0; i < n_elements; ++i)
      mesh.elements.push_back({first + i, first + i + 1});
  }

  BeamSection BeamSection::circular(double youngs_modulus, double radius)
  {
    BeamSection s;
    s.EA = youngs_modulus * M_PI * radius * radius;
    s.EI = youngs_modulus * M_PI * std::pow(radius, 4) / 4;
    return s;
  }

  HermiteValues hermite(double xi)
  {
    HermiteValues h;
    h.value = {{(2 - 3 * xi + xi * xi * xi) / 4, (1 - xi - xi * xi + xi * xi * xi) / 4,
                (2 + 3 * xi - xi * xi * xi) / 4, (-1 - xi + xi * xi + xi * xi * xi) / 4}};
    h.d1    = {{(-3 + 3 * xi * xi) / 4, (-1 - 2 * xi + 3 * xi * xi) / 4, (3 - 3 * xi * xi) / 4,
             (-1 + 2 * xi + 3 * xi * xi) / 4}};
    h.d2    = {{6 * xi / 4, (-2 + 6 * xi) / 4, -6 * xi / 4, (2 + 6 * xi) / 4}};
    return h;
  }

  std::array<double, 4> centreline_weights(double xi, double length)
  {
    const auto h = hermite(xi);
    return {{h.value[0], 0.5 * length * h.value[1], h.value[2], 0.5 * length * h.value[3]}};
  }

  namespace
  {
    constexpr int n_element_dofs = 12;
    using Inner                  = Sacado::Fad::SFad<double, n_element_dofs>;
    using Outer                  = Sacado::Fad::SFad<Inner, n_element_dofs>;

    /// Nested AD variables: value, first derivatives (inner) and second derivatives (outer).
    template <int n>
    std::array<Sacado::Fad::SFad<Sacado::Fad::SFad<double, n>, n>, n> seed(const std::array<double, n>& x)
    {
      using I = Sacado::Fad::SFad<double, n>;
      std::array<Sacado::Fad::SFad<I, n>, n> v;
      for (int i = 0; i < n; ++i)
        {
          v[i] = Sacado::Fad::SFad<I, n>(n, i, I(n, i, x[i]));
        }
      return v;
    }
  } // namespace

  ElementDerivatives element_derivatives(const BeamMesh& mesh, std::size_t e, const BeamSection& section,
                                         const std::array<double, 12>& d)
  {
    const double l         = mesh.element_length(e);
    const auto   reference = reference_vectors(mesh, e, l); // (X1, (l/2) T1, X2, (l/2) T2)
    // Current nodal vectors (r1, (l/2) t1, r2, (l/2) t2) as AD variables.
    const auto                          x = seed<n_element_dofs>(d);
    std::array<std::array<Outer, 3>, 4> nodal;
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < 3; ++c)
        nodal[a][c] = reference[a][c] + (a % 2 == 1 ? 0.5 * l : 1.0) * x[3 * a + c];

    const dealii::QGauss<1> gauss(6); // on [0, 1]
    Outer                   energy = 0.0;
    for (unsigned int q = 0; q < gauss.size(); ++q)
      {
        const double xi = 2 * gauss.point(q)[0] - 1;
        const auto   h  = hermite(xi);
        // Reference: J = |X_xi| and the reference curvature kappa_0 = |X_xi x X_xixi| / J^3.
        const auto [X1, X2]       = reference_derivatives(reference, xi);
        const double J            = X1.norm();
        const double kappa_0      = cross_product_3d(X1, X2).norm() / (J * J * J);
        const bool   curved       = kappa_0 * l > 1e-12;
        std::array<Outer, 3> r1, r2; // r_xi, r_xixi
        for (int c = 0; c < 3; ++c)
          {
            r1[c] = 0.0;
            r2[c] = 0.0;
            for (int a = 0; a < 4; ++a)
              {
                r1[c] += h.d1[a] * nodal[a][c];
                r2[c] += h.d2[a] * nodal[a][c];
              }
          }
        const Outer norm2 = r1[0] * r1[0] + r1[1] * r1[1] + r1[2] * r1[2];
        const Outer eps   = sqrt(norm2) / J - 1.0;
        const Outer c0 = r1[1] * r2[2] - r1[2] * r2[1], c1 = r1[2] * r2[0] - r1[0] * r2[2],
                    c2 = r1[0] * r2[1] - r1[1] * r2[0];
        const Outer kappa2  = (c0 * c0 + c1 * c1 + c2 * c2) / (J * J * norm2 * norm2);
        // (kappa - kappa_0)^2 = kappa^2 - 2 kappa_0 kappa + kappa_0^2; without the square root
        // when the reference is straight (smooth at kappa = 0).
        const Outer bending = curved ? kappa2 - 2 * kappa_0 * sqrt(kappa2) + kappa_0 * kappa_0 : kappa2;
        // ds = J dxi; Gauss weights on [0, 1] sum to 1, on [-1, 1] to 2.
        energy += (0.5 * section.EA * eps * eps + 0.5 * section.EI * bending) * (2 * J * gauss.weight(q));
      }
    ElementDerivatives result;
    result.energy = energy.val().val();
    for (int i = 0; i < n_element_dofs; ++i)
      {
        result.gradient[i] = energy.dx(i).val();
        for (int j = 0; j < n_element_dofs; ++j)
          result.hessian[i * n_element_dofs + j] = energy.dx(i).dx(j);
      }
    return result;
  }

  MomentDerivatives planar_end_moment(const Tensor<1, 3>& reference_tangent, const std::array<double, 3>& d_t,
                                      double moment)
  {
    const auto        x = seed<3>(d_t);
    using O           = Sacado::Fad::SFad<Sacado::Fad::SFad<double, 3>, 3>;
    const O tx        = reference_tangent[0] + x[0];
    const O ty        = reference_tangent[1] + x[1];
    const O potential = -moment * atan2(ty, tx);
    MomentDerivatives result;
    for (int i = 0; i < 3; ++i)
      {
        result.gradient[i] = potential.dx(i).val();
        for (int j = 0; j < 3; ++j)
          result.hessian[3 * i + j] = potential.dx(i).dx(j);
      }
    return result;
  }
} // namespace physics::beam_solid
