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

  double BeamMesh::element_length(std::size_t e) const
  {
    return nodes[elements[e][1]].distance(nodes[elements[e][0]]);
  }

  void BeamMesh::check_and_set_tangents(const std::string& source)
  {
    auto fail = [&](const std::string& what) { throw std::invalid_argument(source + ": " + what); };
    auto node = [&](std::size_t n) {
      std::ostringstream where;
      where << "node " << n << " (" << nodes[n] << ")";
      return where.str();
    };
    std::vector<std::vector<std::size_t>> at_node(nodes.size()); // elements at each node
    for (std::size_t e = 0; e < elements.size(); ++e)
      {
        for (const int n : elements[e])
          if (n < 0 || n >= static_cast<int>(nodes.size()))
            fail("beam element " + std::to_string(e) + " refers to node " + std::to_string(n) + ", but there are " +
                 std::to_string(nodes.size()));
        if (!(element_length(e) > 1e-12))
          fail("beam element " + std::to_string(e) + " has zero length");
        for (const int n : elements[e])
          at_node[n].push_back(e);
      }
    for (std::size_t n = 0; n < nodes.size(); ++n)
      if (at_node[n].empty())
        fail("beam " + node(n) + " belongs to no element");
      else if (at_node[n].size() > 2)
        fail("beam branches at " + node(n) + ": " + std::to_string(at_node[n].size()) +
             " elements meet there (every fibre must be a simple line)");

    // Orient every fibre head to tail (gmsh may list a line's elements in either direction; the
    // nodal tangent is shared by both elements at a node, so they must agree): walk each chain
    // from an end node, then closed loops from any node.
    std::vector<bool> oriented(elements.size(), false);
    auto              walk = [&](int n) {
      while (true)
        {
          const auto next = std::find_if(at_node[n].begin(), at_node[n].end(), [&](std::size_t k) { return !oriented[k]; });
          if (next == at_node[n].end())
            return;
          if (elements[*next][0] != n)
            std::swap(elements[*next][0], elements[*next][1]);
          oriented[*next] = true;
          n               = elements[*next][1];
        }
    };
    for (std::size_t n = 0; n < nodes.size(); ++n)
      if (at_node[n].size() == 1)
        walk(static_cast<int>(n));
    for (std::size_t e = 0; e < elements.size(); ++e)
      if (!oriented[e])
        walk(elements[e][0]);

    // The reference fibre is straight: the unit chord is the nodal tangent of both its nodes.
    tangents.assign(nodes.size(), Tensor<1, 3>());
    std::vector<bool> set(nodes.size(), false);
    for (std::size_t e = 0; e < elements.size(); ++e)
      {
        const Tensor<1, 3> chord = (nodes[elements[e][1]] - nodes[elements[e][0]]) / element_length(e);
        for (const int n : elements[e])
          {
            if (set[n] && (tangents[n] - chord).norm() > 1e-8)
              {
                const double angle = 2 * std::asin(std::min(1.0, 0.5 * (tangents[n] - chord).norm())) * 180 / M_PI;
                std::ostringstream degrees;
                degrees.precision(3);
                degrees << angle;
                fail("beam kinks by " + degrees.str() + " degrees at " + node(n) +
                     " (the torsion-free beam needs straight reference fibres: elements collinear where they "
                     "meet; curved fibres need a rod with torsional stiffness, not implemented)");
              }
            tangents[n] = chord;
            set[n]      = true;
          }
      }
  }

  BeamMesh read_beam_mesh(const std::string& file, const std::string& name)
  {
    const std::string source = name.empty() ? file : name;
    std::ifstream     in(file);
    if (!in)
      throw std::invalid_argument(source + ": cannot open the beam mesh");
    BeamMesh                mesh;
    std::map<long, int>     index_of_node;
    std::string             line;
    auto fail = [&](const std::string& what) { throw std::invalid_argument(source + ": " + what); };
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
                mesh.elements.push_back({{index_of_node[a], index_of_node[b]}});
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
    used.check_and_set_tangents(source);
    return used;
  }

  void add_straight_fibre(BeamMesh& mesh, const Point<3>& a, const Point<3>& b, int n_elements)
  {
    const int first = static_cast<int>(mesh.nodes.size());
    for (int i = 0; i <= n_elements; ++i)
      mesh.nodes.push_back(a + (b - a) * (static_cast<double>(i) / n_elements));
    for (int i = 0; i < n_elements; ++i)
      mesh.elements.push_back({{first + i, first + i + 1}});
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
    const double l  = mesh.element_length(e);
    const auto   n0 = mesh.elements[e][0], n1 = mesh.elements[e][1];
    // Nodal vectors (r1, t1, r2, t2) as AD variables.
    const auto                     x = seed<n_element_dofs>(d);
    std::array<std::array<Outer, 3>, 4> nodal;
    const std::array<Tensor<1, 3>, 4> reference{{Tensor<1, 3>(mesh.nodes[n0]), mesh.tangents[n0],
                                                 Tensor<1, 3>(mesh.nodes[n1]), mesh.tangents[n1]}};
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < 3; ++c)
        nodal[a][c] = reference[a][c] + x[3 * a + c];

    const dealii::QGauss<1> gauss(6); // on [0, 1]
    Outer                   energy = 0.0;
    for (unsigned int q = 0; q < gauss.size(); ++q)
      {
        const double xi = 2 * gauss.point(q)[0] - 1;
        const auto   h  = hermite(xi);
        // r' = (2/l) r_xi, r'' = (4/l^2) r_xixi; the tangent weights carry l/2.
        const std::array<double, 4> w1{{2 / l * h.d1[0], h.d1[1], 2 / l * h.d1[2], h.d1[3]}};
        const std::array<double, 4> w2{{4 / (l * l) * h.d2[0], 2 / l * h.d2[1], 4 / (l * l) * h.d2[2], 2 / l * h.d2[3]}};
        std::array<Outer, 3> r1, r2;
        for (int c = 0; c < 3; ++c)
          {
            r1[c] = 0.0;
            r2[c] = 0.0;
            for (int a = 0; a < 4; ++a)
              {
                r1[c] += w1[a] * nodal[a][c];
                r2[c] += w2[a] * nodal[a][c];
              }
          }
        const Outer norm2 = r1[0] * r1[0] + r1[1] * r1[1] + r1[2] * r1[2];
        const Outer eps   = sqrt(norm2) - 1.0;
        const Outer c0 = r1[1] * r2[2] - r1[2] * r2[1], c1 = r1[2] * r2[0] - r1[0] * r2[2],
                    c2 = r1[0] * r2[1] - r1[1] * r2[0];
        const Outer kappa2 = (c0 * c0 + c1 * c1 + c2 * c2) / (norm2 * norm2);
        // ds = (l/2) dxi; Gauss weights on [0,1] sum to 1, on [-1,1] to 2: factor l overall.
        energy += (0.5 * section.EA * eps * eps + 0.5 * section.EI * kappa2) * (l * gauss.weight(q));
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
