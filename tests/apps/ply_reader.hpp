#pragma once
/// @file ply_reader.hpp
/// Test-only reader of the binary little-endian PLY files tetfsi writes (header parsed
/// independently of the writer, so that a wrong header or layout fails the tests).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace tetfsi::test {

struct PlyData {
  std::vector<std::string> vertex_properties;  ///< in file order
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3d> velocities;     ///< empty if the file has no vx, vy, vz
  std::vector<std::array<int, 3>> triangles;
};

/// Reads a PLY file; throws std::runtime_error on anything unexpected.
PlyData read_ply(const std::filesystem::path& file);

}  // namespace tetfsi::test
