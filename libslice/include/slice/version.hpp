#pragma once
namespace slice {
/// The rockslice version, e.g. "0.1.0".
const char* version();
}  // namespace slice
