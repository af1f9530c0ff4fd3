#include "mesh/io/msh_writer.hpp"

#include <sstream>

#include "mesh/io/atomic_file.hpp"

namespace tetfsi::mesh::io {

void write_msh(const std::filesystem::path& path, const TetMesh& mesh, MshVersion version) {
  const auto n = mesh.vertices.size(), m = mesh.tets.size();
  std::ostringstream s;
  s.precision(17);
  auto node = [&](std::size_t i) { s << mesh.vertices[i].x() << ' ' << mesh.vertices[i].y() << ' ' << mesh.vertices[i].z() << '\n'; };
  auto tet = [&](std::size_t t) {
    const auto& v = mesh.tets[t];
    s << v[0] + 1 << ' ' << v[1] + 1 << ' ' << v[2] + 1 << ' ' << v[3] + 1 << '\n';
  };
  if (version == MshVersion::k22) {
    s << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" << n << '\n';
    for (std::size_t i = 0; i < n; ++i) s << i + 1 << ' ', node(i);
    s << "$EndNodes\n$Elements\n" << m << '\n';
    for (std::size_t t = 0; t < m; ++t) s << t + 1 << " 4 2 1 1 ", tet(t);  // type 4 (tet), tags: physical 1, elementary 1
    s << "$EndElements\n";
  } else {
    s << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
    s << "$Nodes\n1 " << n << " 1 " << n << "\n3 1 0 " << n << '\n';  // one block: volume entity 1, not parametric
    for (std::size_t i = 0; i < n; ++i) s << i + 1 << '\n';
    for (std::size_t i = 0; i < n; ++i) node(i);
    s << "$EndNodes\n$Elements\n1 " << m << " 1 " << m << "\n3 1 4 " << m << '\n';  // one block of type 4
    for (std::size_t t = 0; t < m; ++t) s << t + 1 << ' ', tet(t);
    s << "$EndElements\n";
  }
  write_file_atomically(path, s.str());
}

}  // namespace tetfsi::mesh::io
