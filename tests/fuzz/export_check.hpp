#pragma once
// fuzz_export's oracle: what it reads back from the 3DEC and YADE writers' outputs
// (fuzz_export.cpp lists the checks). Compiled without libFuzzer's coverage (CMakeLists.txt):
// it is no code under test, and its comparisons, char by char over every output, cost more
// than the writers themselves when instrumented. ASan and UBSan still cover it. Each check
// stops the run with fuzz::finding when the output breaks the contract.
#include <cstddef>
#include <string>

#include "slice/export_3dec.hpp"

namespace fuzz {

void check_grid(const std::string& text, const slice::ThreeDecStats& st);
void check_commands(const std::string& text);
void check_python(const std::string& text, std::size_t bodies, const std::string& file);

}  // namespace fuzz
