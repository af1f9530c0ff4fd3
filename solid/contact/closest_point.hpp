#pragma once
/// @file closest_point.hpp
/// The closest point on a triangle (mesh/closest_point.hpp), under the solids' names.
#include "mesh/closest_point.hpp"

namespace tetfsi::solid {
using mesh::ClosestPoint;
using mesh::closest_point_on_triangle;
}  // namespace tetfsi::solid
