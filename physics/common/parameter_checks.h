// Range checks of parameter-file values with the project's one-line errors
// ("parameter 'X': expected ..., got ..."), shared by the apps' parameter classes.
#pragma once

#include <deal.II/base/utilities.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace physics::parameters
{
  inline double positive(double v, const std::string& name)
  {
    if (!(v > 0))
      throw std::invalid_argument("parameter '" + name + "': expected a positive value, got " + std::to_string(v));
    return v;
  }

  /// Poisson's ratio of an isotropic material: -1 < v < 0.5.
  inline double poisson_ratio(double v, const std::string& name = "Poisson's ratio")
  {
    if (!(v > -1 && v < 0.5))
      throw std::invalid_argument("parameter '" + name + "': expected -1 < nu < 0.5, got " + std::to_string(v));
    return v;
  }

  /// A tolerance: 0 < v < 1. `name` says which parameter (and, if ambiguous, its section).
  inline double tolerance(double v, const std::string& name)
  {
    if (!(v > 0 && v < 1))
      throw std::invalid_argument("parameter " + name + ": expected 0 < tol < 1");
    return v;
  }

  /// Comma-separated numbers of parameter `name`; `count` > 0 also checks how many.
  inline std::vector<double> numbers(const std::string& text, const std::string& name, int count = 0)
  {
    std::vector<double> values;
    for (const auto& s : dealii::Utilities::split_string_list(text, ','))
      {
        try
          {
            std::size_t end = 0;
            values.push_back(std::stod(s, &end));
            if (end != s.size())
              throw std::invalid_argument("");
          }
        catch (const std::exception&)
          {
            throw std::invalid_argument("parameter '" + name + "': '" + s + "' is not a number");
          }
      }
    if (count > 0 && static_cast<int>(values.size()) != count)
      throw std::invalid_argument("parameter '" + name + "': expected " + std::to_string(count) +
                                  " components, got " + std::to_string(values.size()));
    return values;
  }
} // namespace physics::parameters
