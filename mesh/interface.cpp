/// @file interface.cpp
#include "mesh/interface.hpp"

#include <algorithm>
#include <cstdint>
#include <unordered_map>

#include "mesh/complex_mesher.hpp"  // MeshError

namespace tetfsi::mesh {
namespace {

struct FaceKeyHash {
  std::size_t operator()(const std::array<int, 3>& k) const {
    std::uint64_t h = 1469598103934665603ull;
    for (int v : k) h = (h ^ static_cast<std::uint32_t>(v)) * 1099511628211ull;
    return static_cast<std::size_t>(h);
  }
};

struct Side {
  int tet, face;
};

/// All tet sides of every face, keyed by its sorted vertex triple.
using FaceMap = std::unordered_map<std::array<int, 3>, std::vector<Side>, FaceKeyHash>;

std::array<int, 3> face_vertices(const TetMesh& m, int t, int f) {
  const auto& tet = m.tets[t];
  return {tet[kTetFaceVertices[f][0]], tet[kTetFaceVertices[f][1]], tet[kTetFaceVertices[f][2]]};
}

FaceMap build_faces(const TetMesh& m) {
  FaceMap faces;
  faces.reserve(2 * m.tets.size() + 16);
  for (int t = 0; t < m.num_tets(); ++t)
    for (int f = 0; f < 4; ++f) {
      auto key = face_vertices(m, t, f);
      std::sort(key.begin(), key.end());
      faces[key].push_back({t, f});
    }
  return faces;
}

int label(const TetMesh& m, int t) { return m.subdomain.empty() ? kFluidSubdomain : m.subdomain[t]; }

/// The two tets of a shared face lie on opposite sides iff the face's outward orientations are
/// opposite, i.e. one vertex cycle is a rotation of the reverse of the other.
bool opposite(const std::array<int, 3>& a, const std::array<int, 3>& b) {
  for (int r = 0; r < 3; ++r)
    if (a[0] == b[r] && a[1] == b[(r + 2) % 3] && a[2] == b[(r + 1) % 3]) return true;
  return false;
}

}  // namespace

InterfaceCheck check_interface(const TetMesh& mesh) {
  InterfaceCheck c;
  const FaceMap faces = build_faces(mesh);
  auto note = [&](const std::string& what, int t, int f) {
    if (c.first_defect.empty())
      c.first_defect = what + " at local face " + std::to_string(f) + " of tet " + std::to_string(t);
  };
  // Visit faces in tet order so that the reported example is deterministic.
  for (int t = 0; t < mesh.num_tets(); ++t)
    for (int f = 0; f < 4; ++f) {
      auto key = face_vertices(mesh, t, f);
      std::sort(key.begin(), key.end());
      const auto& sides = faces.at(key);
      if (sides[0].tet != t || sides[0].face != f) continue;  // count each face once
      if (sides.size() > 2) {
        ++c.overshared_faces;
        note("face in " + std::to_string(sides.size()) + " tets", t, f);
        continue;
      }
      const int la = label(mesh, t);
      if (sides.size() == 1) {
        if (la != kFluidSubdomain) {
          ++c.exposed_solid_faces;
          note("solid face (subdomain " + std::to_string(la) + ") with no fluid tet on the other side", t, f);
        }
        continue;
      }
      const Side& o = sides[1];
      if (!opposite(face_vertices(mesh, t, f), face_vertices(mesh, o.tet, o.face))) {
        ++c.misoriented_faces;
        note("tets " + std::to_string(t) + " and " + std::to_string(o.tet) + " on the same side of a face", t, f);
      }
      const int lb = label(mesh, o.tet);
      if (la == lb) continue;
      if (la == kFluidSubdomain || lb == kFluidSubdomain) {
        ++c.interface_faces;
      } else {
        ++c.solid_solid_faces;
        note("face shared by solids " + std::to_string(la) + " and " + std::to_string(lb), t, f);
      }
    }
  return c;
}

std::vector<InterfaceFace> interface_faces(const TetMesh& mesh) {
  const InterfaceCheck c = check_interface(mesh);
  if (!c.conforming()) throw MeshError("non-conforming fluid-solid interface: " + c.first_defect);
  const FaceMap faces = build_faces(mesh);
  std::vector<InterfaceFace> out;
  out.reserve(c.interface_faces);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (label(mesh, t) == kFluidSubdomain) continue;
    for (int f = 0; f < 4; ++f) {
      auto key = face_vertices(mesh, t, f);
      std::sort(key.begin(), key.end());
      const auto& sides = faces.at(key);
      if (sides.size() != 2) continue;
      const Side& o = sides[0].tet == t ? sides[1] : sides[0];
      if (label(mesh, o.tet) != kFluidSubdomain) continue;
      InterfaceFace face;
      face.vertices = face_vertices(mesh, t, f);
      face.solid_tet = t;
      face.solid_face = f;
      face.fluid_tet = o.tet;
      face.fluid_face = o.face;
      face.solid_subdomain = label(mesh, t);
      out.push_back(face);
    }
  }
  return out;
}

}  // namespace tetfsi::mesh
