#pragma once
#include <filesystem>
#include <string>
#include <string_view>

namespace slice {
/// SHA-256 of bytes, lower-case hex.
std::string sha256_hex(std::string_view bytes);
/// SHA-256 of a file's content, lower-case hex. Throws Error if it cannot be read.
std::string sha256_file(const std::filesystem::path& file);
}  // namespace slice
