#pragma once
/// @file surface_layer.hpp
/// The velocity of a liquid's thinnest cut tets on particles (particles.hpp, step 3).
///
/// The cut-tet projection (liquid/free_surface_projection.hpp) weighs a tet by its liquid volume,
/// so it barely constrains the velocity of a tet that holds little liquid. The mesh advection reads
/// such tets from the node interpolant every step (semi_lagrangian.hpp, kLinear anchors only in tets
/// full of liquid), which damps whatever they pick up; particles, which carry velocity without
/// that smoothing, let it grow. Measured on the sloshing tank of bench_fluid --sloshing (32 cells,
/// 13.8k tets, T/40, APIC): with no tet smoothed the wave's energy grows by 6.3% per period over 8
/// periods (velocities of 0.5 m/s in tets a fifth full, within a cell of a side wall, against
/// 0.04 m/s in the wave); smoothing every cut tet, as the mesh advection does, loses 3.1% per period
/// over 20; smoothing the tets less than kSurfaceLayerFraction full keeps the growth down for
/// several periods but not for 20 (fluid/README.md, "Particles"). The mesh advection with its
/// smoothing removed (every tet anchored) grows the same way: the growth is the free-surface
/// discretization's, not the particles'.
#include <vector>

#include "fluid/operators/fluid_mesh.hpp"
#include "fluid/operators/p1_operators.hpp"

namespace tetfsi::fluid {

/// Liquid fraction |Omega_t| / V_t below which a cut tet takes the node interpolant.
constexpr double kSurfaceLayerFraction = 0.6;

/// For every tet with 0 < |Omega_t| < kSurfaceLayerFraction V_t (all at once, from the values before):
///     v_t <- (1/4) sum_{k in t} U_k,   U_k = sum_{s ∋ k} |Omega_s| v_s / sum_{s ∋ k} |Omega_s|,
/// the liquid-weighted node interpolant at its centroid (the mesh advection's node averages
/// without the air's share, which would bring in the extension's values).
void smooth_surface_layer(const FluidMesh& mesh, const std::vector<double>& liquid_volume, TetVectors& v);

}  // namespace tetfsi::fluid
