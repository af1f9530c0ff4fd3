#pragma once
/// @file material.hpp
/// Particle materials of the MPM (Lian, Liu & Zhang 2014, sections 3.3 and 7):
/// a hypo-elastic linear solid (Jaumann rate, eqs. 22 and 25) and a compressible fluid with shear
/// viscosity and an equation-of-state pressure (eq. 26): Mie-Grueneisen (eq. 66, Table 1) or
/// ideal gas (eq. 67, Table 2).
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace tetfsi::mpm {

/// Equation of state of a fluid. Both are linear in E, the internal energy per unit
/// *reference* volume [J/m^3] (the LS-DYNA convention the paper uses: ideal gas p0 = (gamma-1) E0,
/// Table 2 gives E0 = 25, p0 = 10). mu_c = rho/rho0 - 1 is the compression.
enum class Eos { IdealGas, MieGruneisen };

struct Material {
  enum class Kind { LinearElastic, Fluid };
  Kind kind = Kind::Fluid;
  std::string name = "material";
  double rho0 = 1.0;  ///< reference density [kg/m^3]
  // Linear elastic solid.
  double youngs = 0.0;   ///< E [Pa]
  double poisson = 0.0;  ///< nu [-]
  // Fluid.
  double viscosity = 0.0;  ///< shear viscosity mu [Pa s] (eq. 26)
  Eos eos = Eos::IdealGas;
  double gamma = 1.4;   ///< ideal gas: ratio of specific heats (eq. 67)
  double c0 = 0.0;      ///< Mie-Grueneisen: bulk sound speed [m/s] (Table 1)
  double s = 0.0;       ///< Mie-Grueneisen: Hugoniot slope (Table 1)
  double gamma0 = 0.0;  ///< Mie-Grueneisen: Grueneisen gamma_0 (Table 1)

  static Material linear_elastic(double rho0, double E, double nu);
  static Material ideal_gas(double rho0, double gamma, double viscosity);
  static Material mie_gruneisen(double rho0, double c0, double s, double gamma0, double viscosity);
  /// @throws std::invalid_argument naming the bad parameter
  void validate() const;

  double lame_lambda() const { return youngs * poisson / ((1 + poisson) * (1 - 2 * poisson)); }
  double shear_modulus() const { return youngs / (2 * (1 + poisson)); }

  /// EOS as p = a(rho) + b(rho) E (both EOS are linear in E). Returns {a, b}.
  /// Ideal gas (eq. 67): a = 0, b = (gamma-1) rho/rho0.
  /// Mie-Grueneisen (eq. 66): for mu_c >= 0, a = p_H (1 - gamma0 mu_c / 2), b = gamma0 with
  /// p_H = rho0 c0^2 mu_c (1+mu_c) / [1-(s-1) mu_c]^2; for mu_c < 0 (tension) p = 0, a = b = 0.
  /// (The paper writes gamma = gamma0 rho0/rho for the Grueneisen parameter; with E per reference
  /// volume gamma rho e = gamma0 E, so the energy term is gamma0 E; the Hugoniot term uses gamma0.)
  /// (Inline: called once per particle and step.)
  std::pair<double, double> eos_coefficients(double rho) const {
    if (eos == Eos::IdealGas) return {0.0, (gamma - 1.0) * rho / rho0};
    const double mu = rho / rho0 - 1.0;
    if (mu < 0.0) return {0.0, 0.0};
    const double den = 1.0 - (s - 1.0) * mu;
    const double pH = rho0 * c0 * c0 * mu * (1.0 + mu) / (den * den);
    return {pH * (1.0 - 0.5 * gamma0 * mu), gamma0};
  }
  double pressure(double rho, double E) const {
    const auto [a, b] = eos_coefficients(rho);
    return a + b * E;
  }
  /// Local sound speed [m/s] for the critical time step (eq. 21).
  /// Solid: sqrt((lambda + 2G)/rho). Ideal gas: sqrt(gamma p / rho). Mie-Grueneisen:
  /// c0 (1 + s mu_c) for mu_c > 0 (slope of the Hugoniot), else c0.
  double sound_speed(double rho, double p) const {
    if (kind == Kind::LinearElastic) return std::sqrt((lame_lambda() + 2 * shear_modulus()) / rho);
    if (eos == Eos::IdealGas) return std::sqrt(gamma * std::max(p, 0.0) / rho);
    const double mu = rho / rho0 - 1.0;
    return c0 * (1.0 + s * std::max(mu, 0.0));
  }
};

}  // namespace tetfsi::mpm
