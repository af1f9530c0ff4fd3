#pragma once
/// @file watchdog.hpp
/// The physics watchdog of the runners (/simulation/watchdog): inverted tets of a deforming tet
/// solid, inverted hex8 elements, and total energy rising above its start where every load is
/// conservative (solid-only tet scenes, hex8 dynamics with the work of their dead loads, coupled
/// scenes in a closed container). Each check returns "" or a diagnosis naming the object and the
/// keys to change; the driver adds the step.
#include <string>

#include <Eigen/Core>

#include "apps/scene/scene.hpp"
#include "solid/hex/hex_model.hpp"
#include "solid/tet/tet_model.hpp"

namespace tetfsi::run {

struct WatchdogSettings {
  bool allow_inverted = false;     ///< /simulation/watchdog/allow_inverted
  double max_energy_growth = 0.5;  ///< /simulation/watchdog/max_energy_growth
};

/// The resolved /simulation/watchdog block.
WatchdogSettings watchdog_settings(const scene::Json& simulation);

/// "" if no tet of `model` is inverted at displacement `d` (volume ratio J = V / V0 <= 0), else
/// the diagnosis for solid `name` (/solids/`index`).
std::string inverted_tets(const solid::TetModel& model, const Eigen::VectorXd& d, const std::string& name,
                          int index, const WatchdogSettings& settings);

/// "" if every hex8 element of `model` evaluates at `d` (det F > 0 at its Gauss points), else the
/// diagnosis for hex solid `name` (/solids/`index`) naming the first failed element (index, cell
/// and centre) and how many failed. A hex8 state with an inverted element has no internal force,
/// so the run cannot go on (allow_inverted does not apply).
std::string inverted_hexes(const solid::hex::HexModel& model, const Eigen::VectorXd& d, const std::string& name,
                           int index);

/// Energy balance of a system whose loads are all conservative: its total energy E (kinetic +
/// elastic + gravitational + springs + the potential -f.d of dead loads f) can only fall
/// (damping, dissipative integration, friction, numerical dissipation of the fluid). Energy from
/// nowhere is a rise E - E_0 > max_energy_growth * S, with the scale S the largest mechanical
/// (kinetic + elastic + spring) energy so far, at least a floor (m |g| L of the solids: the work
/// of lifting each by its size).
class EnergyWatch {
 public:
  EnergyWatch() = default;
  /// @param total  E_0 [J]; @param floor  m |g| L [J] (> 0 or a small positive number)
  EnergyWatch(double total, double mechanical, double floor) : start_(total), last_(total), scale_(std::max(mechanical, floor)) {}
  /// Records the energies after a step.
  void record(double total, double mechanical) {
    last_ = total;
    scale_ = std::max(scale_, mechanical);
  }
  double start() const { return start_; }  ///< E_0 [J]
  double last() const { return last_; }    ///< the last recorded energy [J]
  double scale() const { return scale_; }  ///< the energy scale so far [J]
  /// Whether the last recorded energy rose past the limit.
  bool exceeded(const WatchdogSettings& settings) const { return last_ - start_ > settings.max_energy_growth * scale_; }
  /// "" or "<subject>: the total energy (<terms>) rose by ... J above its start ..., <why>. <advice>,
  /// or raise /simulation/watchdog/max_energy_growth (now ...)".
  std::string diagnosis(const std::string& subject, const std::string& terms, const std::string& why,
                        const std::string& advice, const WatchdogSettings& settings) const;
  /// "" or the diagnosis for tet solid `name` (/solids/`index`, integrator `scheme`).
  std::string check(const std::string& name, int index, const std::string& scheme,
                    const WatchdogSettings& settings) const;
  /// The baselines in a checkpoint (support/binary_stream.hpp): E_0, the last energy, the scale.
  template <class Archive>
  void state(Archive& a) {
    a(start_, last_, scale_);
  }

 private:
  double start_ = 0, last_ = 0, scale_ = 0;
};

/// Floor of the energy scale of one body [J]: m |g| L, with `weight` = m |g| [N] and L the
/// diagonal of the bounding box of its rest nodes `X` (x0 y0 z0 x1 ...): the work of lifting it by
/// its size; at least 1e-12 J so that round-off of a body at rest far from any load is no rise.
double energy_floor(const Eigen::VectorXd& X, double weight);

/// Why the energy of a coupled fluid-solid scene is not watched: "" if its loads are
/// conservative, else the first way energy enters (an inflow, an open face, an emitter,
/// vorticity confinement, a fixed region driven at a velocity). Gravity, walls, fixed regions
/// held in place, springs, static obstacles and wall contact (inelastic) are conservative or
/// dissipative. The work supplied through inflows and open faces is not accounted:
/// such scenes are not watched.
std::string coupled_energy_source(const scene::Json& scene);

}  // namespace tetfsi::run
