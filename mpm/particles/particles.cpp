#include "mpm/particles/particles.hpp"

#include <cmath>
#include <stdexcept>

namespace tetfsi::mpm {

void Particles::add(double m, const Vec3& pos, const Vec3& vel, double density, double E,
                    std::uint16_t mat) {
  mass.push_back(m);
  x.push_back(pos);
  v.push_back(vel);
  stress.push_back(Mat3::Zero());
  rho.push_back(density);
  energy.push_back(E);
  material.push_back(mat);
}

std::size_t sample_lattice(Particles& particles, const Vec3& lo, const Vec3& hi, double dx,
                           double rho0, double E0, const Vec3& velocity, std::uint16_t material,
                           const std::function<bool(const Vec3&)>& inside) {
  if (!(dx > 0)) throw std::invalid_argument("mpm::sample_lattice: spacing must be positive");
  int n[3];
  for (int a = 0; a < 3; ++a) n[a] = std::max(1, static_cast<int>(std::lround((hi[a] - lo[a]) / dx)));
  std::size_t added = 0;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const Vec3 p = lo + dx * Vec3(i + 0.5, j + 0.5, k + 0.5);
        if (inside && !inside(p)) continue;
        particles.add(rho0 * dx * dx * dx, p, velocity, rho0, E0, material);
        ++added;
      }
  return added;
}

}  // namespace tetfsi::mpm
