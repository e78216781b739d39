#include "slice/hash.hpp"

#include <catch2/catch.hpp>

#include "slice/error.hpp"
#include "support/support.hpp"

TEST_CASE("SHA-256 of the FIPS 180-4 examples", "[hash]") {
  CHECK(slice::sha256_hex("") ==
        "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  CHECK(slice::sha256_hex("abc") ==
        "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  CHECK(slice::sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq") ==
        "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST_CASE("SHA-256 of a file equals that of its bytes -- a missing file is an Error", "[hash]") {
  test::TempDir tmp;
  const std::string text(1000, 'x');
  test::write_text(tmp / "a.txt", text);
  CHECK(slice::sha256_file(tmp / "a.txt") == slice::sha256_hex(text));
  CHECK_THROWS_AS(slice::sha256_file(tmp / "missing.txt"), slice::Error);
}
