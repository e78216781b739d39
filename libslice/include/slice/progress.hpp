#pragma once
#include <cstddef>
#include <functional>
#include <string_view>

namespace slice {
/// Progress callback: the library reports, a tool draws (or not). May be empty.
using Progress = std::function<void(std::string_view stage, std::size_t done, std::size_t total)>;
}  // namespace slice
