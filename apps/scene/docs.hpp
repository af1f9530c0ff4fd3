#pragma once
/// @file docs.hpp
/// The scene key reference as Markdown, generated from the schema (`tetfsi schema`;
/// committed as docs/scene_format.md and checked by a test to be in sync).
#include <string>

#include "apps/scene/schema.hpp"

namespace tetfsi::scene {

/// Markdown reference of every key of `schema`: one table per object, nested objects and array
/// elements under their JSON-pointer path (array elements as `/solids/*`).
std::string schema_markdown(const Field& schema);

}  // namespace tetfsi::scene
