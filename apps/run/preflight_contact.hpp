#pragma once
/// @file preflight_contact.hpp
/// Preflight's check of /coupling/contact_gap (preflight.cpp).
#include <string>
#include <vector>

#include <Eigen/Core>

#include "apps/scene/schema.hpp"

namespace tetfsi::run {

/// A solid's placed bounding box, as preflight read it (`ok` false: not read).
struct PlacedBox {
  bool ok = false;
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();  ///< [m]
};

/// The coupled runner keeps free solids a film of /coupling/contact_gap off the walls of a box
/// container (coupled_runner.cpp): a free solid (no fixed region, no motion) that starts inside
/// that film would be pushed out of it in its first step. Checked when the gap is given (its
/// default follows the meshed edge length, known only after meshing). A film given while every
/// contact that would keep it is off contradicts itself. `boxes` follow /solids; the domain is
/// [lo, hi]. Each issue with its JSON pointer.
std::vector<scene::Issue> contact_gap_issues(const scene::Json& js, const std::string& runner,
                                             const std::vector<PlacedBox>& boxes, const Eigen::Vector3d& lo,
                                             const Eigen::Vector3d& hi);

}  // namespace tetfsi::run
