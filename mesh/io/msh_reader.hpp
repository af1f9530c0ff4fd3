#pragma once
/// @file msh_reader.hpp
/// Reader for the tetrahedra or hexahedra of Gmsh mesh files (.msh), ASCII format versions 2.2 and 4.1
/// (gmsh.info/doc/texinfo "MSH file format"; 2.2 is the legacy format "Gmsh 2" documents).
///
/// Read: $MeshFormat, $Nodes and $Elements; every other section ($Entities, $PhysicalNames,
/// $Periodic, ...) is skipped. 3-D elements must all be 4-node tetrahedra (type 4; read_msh_tets)
/// or all 8-node hexahedra (type 5; read_msh_hexes); elements of lower dimension (points, lines,
/// triangles, quads, which Gmsh writes for tagged boundaries) are ignored; any other 3-D element
/// (the other of the two, prism 6, pyramid 7, 10-node tet 11, ...) is refused, naming its element
/// tag and type. Binary files (file-type 1) are refused. Gmsh's 8-node hexahedron numbers its
/// nodes as VTK_HEXAHEDRON does (bottom face 0-3 counter-clockwise about +zeta, top face 4-7
/// above them), so hexes are kept in the file's order.
///
/// Hand-written rather than with Debian's libgmsh-dev (gmsh::open and
/// gmsh::model::mesh::getNodes/getElements): that API is a process-wide singleton
/// (gmsh::initialize/finalize, not re-entrant) and libgmsh4.8 pulls 24 packages into the build
/// (OpenCASCADE, FLTK, OpenGL, alglib), while the two ASCII layouts are a few dozen lines each.
#include <filesystem>
#include <string>

#include "mesh/hex_mesh.hpp"
#include "mesh/tet_mesh.hpp"

namespace tetfsi::mesh::io {

/// Every node of the file (in the order of the file) and its 4-node tets as indices into them,
/// vertex order as in the file (Gmsh's reference tet is positively oriented). No checks beyond
/// the format: see mesh/volume_mesh.hpp.
/// @throws std::runtime_error naming the file and the cause (missing file, unsupported version or
///         binary, malformed section, unknown node tag, non-tet 3-D element)
TetMesh read_msh_tets(const std::filesystem::path& path);
/// Same from the file's text (`name` is used in error messages).
TetMesh parse_msh_tets(const std::string& text, const std::string& name = "<string>");

/// Every node of the file and its 8-node hexahedra (Gmsh type 5), as read_msh_tets does for tets;
/// no checks beyond the format (mesh/hex_volume_mesh.hpp).
/// @throws std::runtime_error as read_msh_tets (a 3-D element other than an 8-node hex refused)
HexMesh read_msh_hexes(const std::filesystem::path& path);
/// Same from the file's text (`name` is used in error messages).
HexMesh parse_msh_hexes(const std::string& text, const std::string& name = "<string>");

}  // namespace tetfsi::mesh::io
