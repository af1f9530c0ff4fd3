#pragma once
/// @file validate.hpp
/// Checks a parsed scene against its schema (schema.hpp), collecting every problem, and returns
/// the resolved scene: the input with defaults filled in and file paths made absolute.
#include <filesystem>
#include <string>
#include <vector>

#include "apps/scene/schema.hpp"

namespace tetfsi::scene {

/// Validates `input` against `schema`.
/// @param base_dir  folder against which relative file paths are resolved (the scene's folder)
/// @param issues    receives one Issue per problem (pointer + message), in document order
/// @return the resolved JSON (meaningful only when no issue was added)
Json validate(const Json& input, const Field& schema, const std::filesystem::path& base_dir,
              std::vector<Issue>& issues);

/// Levenshtein edit distance (case-insensitive), for "did you mean" hints.
int edit_distance(const std::string& a, const std::string& b);

/// The candidate closest to `word` if it is close enough to be a likely typo, else "".
std::string closest_match(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace tetfsi::scene
