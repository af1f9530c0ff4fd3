#pragma once
/// @file surface_voxels.hpp
/// The voxel fields of the smooth liquid surface (render_surface.hpp), before meshing
/// (vdb_surface.hpp): the level set smoothed inside the fluid, continued a little beyond its walls,
/// and the signed distance to the walls. With h the voxel size:
///
/// Smoothing. phi is the initial value of the heat equation phi_t = Laplacian(phi), run for
/// t = sigma^2 / 2: convolution with a Gaussian of standard deviation sigma. On a signed distance
/// function Laplacian(phi) is the mean curvature of its level sets, so this is mean-curvature flow
/// of the surface for that time (to first order): a wrinkle of wavelength lambda decays as
/// exp(-2 pi^2 sigma^2 / lambda^2), to 7e-3 at lambda = 2 sigma, 0.29 at 4 sigma, 0.82 at 10 sigma;
/// a plane is unchanged. Discretely: explicit steps of the 7-point Laplacian on the voxels inside the
/// fluid, n = ceil(3 sigma^2 / h^2) steps of dt = sigma^2 / (2 n) <= h^2 / 6 (the stability limit).
/// Walls: along an axis where a voxel's neighbour is not in the fluid (beyond a wall, inside a
/// solid, or beyond the plane of the boundary triangle nearest either voxel: a thin wall between
/// two fluid voxels), that axis's second difference is taken as zero, i.e. phi continued linearly
/// into the wall. The liquid then neither leaks through a wall nor is pulled at it: a still pool
/// against walls and floor stays exactly flat and a thin layer on a floor keeps its thickness.
/// Only voxels within the band |phi| < W = (ceil(3 sigma / h) + 2) h move (beyond it the Gaussian's
/// weight on the surface is below 1e-3); voxels outside the band keep their sampled values.
///
/// Continuation: the voxels next to the sampled ones (two layers of neighbours, of 26; not the
/// deep liquid) get phi
/// continued linearly from the fluid along each axis (the mean of 2 phi(a) - phi(b) over the axes
/// with two fluid voxels a, b in a row), else the mean of their known neighbours: the mesher reads
/// the free surface's zero crossing on edges that cross a wall from it.
///
/// D: the distance to the nearest boundary triangle within 2 voxels (computed for every triangle's
/// neighbourhood, in triangle order; the first of equally near triangles kept), negative for voxels
/// in the fluid; +-W beyond 2 voxels (only its sign counts there).
#include <Eigen/Core>
#include <vector>

#include "fluid/io/level_set_voxels.hpp"

namespace tetfsi::fluid {

/// Voxels from a wall within which D is a distance.
constexpr int kWallBandVoxels = 2;

struct SurfaceVoxels {
  double voxel_size = 0;               ///< h [m]
  double band = 0;                     ///< W [m]
  std::vector<Eigen::Vector3i> index;  ///< the sampled voxels (in their order), then the continuation
  std::vector<float> phi;              ///< smoothed level set [m], clamped to [-W, W]
  std::vector<float> wall;             ///< D [m], in [-W, W]
  std::vector<int> nearest;            ///< nearest boundary triangle within 2 voxels, else -1
  std::vector<char> inside;            ///< 1: voxel centre in the fluid (sampled), 0: continuation
  /// Voxels deep in the liquid (beyond the band; not in `index`): inside, psi = -W for the mesher.
  /// Every voxel with phi_s < 0 in the fluid is in `index` or here; the others are outside.
  std::vector<Eigen::Vector3i> deep;
  int steps = 0;                       ///< heat-equation steps taken
  std::size_t size() const { return index.size(); }
};

/// Steps of the heat equation and the band half-width [voxels] for sigma_voxels = sigma / h.
int smoothing_steps(double sigma_voxels);
int smoothing_band_voxels(double sigma_voxels);

/// Smooths `voxels` (sampled with band >= smoothing_band_voxels(sigma / h) h + h, so that every
/// fluid voxel next to one in the band is sampled) as the file doc says; `deep` (the liquid's
/// voxels beyond the band, SurfaceVoxels::deep) is kept out of the continuation.
/// @throws std::invalid_argument if smoothing < 0
SurfaceVoxels smooth_level_set(const LevelSetVoxels& voxels, const BoundaryTriangles& walls, double smoothing,
                               std::vector<Eigen::Vector3i> deep = {});

/// phi_s of `coarse` at `points` [m]: trilinear in the coarse voxels around each; a corner not
/// sampled (beyond the band) counts as -W or W by the sign of `fallback` there (phi itself).
Eigen::VectorXd smoothed_at(const SurfaceVoxels& coarse, const std::vector<Eigen::Vector3d>& points,
                            const Eigen::VectorXd& fallback);

/// The smoothed level set `coarse` carried to the finer voxels `fine_samples` (sampled with the
/// band coarse.band + their voxel size): phi_s trilinear in the coarse voxels around each fine one
/// (corners behind the plane of the fine voxel's nearest boundary triangle left out: the other side
/// of a thin wall), D and the continuation layers made anew at the fine voxel size. The smoothing
/// costs the same at any fine voxel size, and the mesh resolves liquid thinner than a coarse
/// voxel (a 3 cm layer on a floor under 3.5 cm voxels, which no voxel centre inside it would hold).
SurfaceVoxels resample(const SurfaceVoxels& coarse, const LevelSetVoxels& fine_samples, const BoundaryTriangles& walls,
                       std::vector<Eigen::Vector3i> deep = {});

}  // namespace tetfsi::fluid
