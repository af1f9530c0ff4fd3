#pragma once
/// @file volume_mesh.hpp
/// Tet meshes read from files (VTK .vtu, Gmsh .msh) for solids whose FEM mesh the user brings,
/// checked before they reach the FEM model (solid/tet/tet_model.hpp).
#include <string>
#include <vector>

#include "mesh/complex_mesher.hpp"  // MeshError

#include "mesh/surface_import.hpp"
#include "mesh/tet_mesh.hpp"

namespace tetfsi::mesh {

/// Relative volume at or below which a tet counts as degenerate: |V| <= kDegenerateTet * l^3,
/// l its longest edge (a regular tet has V = l^3 / (6 sqrt 2) = 0.118 l^3). The same bound as
/// TetModel's, so every tet accepted here is accepted there.
constexpr double kDegenerateTet = 1e-12;

/// The lower-case extension of a volume mesh file (".vtu" or ".msh") after checking that the file
/// exists and is at most kMaxSurfaceBytes.
/// @throws MeshError naming the file (missing, too large, another extension)
std::string volume_mesh_extension(const std::string& path);

/// The cells of a .vtu volume mesh (point indices) and its points, every cell a VTK_TETRA (4 points)
/// or, with `hexes`, a VTK_HEXAHEDRON (8 points).
/// @throws MeshError naming the file and the first cell of another type (for a tet / hex mix-up,
///         the model the file is for)
std::vector<std::vector<int>> read_vtu_cells(const std::string& path, bool hexes, std::vector<Eigen::Vector3d>& points);

/// Runs `read` and turns any std::exception it throws into a MeshError with the same message (the
/// file readers' std::runtime_error already names the file).
template <class Read>
auto as_mesh_error(Read&& read) {
  try {
    return read();
  } catch (const MeshError&) {
    throw;
  } catch (const std::exception& e) {
    throw MeshError(e.what());
  }
}

/// Reads the tets of `path` by its extension: `.vtu` (io::read_vtu; every cell must be VTK_TETRA,
/// type 10) or `.msh` (io::read_msh_tets). No placement, no checks (check_volume_mesh).
/// @throws MeshError naming the file and the cause (missing, over kMaxSurfaceBytes, unreadable,
///         another cell type with its index and type, unknown extension)
TetMesh read_volume_mesh(const std::string& path);

/// Checks a tet mesh for use as an FEM solid and makes it tidy. Refused (MeshError starting with
/// `label`): no tets; a non-finite coordinate; a tet repeating a vertex; a degenerate tet
/// (kDegenerateTet); tets of both orientations (the mesh is tangled: tet t is inverted relative
/// to the others); a face shared by more than two tets (overlapping tets); tets that fall apart
/// into more than one face-connected piece. Repaired, with a message in `warnings`: every tet
/// negatively oriented (a file written with the other convention) is reordered to positive
/// orientation (vertices 1 and 2 swapped); nodes used by no tet are dropped and the rest
/// renumbered in order.
void check_volume_mesh(TetMesh& mesh, const std::string& label, std::vector<std::string>& warnings);

/// read_volume_mesh, placement (x -> R (unit_scale x) + translation, orientation kept) and
/// check_volume_mesh with the file as the label.
/// @throws MeshError as above
TetMesh import_volume_mesh(const std::string& path, const Placement& placement, std::vector<std::string>& warnings);

}  // namespace tetfsi::mesh
