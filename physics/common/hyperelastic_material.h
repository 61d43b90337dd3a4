// Hyperelastic materials of the common physics layer (used by contact, beam/solid and FSI):
// Saint Venant-Kirchhoff and compressible Neo-Hooke, written in the reference configuration.
//
// Given the deformation gradient F, with C = F^T F, E = (C - I)/2, J = det F, the second
// Piola-Kirchhoff stress S = dpsi/dE and the material tangent CC = dS/dE (= 2 dS/dC), which the
// Newton method needs for its consistent linearization:
//   Saint Venant-Kirchhoff  psi = lambda/2 (tr E)^2 + mu E:E
//                           S   = lambda tr(E) I + 2 mu E,      CC = lambda I(x)I + 2 mu II
//   Neo-Hooke (compressible) psi = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2
//                           S   = mu (I - C^-1) + lambda ln J C^-1
//                           CC  = lambda C^-1(x)C^-1 + 2 (mu - lambda ln J) d(C^-1)
//   with d(C^-1)_IJKL = (C^-1_IK C^-1_JL + C^-1_IL C^-1_JK)/2.
// Both reduce to linear elasticity (Lame lambda, mu) for small strains; the tangents are checked
// against finite differences of S in tests/test_materials.cc.
#pragma once

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <memory>
#include <string>

namespace physics
{
  /// Lame parameters from Young's modulus and Poisson's ratio; throws std::invalid_argument
  /// naming the offending value (E > 0, -1 < nu < 0.5 expected).
  struct LameParameters
  {
    double                lambda = 0.0, mu = 0.0;
    static LameParameters from_young_poisson(double youngs_modulus, double poisson_ratio);
  };

  template <int dim>
  struct StressAndTangent
  {
    dealii::SymmetricTensor<2, dim> S;  ///< second Piola-Kirchhoff stress
    dealii::SymmetricTensor<4, dim> CC; ///< dS/dE
  };

  template <int dim>
  class HyperelasticMaterial
  {
  public:
    explicit HyperelasticMaterial(const LameParameters& lame)
        : lame_(lame)
    {
    }
    virtual ~HyperelasticMaterial() = default;

    /// Strain energy density psi(F) per unit reference volume.
    virtual double energy(const dealii::Tensor<2, dim>& F) const = 0;
    /// S and dS/dE at F. Throws std::domain_error if det F <= 0 (inverted element).
    virtual StressAndTangent<dim> stress_and_tangent(const dealii::Tensor<2, dim>& F) const = 0;

    const LameParameters& lame() const { return lame_; }

  protected:
    LameParameters lame_;
  };

  template <int dim>
  class SaintVenantKirchhoff : public HyperelasticMaterial<dim>
  {
  public:
    using HyperelasticMaterial<dim>::HyperelasticMaterial;
    double                energy(const dealii::Tensor<2, dim>& F) const override;
    StressAndTangent<dim> stress_and_tangent(const dealii::Tensor<2, dim>& F) const override;
  };

  template <int dim>
  class NeoHooke : public HyperelasticMaterial<dim>
  {
  public:
    using HyperelasticMaterial<dim>::HyperelasticMaterial;
    double                energy(const dealii::Tensor<2, dim>& F) const override;
    StressAndTangent<dim> stress_and_tangent(const dealii::Tensor<2, dim>& F) const override;
  };

  /// "SaintVenantKirchhoff" or "NeoHooke" (the names parameter files use); throws
  /// std::invalid_argument naming the unknown law and the known ones.
  template <int dim>
  std::unique_ptr<HyperelasticMaterial<dim>> make_material(const std::string&    law,
                                                           const LameParameters& lame);
} // namespace physics
