#pragma once
/// @file preflight_container.hpp
/// Preflight's checks of /domain/container (preflight.cpp), so that `validate` refuses what
/// meshing the container would.
#include <string>
#include <vector>

#include "apps/scene/schema.hpp"
#include "mesh/surface_mesh.hpp"

namespace tetfsi::run {

/// A solid the container must hold: its placed surface (nullptr if it could not be read, then not
/// checked) and its name for the messages.
struct ContainedSolid {
  const mesh::SurfaceMesh* surface = nullptr;
  std::string name;
};

/// A sphere, cylinder or mesh container (a box container has none): a readable closed surface
/// (`mesh`), inside the domain box (`mesh`; the primitives are checked by the schema), at least
/// one mesh.edge_length across, and every solid strictly inside it (mesh::surface_inside, the test
/// mesh::build_complex makes). Each issue with its JSON pointer; `solids` follow /solids.
std::vector<scene::Issue> container_issues(const scene::Json& js, const std::vector<ContainedSolid>& solids);

}  // namespace tetfsi::run
