// Hyperelastic materials: the tangent dS/dE is the derivative of S (central finite differences),
// S is the derivative of the energy, and both laws reduce to linear elasticity at F = I.
#include "common/hyperelastic_material.h"

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <gtest/gtest.h>

#include <random>

using namespace physics;
using dealii::SymmetricTensor;
using dealii::Tensor;

namespace
{
  template <int dim>
  Tensor<2, dim> random_deformation_gradient(std::mt19937& rng, double amplitude)
  {
    std::uniform_real_distribution<double> u(-amplitude, amplitude);
    Tensor<2, dim>                         F;
    for (unsigned int i = 0; i < dim; ++i)
      for (unsigned int j = 0; j < dim; ++j)
        F[i][j] = (i == j ? 1.0 : 0.0) + u(rng);
    return F;
  }

  /// A deformation gradient whose Green-Lagrange strain is E: F = sqrt(2E + I) (symmetric).
  template <int dim>
  Tensor<2, dim> from_green_lagrange(const SymmetricTensor<2, dim>& E)
  {
    const auto     C     = 2.0 * E + dealii::unit_symmetric_tensor<dim>();
    const auto     eigen = dealii::eigenvectors(C);
    Tensor<2, dim> F;
    for (const auto& [value, vector] : eigen)
      F += std::sqrt(value) * dealii::outer_product(vector, vector);
    return F;
  }

  template <int dim>
  void check_tangent_and_stress(const std::string& law)
  {
    const auto   lame     = LameParameters::from_young_poisson(10.0e6, 0.3);
    const auto   material = make_material<dim>(law, lame);
    std::mt19937 rng(42);
    for (int sample = 0; sample < 20; ++sample)
      {
        const Tensor<2, dim> F = random_deformation_gradient<dim>(rng, 0.3);
        const auto           E =
            0.5 * (dealii::symmetrize(dealii::transpose(F) * F) - dealii::unit_symmetric_tensor<dim>());
        const auto   r = material->stress_and_tangent(F);
        const double h = 1e-6;
        for (unsigned int k = 0; k < dim; ++k)
          for (unsigned int l = k; l < dim; ++l)
            {
              SymmetricTensor<2, dim> dE;
              dE[k][l]         = 1.0; // symmetric unit direction
              const auto Sp    = material->stress_and_tangent(from_green_lagrange<dim>(E + h * dE)).S;
              const auto Sm    = material->stress_and_tangent(from_green_lagrange<dim>(E - h * dE)).S;
              const auto fd    = (Sp - Sm) / (2.0 * h);
              const auto exact = r.CC * dE;
              EXPECT_LT((fd - exact).norm(), 1e-6 * r.CC.norm())
                  << law << " dim " << dim << " sample " << sample;
              // S = dpsi/dE: energy difference along dE equals S : dE.
              const double ep = material->energy(from_green_lagrange<dim>(E + h * dE));
              const double em = material->energy(from_green_lagrange<dim>(E - h * dE));
              EXPECT_NEAR((ep - em) / (2.0 * h), r.S * dE, 1e-6 * (r.S.norm() + lame.mu)) << law;
            }
      }
    // Small-strain limit: S = 0 and CC = lambda I(x)I + 2 mu II at F = I.
    const auto at_rest = material->stress_and_tangent(dealii::unit_symmetric_tensor<dim>());
    EXPECT_LT(at_rest.S.norm(), 1e-12 * lame.mu);
    const auto linear = lame.lambda * dealii::outer_product(dealii::unit_symmetric_tensor<dim>(),
                                                            dealii::unit_symmetric_tensor<dim>()) +
                        2.0 * lame.mu * dealii::identity_tensor<dim>();
    EXPECT_LT((at_rest.CC - linear).norm(), 1e-12 * linear.norm()) << law;
  }
} // namespace

TEST(HyperelasticMaterial, SaintVenantKirchhoffTangentIsConsistent)
{
  check_tangent_and_stress<2>("SaintVenantKirchhoff");
  check_tangent_and_stress<3>("SaintVenantKirchhoff");
}

TEST(HyperelasticMaterial, NeoHookeTangentIsConsistent)
{
  check_tangent_and_stress<2>("NeoHooke");
  check_tangent_and_stress<3>("NeoHooke");
}

TEST(HyperelasticMaterial, BadInputIsRejectedWithAMessage)
{
  EXPECT_THROW(LameParameters::from_young_poisson(-1.0, 0.3), std::invalid_argument);
  EXPECT_THROW(LameParameters::from_young_poisson(1.0, 0.5), std::invalid_argument);
  EXPECT_THROW(make_material<3>("Ogden", LameParameters::from_young_poisson(1.0, 0.3)),
               std::invalid_argument);
  Tensor<2, 3> inverted;
  inverted[0][0] = -1.0;
  inverted[1][1] = inverted[2][2] = 1.0;
  const auto neo = make_material<3>("NeoHooke", LameParameters::from_young_poisson(1.0, 0.3));
  EXPECT_THROW(neo->stress_and_tangent(inverted), std::domain_error);
}
