#include "slice/version.hpp"

namespace slice {
const char* version() { return SLICE_VERSION; }
}  // namespace slice
