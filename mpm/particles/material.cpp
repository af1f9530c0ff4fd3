#include "mpm/particles/material.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tetfsi::mpm {

Material Material::linear_elastic(double rho0, double E, double nu) {
  Material m;
  m.kind = Kind::LinearElastic;
  m.name = "linear_elastic";
  m.rho0 = rho0;
  m.youngs = E;
  m.poisson = nu;
  m.validate();
  return m;
}

Material Material::ideal_gas(double rho0, double gamma, double viscosity) {
  Material m;
  m.kind = Kind::Fluid;
  m.name = "ideal_gas";
  m.eos = Eos::IdealGas;
  m.rho0 = rho0;
  m.gamma = gamma;
  m.viscosity = viscosity;
  m.validate();
  return m;
}

Material Material::mie_gruneisen(double rho0, double c0, double s, double gamma0, double viscosity) {
  Material m;
  m.kind = Kind::Fluid;
  m.name = "mie_gruneisen";
  m.eos = Eos::MieGruneisen;
  m.rho0 = rho0;
  m.c0 = c0;
  m.s = s;
  m.gamma0 = gamma0;
  m.viscosity = viscosity;
  m.validate();
  return m;
}

void Material::validate() const {
  auto fail = [&](const std::string& what) {
    throw std::invalid_argument("mpm::Material '" + name + "': " + what);
  };
  if (!(rho0 > 0)) fail("reference density rho0 must be > 0");
  if (kind == Kind::LinearElastic) {
    if (!(youngs > 0)) fail("Young's modulus must be > 0");
    if (!(poisson > -1.0 && poisson < 0.5)) fail("Poisson ratio must lie in (-1, 0.5)");
    return;
  }
  if (!(viscosity >= 0)) fail("viscosity must be >= 0");
  if (eos == Eos::IdealGas && !(gamma > 1.0)) fail("ideal gas gamma must be > 1");
  if (eos == Eos::MieGruneisen && !(c0 > 0)) fail("Mie-Grueneisen c0 must be > 0");
}

}  // namespace tetfsi::mpm
