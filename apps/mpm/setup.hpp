#pragma once
/// @file setup.hpp
/// The MPM + membrane problem of a scene's `mpm` block (apps/scene/blocks/mpm.cpp): grid, particle
/// bodies, membrane, contact, gas sources and probes, built from the resolved scene JSON. The same
/// build runs when a scene is validated (apps/scene/scene_schema.cpp) and when it is run
/// (apps/run/mpm_runner.cpp), so `validate` and `run` reject the same scenes with the same message.
#include <nlohmann/json.hpp>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/mpm/membrane_shapes.hpp"
#include "coupling/mpm/coupled_model.hpp"
#include "fluid/mpm/mpm_solver.hpp"

namespace tetfsi::mpm_setup {

using Json = nlohmann::json;

/// A problem in the scene: the JSON pointer of the key and what is wrong.
class SetupError : public std::runtime_error {
 public:
  SetupError(std::string pointer, const std::string& message)
      : std::runtime_error(message), pointer_(std::move(pointer)) {}
  const std::string& pointer() const { return pointer_; }

 private:
  std::string pointer_;
};

/// A particle body: its particles are those with material index `material` (one material per body).
struct Body {
  std::string name;
  std::uint16_t material = 0;
  std::size_t particles = 0;  ///< at t = 0
};

struct Setup {
  mpm::Grid grid;
  std::vector<mpm::Material> materials;  ///< one per body, in the order of /mpm/bodies
  mpm::Particles particles;
  mpm::MpmOptions options;
  std::vector<Body> bodies;
  std::string membrane_name;
  QuadMesh membrane_mesh;
  membrane::MembraneMaterial membrane_material;
  std::vector<std::array<bool, 3>> membrane_fixed;  ///< per node
  Vec3 membrane_velocity = Vec3::Zero();
  double membrane_pressure = 0, membrane_damping = 0;
  std::vector<SymmetryPlane> symmetry_planes;
  bool membrane_closed = false;  ///< every edge in two quads but those in symmetry planes
  mpm_contact::ContactOptions contact;
  double membrane_cfl = 0.9;
  std::vector<mpm_contact::GasSource> sources;
};

/// Builds the problem of the resolved `mpm` block (defaults filled in, file paths absolute) with
/// gravity g [m/s^2] (simulation.gravity) on particles and membrane.
/// @throws SetupError naming the key (pointer from the scene root) on every problem the schema
///         cannot see: unreadable or open surface files, bodies with no particle or outside the
///         grid, empty fixed regions, a membrane outside the grid, unknown body names, ...
Setup build_setup(const Json& mpm, const Vec3& gravity);

/// The solvers of a setup. @throws std::invalid_argument / std::runtime_error from the solvers
std::unique_ptr<mpm_contact::CoupledModel> make_model(const Setup& setup);

/// Tolerance for "on a plane" / "in a region" tests of membrane nodes: 1e-9 of the grid size.
double node_tolerance(const Setup& s);

}  // namespace tetfsi::mpm_setup
