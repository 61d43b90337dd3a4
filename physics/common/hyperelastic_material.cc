#include "hyperelastic_material.h"

#include <deal.II/base/symmetric_tensor.h>

#include <cmath>
#include <stdexcept>

namespace physics
{
  using dealii::SymmetricTensor;
  using dealii::Tensor;

  LameParameters LameParameters::from_young_poisson(double E, double nu)
  {
    if (!(E > 0.0))
      throw std::invalid_argument("Young's modulus is " + std::to_string(E) + ", expected a positive value");
    if (!(nu > -1.0 && nu < 0.5))
      throw std::invalid_argument("Poisson's ratio is " + std::to_string(nu) + ", expected -1 < nu < 0.5");
    LameParameters p;
    p.lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    p.mu     = E / (2.0 * (1.0 + nu));
    return p;
  }

  namespace
  {
    template <int dim>
    SymmetricTensor<2, dim> right_cauchy_green(const Tensor<2, dim>& F)
    {
      return dealii::symmetrize(dealii::transpose(F) * F);
    }

    template <int dim>
    double checked_determinant(const Tensor<2, dim>& F)
    {
      const double J = dealii::determinant(F);
      if (!(J > 0.0))
        throw std::domain_error("deformation gradient with det F = " + std::to_string(J) +
                                " (inverted or degenerate element)");
      return J;
    }
  } // namespace

  template <int dim>
  double SaintVenantKirchhoff<dim>::energy(const Tensor<2, dim>& F) const
  {
    const auto  E = 0.5 * (right_cauchy_green(F) - dealii::unit_symmetric_tensor<dim>());
    const auto& l = this->lame_;
    return 0.5 * l.lambda * dealii::trace(E) * dealii::trace(E) + l.mu * (E * E);
  }

  template <int dim>
  StressAndTangent<dim> SaintVenantKirchhoff<dim>::stress_and_tangent(const Tensor<2, dim>& F) const
  {
    const auto            I = dealii::unit_symmetric_tensor<dim>();
    const auto            E = 0.5 * (right_cauchy_green(F) - I);
    const auto&           l = this->lame_;
    StressAndTangent<dim> r;
    r.S  = l.lambda * dealii::trace(E) * I + 2.0 * l.mu * E;
    r.CC = l.lambda * dealii::outer_product(I, I) + 2.0 * l.mu * dealii::identity_tensor<dim>();
    return r;
  }

  template <int dim>
  double NeoHooke<dim>::energy(const Tensor<2, dim>& F) const
  {
    const double J   = checked_determinant(F);
    const auto&  l   = this->lame_;
    const double lnJ = std::log(J);
    return 0.5 * l.mu * (dealii::trace(right_cauchy_green(F)) - dim) - l.mu * lnJ +
           0.5 * l.lambda * lnJ * lnJ;
  }

  template <int dim>
  StressAndTangent<dim> NeoHooke<dim>::stress_and_tangent(const Tensor<2, dim>& F) const
  {
    const double          J    = checked_determinant(F);
    const double          lnJ  = std::log(J);
    const auto            I    = dealii::unit_symmetric_tensor<dim>();
    const auto            Cinv = dealii::invert(right_cauchy_green(F));
    const auto&           l    = this->lame_;
    StressAndTangent<dim> r;
    r.S = l.mu * (I - Cinv) + l.lambda * lnJ * Cinv;
    // d(C^-1)/dC = -(C^-1_IK C^-1_JL + C^-1_IL C^-1_JK)/2; CC = 2 dS/dC.
    SymmetricTensor<4, dim> dCinv;
    for (unsigned int i = 0; i < dim; ++i)
      for (unsigned int j = i; j < dim; ++j)
        for (unsigned int k = 0; k < dim; ++k)
          for (unsigned int m = k; m < dim; ++m)
            dCinv[i][j][k][m] = 0.5 * (Cinv[i][k] * Cinv[j][m] + Cinv[i][m] * Cinv[j][k]);
    r.CC = l.lambda * dealii::outer_product(Cinv, Cinv) + 2.0 * (l.mu - l.lambda * lnJ) * dCinv;
    return r;
  }

  template <int dim>
  std::unique_ptr<HyperelasticMaterial<dim>> make_material(const std::string& law, const LameParameters& lame)
  {
    if (law == "SaintVenantKirchhoff")
      return std::make_unique<SaintVenantKirchhoff<dim>>(lame);
    if (law == "NeoHooke")
      return std::make_unique<NeoHooke<dim>>(lame);
    throw std::invalid_argument("material law '" + law +
                                "' is unknown (expected SaintVenantKirchhoff or NeoHooke)");
  }

  template class SaintVenantKirchhoff<2>;
  template class SaintVenantKirchhoff<3>;
  template class NeoHooke<2>;
  template class NeoHooke<3>;
  template std::unique_ptr<HyperelasticMaterial<2>> make_material<2>(const std::string&,
                                                                     const LameParameters&);
  template std::unique_ptr<HyperelasticMaterial<3>> make_material<3>(const std::string&,
                                                                     const LameParameters&);
} // namespace physics
