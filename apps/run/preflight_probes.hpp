#pragma once
/// @file preflight_probes.hpp
/// Preflight's check of /probes (preflight.cpp).
#include <string>
#include <vector>

#include "apps/scene/schema.hpp"

namespace tetfsi::run {

/// A probe whose kind the scene's runner (`runner`, its kinds `probe_kinds`; empty: any) does not
/// have, or an energy or contact probe in a static analysis, is an issue at /probes/i/kind.
std::vector<scene::Issue> probe_issues(const scene::Json& js, const std::string& runner,
                                       const std::vector<std::string>& probe_kinds);

}  // namespace tetfsi::run
