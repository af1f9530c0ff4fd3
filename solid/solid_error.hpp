#pragma once
/// @file solid_error.hpp
/// The one exception type of the solid module: thrown on bad input (invalid material, mesh or
/// boundary conditions) and on numerical failure (inverted element with a model that cannot
/// handle it, non-finite state, a system matrix that is not positive definite). The message
/// names the cause, and where known the time step and the element or node.
#include <stdexcept>
#include <string>

namespace tetfsi::solid {

class SolidError : public std::runtime_error {
 public:
  explicit SolidError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace tetfsi::solid
