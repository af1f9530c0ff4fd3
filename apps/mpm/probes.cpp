#include "apps/mpm/probes.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

namespace tetfsi::mpm_setup {
namespace {

Vec3 vec3(const Json& j) { return Vec3(j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()); }

void quantity(Probe& p, const std::string& q) {
  p.displacement = q.rfind("displacement", 0) == 0;
  const char last = q.back();
  p.axis = (q == "displacement") ? -1 : last - 'x';
}

}  // namespace

std::vector<Probe> resolve_probes(const Setup& s, const Json& probes) {
  std::vector<Probe> out;
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const auto& j = probes[i];
    const std::string ptr = fmt::format("/probes/{}", i);
    const auto kind = j.at("kind").get<std::string>();
    Probe p;
    if (kind == "membrane_point") {
      p.kind = Probe::Kind::MembranePoint;
      const Vec3 x = vec3(j.at("point"));
      double best = std::numeric_limits<double>::infinity();
      const auto& nodes = s.membrane_mesh.nodes;
      for (std::size_t k = 0; k < nodes.size(); ++k)
        if ((nodes[k] - x).norm() < best) {
          best = (nodes[k] - x).norm();
          p.node = static_cast<int>(k);
        }
      p.rest = nodes[p.node];
      quantity(p, j.at("quantity").get<std::string>());
    } else if (kind == "membrane_radius") {
      p.kind = Probe::Kind::MembraneRadius;
      p.center = vec3(j.at("center"));
      p.direction = vec3(j.at("axis")).normalized();
      p.max = j.at("statistic") == "max";
    } else if (kind == "membrane_volume") {
      p.kind = Probe::Kind::MembraneVolume;
      if (!s.membrane_closed)
        throw SetupError(ptr + "/kind", "membrane_volume needs a closed membrane (every edge in two elements but "
                                        "those in a symmetry plane); /mpm/membrane is open");
    } else if (kind == "particle_point" || kind == "body_energy") {
      const auto name = j.at("body").get<std::string>();
      int body = -2;
      for (std::size_t b = 0; b < s.bodies.size(); ++b)
        if (s.bodies[b].name == name) body = static_cast<int>(b);
      if (kind == "body_energy" && name == s.membrane_name) body = -1;
      if (body == -2)
        throw SetupError(ptr + "/body", fmt::format("no body named \"{}\" in /mpm/bodies{}", name,
                                                    kind == "body_energy" ? " and it is not the membrane's name" : ""));
      p.body = body;
      if (kind == "body_energy") {
        p.kind = Probe::Kind::BodyEnergy;
        p.energy = j.at("energy").get<std::string>();
      } else {
        p.kind = Probe::Kind::ParticlePoint;
        const Vec3 x = vec3(j.at("point"));
        const auto& P = s.particles;
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < P.size(); ++k)
          if (P.material[k] == s.bodies[body].material && (P.x[k] - x).norm() < best) {
            best = (P.x[k] - x).norm();
            p.particle = k;
          }
        p.rest = P.x[p.particle];
        quantity(p, j.at("quantity").get<std::string>());
      }
    } else if (kind == "total_energy") {
      p.kind = Probe::Kind::TotalEnergy;
    } else {
      throw SetupError(ptr + "/kind", fmt::format("probe kind \"{}\" is not one of an mpm scene (membrane_point, "
                                                  "membrane_radius, membrane_volume, particle_point, body_energy, "
                                                  "total_energy)", kind));
    }
    out.push_back(p);
  }
  return out;
}

void body_energies(const mpm::MpmSolver& mpm, std::uint16_t material, double& kinetic, double& internal) {
  const auto& P = mpm.particles();
  const auto& mat = mpm.materials()[material];
  kinetic = internal = 0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (P.material[p] != material) continue;
    kinetic += 0.5 * P.mass[p] * P.v[p].squaredNorm();
    if (mat.kind == mpm::Material::Kind::Fluid) {
      internal += P.energy[p] * P.mass[p] / mat.rho0;
    } else {  // W = 1/2 sigma : eps V, eps = ((1 + nu) sigma - nu tr(sigma) I) / E (as MpmSolver::energies)
      const mpm::Mat3& sg = P.stress[p];
      const mpm::Mat3 eps = ((1 + mat.poisson) * sg - mat.poisson * sg.trace() * mpm::Mat3::Identity()) / mat.youngs;
      internal += 0.5 * sg.cwiseProduct(eps).sum() * P.volume(p);
    }
  }
}

double evaluate(const Probe& p, const Setup& s, const mpm_contact::CoupledModel& model) {
  const auto& mem = model.membrane();
  auto pick = [&](const Vec3& x) {
    if (!p.displacement) return x[p.axis];
    return p.axis < 0 ? (x - p.rest).norm() : x[p.axis] - p.rest[p.axis];
  };
  switch (p.kind) {
    case Probe::Kind::MembranePoint: return pick(mem.positions()[p.node]);
    case Probe::Kind::ParticlePoint: return pick(model.mpm().particles().x[p.particle]);
    case Probe::Kind::MembraneRadius: {
      double r = p.max ? 0.0 : std::numeric_limits<double>::infinity();
      for (const auto& x : mem.positions()) {
        const Vec3 d = x - p.center;
        const double rad = (d - d.dot(p.direction) * p.direction).norm();
        r = p.max ? std::max(r, rad) : std::min(r, rad);
      }
      return r;
    }
    case Probe::Kind::MembraneVolume: return enclosed_volume(mem.positions(), mem.quads(), s.symmetry_planes);
    case Probe::Kind::BodyEnergy: {
      double kin = 0, internal = 0;
      if (p.body < 0) {
        const auto e = mem.energies();
        kin = e.kinetic;
        internal = e.strain + e.hourglass;
      } else {
        body_energies(model.mpm(), s.bodies[p.body].material, kin, internal);
      }
      return p.energy == "kinetic" ? kin : p.energy == "internal" ? internal : kin + internal;
    }
    case Probe::Kind::TotalEnergy: return model.stored_energy();
  }
  return 0;
}

}  // namespace tetfsi::mpm_setup
