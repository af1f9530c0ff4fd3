#pragma once
/// @file atomic_file.hpp
/// Whole-file writes that never leave a half-written file behind: the content goes to a
/// temporary file in the same folder, which is then renamed over the target (rename(2) is
/// atomic on POSIX file systems). An interrupted run therefore leaves only whole frames.
#include <filesystem>
#include <functional>
#include <ostream>
#include <string_view>

namespace tetfsi::mesh::io {

/// Writes a file atomically.
/// @param path   target file; its folder must exist
/// @param write  callback that streams the whole content into the given stream
/// @throws std::runtime_error naming the path if the file cannot be written or renamed
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write);

/// Convenience overload for content already in memory.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

}  // namespace tetfsi::mesh::io
