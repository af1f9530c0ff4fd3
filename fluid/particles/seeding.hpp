#pragma once
/// @file seeding.hpp
/// Seeding and reseeding (particles.hpp, step 2). Tet t with liquid fraction f_t = |Omega_t| / V_t
/// (1 without a free surface) aims at n*_t = round(N f_t) particles, N = ParticleOptions::per_tet,
/// and keeps its count within the band
///
///     floor(2N f_t / 3 + 1/2)  <=  n_t  <=  ceil(4N f_t / 3)            (4 to 8 for N = 6, f_t = 1):
///
/// below, particles are added up to n*_t; above, the particle nearest another in the tet is deleted
/// until n_t is the upper bound (the rest stay spread). New particles lie at uniformly random points
/// of the tet (barycentric coordinates -ln(U_k) / sum_j -ln(U_j), U uniform on (0, 1]) where phi < 0
/// (up to 8 n*_t tries), the random numbers drawn from a counter-based generator keyed by the
/// reseeding count, the tet and the try, so that a run repeats bit for bit on any thread count and
/// after a resume. They take the mesh velocity there, v_p = v_t + G_t (x_p - c_t) (transfer.hpp),
/// and for APIC ∇v_p = G_t.
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "fluid/operators/fluid_mesh.hpp"
#include "fluid/operators/p1_operators.hpp"
#include "fluid/particles/particles.hpp"
#include "fluid/particles/transfer.hpp"

namespace tetfsi::fluid {

/// What seeding or reseeding did.
struct SeedReport {
  int added = 0;
  int deleted = 0;
};

/// Deletes particles from the tets above the band (see file doc). `liquid_volume`: |Omega_t| per
/// tet (the tet volumes without a free surface). Keeps the particles sorted by tet.
int delete_crowded_particles(const FluidMesh& mesh, const std::vector<double>& liquid_volume, int per_tet,
                             ParticleSet& particles);

/// Adds particles to the tets below the band (see file doc; all of them when the set is empty: the
/// first seeding) with the velocity (R) of `v`, its gradient G_t taken over the neighbours marked
/// `valid` (tet_velocity_gradient; computed for the tets that get particles only); `phi` (empty: no
/// free surface) keeps them in the liquid. Increments seed_count. Keeps the particles sorted by tet.
/// @return the number added
int add_particles(const FluidMesh& mesh, const std::vector<double>& liquid_volume, const Eigen::VectorXd& phi,
                  int per_tet, const TetVectors& v, const std::vector<char>* valid, bool affine,
                  ParticleSet& particles);

}  // namespace tetfsi::fluid
