#pragma once
/// @file msh_writer.hpp
/// Writer of a tet mesh as a Gmsh ASCII .msh file (version 4.1 or 2.2), the counterpart of
/// msh_reader.hpp: one volume entity holding every node and every 4-node tet (type 4); node
/// and element tags are 1-based. Coordinates are written with 17 significant digits, so a
/// write/read round trip is exact.
#include <filesystem>

#include "mesh/tet_mesh.hpp"

namespace tetfsi::mesh::io {

enum class MshVersion { k22, k41 };

/// Writes `mesh` atomically (see atomic_file.hpp). @throws std::runtime_error on I/O failure
void write_msh(const std::filesystem::path& path, const TetMesh& mesh, MshVersion version = MshVersion::k41);

}  // namespace tetfsi::mesh::io
