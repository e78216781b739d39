// Issue 15 item 2: --compress writes the same data, deflated, readable by every reader.
#include <catch2/catch.hpp>
#include <string>

#include "slice/h5io.hpp"
#include "support/compare.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

TEST_CASE("compressed files are smaller, hold the same data, and every tool and h5dump read them",
          "[tools][compress]") {
  test::TempDir tmp;
  const std::string joints = test::run_pipeline(tmp, "table3-lognormal.toml", test::Stage::joints);
  const std::string plain = (tmp / "plain.h5").string(), packed = (tmp / "packed.h5").string();
  REQUIRE(test::run_tool("slice-cut", {joints, "--prune", "-o", plain}).exit_code == 0);
  REQUIRE(test::run_tool("slice-cut", {joints, "--prune", "--compress", "-o", packed}).exit_code ==
          0);
  const std::string gplain = (tmp / "gplain.h5").string(), gpacked = (tmp / "gpacked.h5").string();
  REQUIRE(test::run_tool("slice-vertices", {plain, "-o", gplain}).exit_code == 0);
  REQUIRE(test::run_tool("slice-vertices", {packed, "--compress", "-o", gpacked}).exit_code == 0);

  // The same blocks and geometry (the provenance differs: other inputs, other command lines).
  const auto a = slice::read_blocks(gplain), b = slice::read_blocks(gpacked);
  test::check_same(a, b);
  const auto plain_size = test::fs::file_size(gplain), packed_size = test::fs::file_size(gpacked);
  CAPTURE(plain_size, packed_size);
  CHECK(packed_size * 2 < plain_size);

  // HDF5's own tool sees the filters; the exports read the file.
  const test::fs::path dump = tmp / "dump.txt";
  REQUIRE(test::run_shell("h5dump -p -H -d /blocks/face_normal " + test::shell_quote(gpacked) +
                          " > " + test::shell_quote(dump)) == 0);
  const std::string text = test::read_bytes(dump);
  CHECK_THAT(
      text, Catch::Contains("SHUFFLE") && Catch::Contains("DEFLATE") && Catch::Contains("CHUNKED"));
  const std::string vtu = (tmp / "b.vtu").string();
  CHECK(test::run_tool("slice-export", {gpacked, "-o", vtu}).exit_code == 0);
  CHECK(test::run_tool("slice-info", {gpacked}).exit_code == 0);

  // Compressed files are reproducible too (the same command twice).
  const std::string first = test::read_bytes(packed);
  test::fs::remove(packed);
  REQUIRE(test::run_tool("slice-cut", {joints, "--prune", "--compress", "-o", packed}).exit_code ==
          0);
  CHECK(test::read_bytes(packed) == first);
}
