// Geometrically exact, torsion-free Kirchhoff-Love beam in 3D (Meier et al.; BEAM_SOLID.md).
//
// Centreline r(xi), xi in [-1, 1], cubic Hermite on each straight 2-node reference element of
// length l, with nodal positions and (non-unit) nodal tangents as unknowns:
//   r(xi) = H1 r1 + (l/2) H2 t1 + H3 r2 + (l/2) H4 t2,
//   H1 = (2 - 3 xi + xi^3)/4,  H2 = (1 - xi - xi^2 + xi^3)/4,
//   H3 = (2 + 3 xi - xi^3)/4,  H4 = (-1 - xi + xi^2 + xi^3)/4.
// Reference arc length s = (l/2)(xi + 1), so r' = (2/l) r_xi and r'' = (4/l^2) r_xixi. Stored
// energy per unit reference length
//   psi = EA/2 eps^2 + EI/2 kappa^2,   eps = |r'| - 1,   kappa^2 = |r' x r''|^2 / |r'|^4
// (kappa: the rate at which the unit tangent turns per unit reference length). Writing kappa^2
// instead of kappa keeps psi smooth at kappa = 0; reference configurations are straight
// (kappa_0 = 0). Residual and tangent are the gradient and Hessian of the element energy,
// computed with nested Sacado forward AD (exact to rounding, nonsymmetric only through
// external moments).
//
// Why straight references only: the torsion-free model has no twist, and its only objective
// extension to a curved reference (kappa_0 > 0) is the zero-torsional-stiffness limit of an
// isotropic rod, EI/2 (|kappa| - |kappa_0|)^2. That limit is degenerate: it has no linear
// stiffness against out-of-plane bending of a curved fibre, and a straightened fibre recovers
// |kappa| = |kappa_0| at no cost by coiling into a helix. (Tried: embedded crimped fibres in the
// cube case stall Newton near 1e-4.) Curved fibres need a rod with a twist unknown (Kirchhoff-
// Love with torsion, Meier et al., or Simo-Reissner); not implemented.
//
// Unknowns per node (6): the displacement of the position, r - X, then of the tangent, t - T.
// The nodal reference tangent T is the unit vector along the element chords (straight beams).
#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <array>
#include <string>
#include <vector>

namespace physics::beam_solid
{
  /// A beam (or several disjoint fibres): straight 2-node elements through the nodes.
  struct BeamMesh
  {
    std::vector<dealii::Point<3>>    nodes;
    std::vector<std::array<int, 2>>  elements;
    /// Unit reference tangent per node (set by check_and_set_tangents()).
    std::vector<dealii::Tensor<1, 3>> tangents;

    unsigned int n_dofs() const { return 6 * static_cast<unsigned int>(nodes.size()); }
    double       element_length(std::size_t e) const;
    /// Orients the elements of every fibre head to tail and sets the nodal tangents from the
    /// chords. Throws std::invalid_argument naming `source` for an element index out of range, a
    /// zero-length element, a node in no element or in more than two (a branch), and a kink
    /// between the elements at a node (the reference beam must be straight there: the
    /// torsion-free model is defined for straight reference fibres).
    void check_and_set_tangents(const std::string& source);
  };

  /// Beams from a gmsh mesh in the ASCII msh 2.2 format: every 2-node line element (type 1)
  /// becomes a beam element; other elements are ignored. Throws std::invalid_argument naming
  /// `name` (the user's file, e.g. the .geo gmsh meshed into `file`; default `file`) for an
  /// unreadable file, a file without line elements, and what check_and_set_tangents() rejects.
  BeamMesh read_beam_mesh(const std::string& file, const std::string& name = "");

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
