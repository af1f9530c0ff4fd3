#pragma once
/// @file particles.hpp
/// Material points of the MPM (Lian, Liu & Zhang 2014, section 3): each carries mass, position,
/// velocity, Cauchy stress, density, internal energy and (derived) volume m_p / rho_p.
#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <vector>

#include "mpm/particles/grid.hpp"

namespace tetfsi::mpm {

/// Structure of arrays, one entry per particle. Units SI.
struct Particles {
  std::vector<double> mass;      ///< m_p [kg]
  std::vector<Vec3> x;           ///< position [m]
  std::vector<Vec3> v;           ///< velocity v^{n-1/2} [m/s]
  std::vector<Mat3> stress;      ///< Cauchy stress sigma [Pa], symmetric
  std::vector<double> rho;       ///< current density [kg/m^3]
  std::vector<double> energy;    ///< fluids: internal energy per reference volume E [J/m^3]
  std::vector<std::uint16_t> material;  ///< index into the solver's material list

  std::size_t size() const { return mass.size(); }
  double volume(std::size_t p) const { return mass[p] / rho[p]; }
  /// Appends one particle with zero stress.
  void add(double m, const Vec3& pos, const Vec3& vel, double density, double E, std::uint16_t mat);
};

/// Fills the box [lo, hi] with particles on a regular lattice of spacing `dx` (particle centres
/// at lo + (i + 1/2) dx), each of mass rho0 dx^3, keeping those for which `inside(x)` holds.
/// Returns the number of particles added.
std::size_t sample_lattice(Particles& particles, const Vec3& lo, const Vec3& hi, double dx,
                           double rho0, double E0, const Vec3& velocity, std::uint16_t material,
                           const std::function<bool(const Vec3&)>& inside);

}  // namespace tetfsi::mpm
