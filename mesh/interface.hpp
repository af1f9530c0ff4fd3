#pragma once
/// @file interface.hpp
/// Fluid-solid interface of a complex mesh (build_complex): the triangles shared by a fluid tet
/// and a solid tet, with both tets and their local faces, and a conformity check.
///
/// Local face f of a tet is the face opposite its vertex f; kTetFaceVertices[f] lists the face's
/// local vertices ordered so that, for a positively oriented tet, (x1 - x0) x (x2 - x0) points out
/// of the tet. The coupling (Chentanez et al. 2006, eqs. 4-8) integrates fluid pressure over these
/// triangles onto the solid vertices.
#include <array>
#include <string>
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace tetfsi::mesh {

inline constexpr int kTetFaceVertices[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

/// One interface triangle.
struct InterfaceFace {
  std::array<int, 3> vertices{};  ///< mesh vertex indices; normal (v1 - v0) x (v2 - v0) points out of
                                  ///< the solid, into the fluid
  int solid_tet = -1;             ///< tet index on the solid side
  int solid_face = -1;            ///< local face (0..3) of solid_tet, opposite its vertex solid_face
  int fluid_tet = -1;             ///< tet index on the fluid side
  int fluid_face = -1;            ///< local face (0..3) of fluid_tet
  int solid_subdomain = 0;        ///< label of the solid (solid_subdomain(i))
};

/// Result of check_interface(). Conforming means every count except interface_faces is zero.
struct InterfaceCheck {
  int interface_faces = 0;      ///< faces shared by exactly one fluid and one solid tet
  int overshared_faces = 0;     ///< faces of more than two tets
  int solid_solid_faces = 0;    ///< faces shared by tets of two different solids
  int exposed_solid_faces = 0;  ///< solid boundary faces with no tet on the other side
  int misoriented_faces = 0;    ///< shared faces whose two tets lie on the same side of it
  std::string first_defect;     ///< description of one defect (empty if conforming)
  bool conforming() const {
    return overshared_faces == 0 && solid_solid_faces == 0 && exposed_solid_faces == 0 && misoriented_faces == 0;
  }
};

/// Checks that the solids of `mesh` are embedded conformingly in the fluid: every face of a solid
/// tet either is shared with a tet of the same solid or with exactly one fluid tet, no face has
/// more than two tets, and no other face is shared by different subdomains.
/// Labels: kFluidSubdomain for fluid, >= 2 for solids (an unlabelled mesh has no interface).
InterfaceCheck check_interface(const TetMesh& mesh);

/// The interface triangles in a deterministic order (by solid tet index, then local face).
/// @throws MeshError (complex_mesher.hpp) with check_interface's first defect if not conforming
std::vector<InterfaceFace> interface_faces(const TetMesh& mesh);

}  // namespace tetfsi::mesh
