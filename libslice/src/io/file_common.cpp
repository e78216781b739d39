#include "file_common.hpp"

#include <oneapi/tbb/parallel_for.h>

#include <array>
#include <charconv>
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

// What joints_file.cpp, blocks_file.cpp and geometry_file.cpp share: messages, the root header,
// the checks of a read dataset's shape.
namespace slice::h5file {

// Shortest text that reads back as the same double ("nan", "inf", "0.1").
std::string num(double v) {
  std::array<char, 32> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), r.ptr);
}

std::string row_text(const double* v, std::size_t n) {
  std::string s = "(";
  for (std::size_t i = 0; i < n; ++i) s += (i ? ", " : "") + num(v[i]);
  return s + ")";
}

std::string at(const std::string& dataset, std::size_t row) {
  return dataset + " row " + std::to_string(row);
}

std::string text(const At& a) { return at(a.dataset, a.row) + a.suffix; }
const std::string& text(const std::string& s) { return s; }

std::string str(std::int64_t v) { return std::to_string(v); }
std::string str(std::size_t v) { return std::to_string(v); }

// The faces of some blocks: the rows they take in /blocks/face_normal and the per-face datasets.
std::size_t face_count(std::span<const Block> blocks) {
  std::size_t faces = 0;
  for (const Block& b : blocks) faces += b.faces.size();
  return faces;
}

void check_runs(std::span<const Block> blocks,
                const std::function<void(std::size_t, std::size_t, std::size_t)>& check,
                bool concurrent) {
  constexpr std::size_t kRun = 4096;
  if (!concurrent || blocks.size() <= kRun) {  // one run, on this thread
    if (!blocks.empty()) check(0, blocks.size(), 0);
    return;
  }
  const std::size_t runs = (blocks.size() + kRun - 1) / kRun;
  std::vector<std::size_t> first_face(runs, 0);
  for (std::size_t r = 1; r < runs; ++r)
    first_face[r] = first_face[r - 1] + face_count(blocks.subspan((r - 1) * kRun, kRun));
  std::vector<std::exception_ptr> failure(runs);
  tbb::parallel_for(std::size_t(0), runs, [&](std::size_t r) {
    try {
      check(r * kRun, std::min(blocks.size(), (r + 1) * kRun), first_face[r]);
    } catch (...) {
      failure[r] = std::current_exception();
    }
  });
  for (const auto& f : failure)
    if (f) std::rethrow_exception(f);
}

void write_header(const Group& root, FileKind kind, const Provenance& prov, const JointSystem& js) {
  root.write_attribute<std::string>("schema", kSchemaName);
  root.write_attribute<std::int64_t>("schema_version", kSchemaVersion);
  root.write_attribute<std::string>("kind", to_string(kind));
  root.write_attribute<std::int64_t>("dimension", js.dimension);
  root.write_attribute("tool", prov.tool);
  root.write_attribute("tool_version", prov.version);
  root.write_attribute("command_line", prov.command_line);
  root.write_attribute("input", prov.input);
  root.write_attribute("input_sha256", prov.input_sha256);
  root.write_attribute("name", js.name);
  root.write_attribute("seed", js.seed);
}

[[noreturn]] void fail(const Group& g, const std::string& what) {
  throw Error(g.context().file, what, g.context().fix);
}

// A dataset must have `want` rows, as another dataset (`because`) says.
void expect_rows(const Group& g, const std::string& name, std::size_t got, std::size_t want,
                 const std::string& because) {
  if (got != want)
    fail(g, g.member_path(name) + " has " + str(got) + " rows; expected " + str(want) + " (" +
                because + ")");
}

// CSR offsets: n + 1 entries, starting at 0, never decreasing, ending at the flat length.
void check_offsets(const Group& g, const std::string& name, const std::vector<std::int64_t>& off,
                   std::size_t n, const std::string& n_what, std::size_t flat,
                   const std::string& flat_name) {
  const std::string p = g.member_path(name);
  if (off.size() != n + 1)
    fail(g,
         p + " has " + str(off.size()) + " rows; expected " + str(n + 1) + " (" + n_what + " + 1)");
  if (off[0] != 0) fail(g, at(p, 0) + " is " + str(off[0]) + "; offsets start at 0");
  for (std::size_t i = 1; i < off.size(); ++i)
    if (off[i] < off[i - 1])
      fail(g, at(p, i) + " is " + str(off[i]) + ", less than row " + str(i - 1) + " (" +
                  str(off[i - 1]) + "); offsets never decrease");
  if (off.back() != static_cast<std::int64_t>(flat))
    fail(g,
         p + " ends at " + str(off.back()) + " but " + flat_name + " has " + str(flat) + " rows");
}

Vec3 vec3(const std::vector<double>& v, std::size_t row) {
  return {v[3 * row], v[3 * row + 1], v[3 * row + 2]};
}

FileHeader read_root_header(const Group& root) {
  const std::string& file = root.context().file;
  if (!root.has_attribute("schema"))
    throw Error(file, "not a rockslice file (no root attribute schema)",
                "give a file written by a rockslice tool");
  FileHeader h;
  h.schema = root.read_attribute<std::string>("schema");
  if (h.schema != kSchemaName)
    throw Error(file, "root attribute schema is \"" + h.schema + "\", not \"" + kSchemaName + "\"",
                "give a file written by a rockslice tool");
  const auto version = root.read_attribute<std::int64_t>("schema_version");
  if (version > kSchemaVersion)
    throw Error(file,
                "written by a newer rockslice (root attribute schema_version is " + str(version) +
                    "; this one reads up to " + std::to_string(kSchemaVersion) + ")",
                "upgrade rockslice");
  if (version < 1) fail(root, "root attribute schema_version is " + str(version) + "; expected 1");
  h.schema_version = static_cast<int>(version);
  const auto kind = root.read_attribute<std::string>("kind");
  if (kind == to_string(FileKind::joints))
    h.kind = FileKind::joints;
  else if (kind == to_string(FileKind::blocks))
    h.kind = FileKind::blocks;
  else
    fail(root, "root attribute kind is \"" + kind + "\"; expected \"joints\" or \"blocks\"");
  const auto dimension = root.read_attribute<std::int64_t>("dimension");
  if (dimension != 3 && dimension != 2)
    throw Error(file, "root attribute dimension is " + str(dimension),
                "expected 3, or 2 for a section in (x, z); regenerate the file");
  h.dimension = static_cast<int>(dimension);
  h.provenance.tool = root.read_attribute<std::string>("tool");
  h.provenance.version = root.read_attribute<std::string>("tool_version");
  h.provenance.command_line = root.read_attribute<std::string>("command_line");
  h.provenance.input = root.read_attribute<std::string>("input");
  h.provenance.input_sha256 = root.read_attribute<std::string>("input_sha256");
  return h;
}

void expect_kind(const Group& root, FileKind want) {
  const FileHeader h = read_root_header(root);
  if (h.kind == want) return;
  const std::string fix = want == FileKind::joints ? "give a joints file (from slice-joints)"
                                                   : "give a blocks file (from slice-cut)";
  throw Error(root.context().file,
              std::string("root attribute kind is \"") + to_string(h.kind) + "\"; expected \"" +
                  to_string(want) + "\"",
              fix);
}

}  // namespace slice::h5file

namespace slice {

using namespace h5file;

const char* to_string(FileKind k) { return k == FileKind::joints ? "joints" : "blocks"; }

FileHeader read_header(const fs::path& in) {
  const h5::File f =
      h5::File::open(in, {in.string(), "regenerate it with the rockslice tool that made it"});
  return read_root_header(f.root());
}

}  // namespace slice
