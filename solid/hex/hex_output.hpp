#pragma once
/// @file hex_output.hpp
/// VTU output of a hex body: reference points with the point field "displacement" (warp by it in
/// ParaView), cell fields "cauchy_stress" and "pk2_stress" (6 Voigt values [xx yy zz xy yz zx],
/// Gauss-point averages) and "von_mises" (of the Cauchy stress) [Pa].
#include <Eigen/Core>
#include <filesystem>

#include "mesh/io/vtu_writer.hpp"
#include "solid/hex/hex_model.hpp"

namespace tetfsi::solid::hex {

/// Grid with the fields above. @throws std::runtime_error if u is non-finite or an element is
/// inverted (a diverged state is reported, never written out).
mesh::io::UnstructuredGrid make_hex_grid(const HexModel& model, const Eigen::VectorXd& u);

/// Writes make_hex_grid(model, u) to `path` (atomically).
void write_hex_vtu(const std::filesystem::path& path, const HexModel& model, const Eigen::VectorXd& u);

}  // namespace tetfsi::solid::hex
