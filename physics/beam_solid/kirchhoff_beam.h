// Geometrically exact, torsion-free Kirchhoff-Love beam in 3D (Meier et al.; BEAM_SOLID.md).
//
// Centreline r(xi), xi in [-1, 1], cubic Hermite on each 2-node element with nodal positions and
// (non-unit) nodal tangents as unknowns:
//   r(xi) = H1 r1 + (l/2) H2 t1 + H3 r2 + (l/2) H4 t2,
//   H1 = (2 - 3 xi + xi^3)/4,  H2 = (1 - xi - xi^2 + xi^3)/4,
//   H3 = (2 + 3 xi - xi^3)/4,  H4 = (-1 - xi + xi^2 + xi^3)/4.
// The reference centreline X(xi) is the same interpolation of the nodal reference positions X_i
// and unit tangents T_i; l is its arc length (a fixed point, l = int |X_xi(l)| dxi; the chord for
// straight elements). With J = |X_xi| (ds = J dxi) the stored energy per unit reference length is
//   psi = EA/2 eps^2 + EI/2 (kappa - kappa_0)^2,
//   eps = |r_xi| / J - 1,   kappa = |r_xi x r_xixi| / (J |r_xi|^2),   kappa_0 = |X_xi x X_xixi| / J^3
// (kappa: the rate at which the unit tangent turns per unit reference length; independent of the
// parametrization). For straight references (kappa_0 = 0) the bending term is EI/2 kappa^2, smooth
// at kappa = 0. For curved references, EI/2 (|kappa| - |kappa_0|)^2 is the exact torsion-free
// limit of an isotropic rod: with zero torsional stiffness the cross-section may rotate freely about
// the tangent, and minimizing EI/2 |K - K_0|^2 (material curvature vectors) over that rotation
// leaves the difference of the magnitudes. It is objective (depends on stretch and |kappa| only)
// but carries no torsional moment: a free curved beam has no linear stiffness against an
// out-of-plane load (it would need torsion); an embedded fibre is held there by the solid.
// Residual and tangent are the gradient and Hessian of the element energy, computed with nested
// Sacado forward AD (exact to rounding, nonsymmetric only through external moments).
//
// Unknowns per node (6): the displacement of the position, r - X, then of the tangent, t - T.
// Nodal reference tangents of polylines (gmsh line elements along a curve) are those of the
// circle through the node and its two neighbours, exact on circular arcs (BeamMesh::
// set_reference_geometry).
#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <array>
#include <string>
#include <vector>

namespace physics::beam_solid
{
  /// A beam (or several disjoint fibres, open or closed): 2-node elements through the nodes,
  /// each fibre a simple chain of elements.
  struct BeamMesh
  {
    std::vector<dealii::Point<3>>    nodes;
    std::vector<std::array<int, 2>>  elements;
    /// Unit reference tangent per node and reference arc length per element (set by
    /// set_reference_geometry()).
    std::vector<dealii::Tensor<1, 3>> tangents;
    std::vector<double>               lengths;

    /// The largest angle (degrees) between the chords of two elements meeting at a node: a
    /// polyline must resolve its curve (a C1 beam cannot represent a corner).
    static constexpr double max_turn_angle = 60.0;

    unsigned int n_dofs() const { return 6 * static_cast<unsigned int>(nodes.size()); }
    double       element_length(std::size_t e) const { return lengths.at(e); }
    /// Reference centreline X(xi) of element e and J = |dX/dxi| (ds = J dxi).
    dealii::Point<3> reference_position(std::size_t e, double xi) const;
    double           reference_jacobian(std::size_t e, double xi) const;

    /// Orients the elements of every fibre head to tail, sets the nodal tangents (the chord of a
    /// one-element fibre; at inner nodes the tangent of the circle through the node and its
    /// neighbours, at end nodes that circle's tangent there) and the elements' arc lengths.
    /// Throws std::invalid_argument naming `source` for an element index out of range, a
    /// zero-length element, a node shared by more than two elements, or chords turning by more
    /// than max_turn_angle at a node.
    void set_reference_geometry(const std::string& source);
  };

  /// Beams from a gmsh mesh in the ASCII msh 2.2 format: every 2-node line element (type 1)
  /// becomes a beam element (straight lines or polylines along curves); other elements are
  /// ignored. Throws std::invalid_argument naming `file` for an unreadable file, a file without
  /// line elements, and what set_reference_geometry() rejects.
  BeamMesh read_beam_mesh(const std::string& file);

  /// Straight fibre from a to b with n elements.
  void add_straight_fibre(BeamMesh& mesh, const dealii::Point<3>& a, const dealii::Point<3>& b, int n_elements);

  struct BeamSection
  {
    double EA = 0, EI = 0;
    /// Circular cross-section of radius r: A = pi r^2, I = pi r^4 / 4.
    static BeamSection circular(double youngs_modulus, double radius);
  };

  /// Cubic Hermite shape functions (H1..H4) and their first two xi-derivatives.
  struct HermiteValues
  {
    std::array<double, 4> value, d1, d2;
  };
  HermiteValues hermite(double xi);

  /// Position (or displacement, with displacement unknowns) of the centreline at xi of element
  /// e: weights of the 4 nodal vectors (position 1, tangent 1, position 2, tangent 2), i.e.
  /// H1, (l/2) H2, H3, (l/2) H4.
  std::array<double, 4> centreline_weights(double xi, double length);

  /// Energy, gradient (12) and Hessian (12 x 12, row-major) of one element, unknowns d (12) =
  /// displacements of (r1, t1, r2, t2) from the reference (X1, T1, X2, T2).
  struct ElementDerivatives
  {
    double                energy = 0;
    std::array<double, 12> gradient{};
    std::array<double, 144> hessian{};
  };
  ElementDerivatives element_derivatives(const BeamMesh& mesh, std::size_t e, const BeamSection& section,
                                         const std::array<double, 12>& d);

  /// Potential of a dead moment M about the global z axis at a node: -M atan2(t_y, t_x) of the
  /// current tangent t = T + d_t (planar bending in the x-y plane). Gradient and Hessian w.r.t.
  /// the node's tangent displacement (3).
  struct MomentDerivatives
  {
    std::array<double, 3> gradient{};
    std::array<double, 9> hessian{};
  };
  MomentDerivatives planar_end_moment(const dealii::Tensor<1, 3>& reference_tangent, const std::array<double, 3>& d_t,
                                      double moment);
} // namespace physics::beam_solid
