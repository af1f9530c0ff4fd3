#pragma once
/// @file msh_reader.hpp
/// Reader for the tetrahedra of Gmsh mesh files (.msh), ASCII format versions 2.2 and 4.1
/// (gmsh.info/doc/texinfo "MSH file format"; 2.2 is the legacy format "Gmsh 2" documents).
///
/// Read: $MeshFormat, $Nodes and $Elements; every other section ($Entities, $PhysicalNames,
/// $Periodic, ...) is skipped. 3-D elements must be 4-node tetrahedra (type 4); elements of lower
/// dimension (points, lines, triangles, quads, which Gmsh writes for tagged boundaries) are
/// ignored; any other 3-D element (hexahedron 5, prism 6, pyramid 7, 10-node tet 11, ...) is
/// refused, naming its element tag and type. Binary files (file-type 1) are refused.
///
/// Hand-written rather than with Debian's libgmsh-dev (gmsh::open and
/// gmsh::model::mesh::getNodes/getElements): that API is a process-wide singleton
/// (gmsh::initialize/finalize, not re-entrant) and libgmsh4.8 pulls 24 packages into the build
/// (OpenCASCADE, FLTK, OpenGL, alglib), while the two ASCII layouts are a few dozen lines each.
#include <filesystem>
#include <string>

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

}  // namespace tetfsi::mesh::io
