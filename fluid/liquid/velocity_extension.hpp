#pragma once
/// @file velocity_extension.hpp
/// Velocity in the air next to the liquid, for the next step's back-traces (of the level set and
/// of the velocity itself). The projection sets u only on tets with liquid; the other tets get the
/// velocity of the liquid by constant extrapolation along the tet adjacency, one layer of face
/// neighbours at a time: each air tet of layer k takes the mean of its neighbours of layers < k
/// (a graph form of the constant extension n . grad u = 0 of Enright, Marschner & Fedkiw 2002,
/// "Animation and rendering of complex water surfaces"). Tets beyond `layers` get zero.
#include <vector>

#include "fluid/operators/fluid_mesh.hpp"
#include "fluid/operators/p1_operators.hpp"

namespace tetfsi::fluid {

/// Overwrites u on the tets not marked `keep` (see file doc). Deterministic.
/// @param keep   per tet: 1 where the velocity is the liquid's and stays
/// @param layers number of layers of other tets to fill (>= 0)
void extend_velocity(const FluidMesh& mesh, const std::vector<char>& keep, int layers, TetVectors& u);

}  // namespace tetfsi::fluid
