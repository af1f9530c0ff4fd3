#pragma once
/// @file transfer.hpp
/// Particle <-> mesh transfers for the P0 velocity (one v_t per tet, P1 pressure: Ando et al. 2013);
/// fluid/README.md, "Particles", gives the derivations and the measurements.
///
/// P2G goes through the nodes, with the P1 hat functions as the kernel (w_ip = lambda_i(x_p), the
/// barycentric coordinates of x_p in its tet: a partition of unity with linear precision,
/// sum_i w_ip (x_i - x_p) = 0), as APIC's transfer to a grid (Jiang et al. 2015, sec. 5):
///
///     m_i = sum_p w_ip m_p,    m_i U_i = sum_p w_ip m_p (v_p + ∇v_p (x_i - x_p))          (P2G-1)
///
/// (FLIP/PIC: without the ∇v_p term), then each tet takes the average of that P1 field over it,
///
///     v_t = (1/4) sum_{k in t} U_k.                                                       (P2G-2)
///
/// (P2G-1) keeps linear momentum, sum_i m_i U_i = sum_p m_p v_p, and (APIC) angular momentum,
/// sum_i x_i x m_i U_i = sum_p (x_p x m_p v_p + m_p eps : (∇v_p D_p)^T), D_p = sum_i w_ip (x_i - x_p)(x_i - x_p)^T
/// (Jiang et al. 2015: both follow from the linear precision), exactly. (P2G-2) reproduces affine
/// fields exactly (the average of a linear function over a tet is its value at the centroid); its
/// momentum sum_t rho |Omega_t| v_t equals sum_i m_i U_i where the particles' nodal masses m_i equal
/// the mesh's lumped ones, sum_{t ∋ i} rho |Omega_t| / 4, and differs by their sampling noise
/// elsewhere (measured in tests/fluid/test_particle_transfer.cpp). The particles' masses are their
/// shares of their tet's (liquid) mass, m_p = rho |Omega_t| / n_t.
///
/// G2P reads the tet-wise linear reconstruction
///
///     v(x) = v_t + G_t (x - c_t)                                                          (R)
///
/// with G_t the least-squares gradient of the tet values around t (exact for linear fields):
///     APIC:            v_p = v(x_p),  ∇v_p = G_t,
///     FLIP/PIC blend:  v_p = (1 - r) v(x_p) + r (v_p + dv(x_p))   (Zhu & Bridson 2005, sec. 4),
/// dv = v^{n+1} - v^{P2G} per tet, the grid step's change (sources, viscosity, body forces and the
/// projection's -(h/rho) G p), read by (R) too. A constant field reaches every particle unchanged
/// (G_t = 0), so G2P keeps its momentum: sum_p m_p c = sum_t rho |Omega_t| c.
#include <vector>

#include <Eigen/Core>

#include "fluid/operators/fluid_mesh.hpp"
#include "fluid/operators/p1_operators.hpp"
#include "fluid/particles/particles.hpp"

namespace tetfsi::fluid {

using TetMatrices = std::vector<Eigen::Matrix3d>;

/// G_t = argmin_G sum_s |v_s - v_t - G (c_s - c_t)|^2 over the face neighbours s of t that are
/// `valid` (nullptr: all) or, where their d = c_s - c_t do not span 3D (the smallest eigenvalue of
/// sum d d^T below 1e-2 of the largest: at walls and the surface), over the tets sharing a node with
/// t (counted once per shared node): the normal equations G (sum d d^T) = sum (v_s - v_t) d^T,
/// solved in the directions the neighbours span (eigenvalues above 1e-6 of the largest; none:
/// G_t = 0). Exact for linear fields.
TetMatrices tet_velocity_gradients(const FluidMesh& mesh, const TetVectors& v, const std::vector<char>* valid);

/// The tets' centroids c_t [m].
std::vector<Eigen::Vector3d> tet_centroids(const FluidMesh& mesh);

/// G_t of tet t alone (tet_velocity_gradients), with the mesh's `centroids`.
Eigen::Matrix3d tet_velocity_gradient(const FluidMesh& mesh, const std::vector<Eigen::Vector3d>& centroids,
                                      const TetVectors& v, const std::vector<char>* valid, int t);

/// The particles' masses m_p = rho |Omega_t| / n_t (liquid_volume: |Omega_t| per tet, or the tet
/// volumes) [kg]; particles sorted by tet.
std::vector<double> particle_masses(const ParticleSet& particles, const std::vector<double>& liquid_volume,
                                    double density);

/// The nodal masses m_i and momenta m_i U_i of (P2G-1).
struct NodalMomentum {
  std::vector<double> mass;  ///< [kg]
  TetVectors momentum;       ///< [kg m/s]
};

/// (P2G-1) with the particles' masses `m` (particle_masses); APIC when the particles carry ∇v_p.
/// Gathered node by node in a fixed order (deterministic). Particles sorted by tet.
NodalMomentum particles_to_nodes(const FluidMesh& mesh, const ParticleSet& particles, const std::vector<double>& m);

/// P2G, (P2G-1) and (P2G-2), into v for the tets whose four nodes received particle mass; the
/// others keep their value. @return per tet 1 if it received a value
std::vector<char> particles_to_tets(const FluidMesh& mesh, const ParticleSet& particles, const std::vector<double>& m,
                                    TetVectors& v);

/// G2P (see file doc). APIC when the particles carry ∇v_p (grad_v), else the FLIP/PIC blend with
/// FLIP share `flip_ratio` and v^{P2G} = `transferred` (one per tet). `valid` as for
/// tet_velocity_gradients.
void tets_to_particles(const FluidMesh& mesh, const TetVectors& v, const TetVectors& transferred, double flip_ratio,
                       const std::vector<char>* valid, ParticleSet& particles);

/// The velocity of (R) at x in tet t with its gradient G [m/s].
inline Eigen::Vector3d reconstructed_velocity(const FluidMesh& mesh, const TetVectors& v, const TetMatrices& G, int t,
                                              const Eigen::Vector3d& x) {
  return v[t] + G[t] * (x - mesh.centroid(t));
}

}  // namespace tetfsi::fluid
