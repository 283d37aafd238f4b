#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

namespace terramesh {

/// Writes a file atomically: the content goes to a temporary file in the same directory, which is
/// flushed and then renamed over `path`. Readers see either the old file or the complete new one;
/// a failed write leaves no partial file behind.
/// @param write callback that writes the whole content to the stream (binary mode).
/// @throw std::runtime_error naming the path if the file cannot be created, written or renamed.
void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(std::ostream&)>& write);

/// Convenience overload for content already in memory.
void writeFileAtomically(const std::filesystem::path& path, const std::string& content);

}  // namespace terramesh
