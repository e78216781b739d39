#pragma once
// joints.h5 and blocks.h5, schema version 1 (docs/formats.md; why: docs/design.md, "Files and
// schema"). This module owns both formats: writers are atomic (written to "<out>.partial", renamed
// when complete) and deterministic (no time stamps: the same content gives the same bytes); readers
// validate everything and throw Error naming the file, the dataset, the row and the fix.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "slice/geometry.hpp"
#include "slice/scene.hpp"
#include "slice/stability_data.hpp"

namespace slice {

inline constexpr const char* kSchemaName = "rockslice";
inline constexpr int kSchemaVersion = 1;

enum class FileKind { joints, blocks };

/// The path of the HDF5 file a reader of this process has open, or nullptr. Async-signal-safe
/// (one atomic load): HDF5 1.10.8 itself crashes with SIGSEGV on some damaged files (found by
/// fuzzing, tests/fuzz/README.md), and a tool's SIGSEGV handler uses this to say which file.
const char* hdf5_input_being_read() noexcept;
const char* to_string(FileKind k);

/// Who made a file, from what: root attributes. No clock time, so reruns are byte-identical.
struct Provenance {
  std::string tool;          // e.g. "slice-joints"
  std::string version;       // rockslice version
  std::string command_line;  // as the user typed it
  std::string input;         // input file name(s), as given
  std::string input_sha256;  // hash of the input file's content (hex)
};

/// Records a further input in a provenance, as slice-joints records the files a scene names
/// (scene_files, scene.hpp): "; <file>" appended to `input`, "; <SHA-256 of its content>" to
/// `input_sha256`. Throws Error if the file cannot be read.
void add_input(Provenance& p, const std::filesystem::path& file);

/// The root attributes of any rockslice file.
struct FileHeader {
  std::string schema;
  int schema_version = 0;
  FileKind kind = FileKind::joints;
  int dimension = 3;
  Provenance provenance;
};

/// blocks.h5: the joint system it was cut from plus the blocks, and their geometry once
/// slice-vertices has computed it (/geometry; vertices.hpp). Anything that changes the blocks'
/// faces must reset `geometry`: the writer refuses geometry that does not match the faces.
struct BlockSystem {
  JointSystem joints;
  std::vector<Block> blocks;
  bool pruned = false;
  std::optional<Geometry> geometry;
  /// /contacts and /stability (slice-stability), of these very blocks and geometry: whatever
  /// changes them resets it.
  std::optional<StabilityData> stability;
};

/// The blocks' geometry, or Error(where, "the blocks have no vertices (no /geometry)", "run
/// slice-vertices on the blocks file first"): for every stage that needs vertices (the exports,
/// contacts, stability, sub-models). `where` names the file (the input, or the output not
/// written), or "/geometry" where the caller has no file.
const Geometry& geometry_of(const BlockSystem& bs, const std::string& where);

/// How files are written. compress: every dataset chunked, shuffled and deflated (HDF5's
/// built-in filters, which h5py and h5dump read); about 2-3x smaller, slower to write.
struct WriteOptions {
  bool compress = false;
};

void write_joints(const std::filesystem::path& out, const JointSystem& js, const Provenance& prov,
                  const WriteOptions& opt = {});
JointSystem read_joints(const std::filesystem::path& in);

void write_blocks(const std::filesystem::path& out, const BlockSystem& bs, const Provenance& prov,
                  const WriteOptions& opt = {});
BlockSystem read_blocks(const std::filesystem::path& in);

/// write_blocks while /geometry is computed (slice-vertices): the constructor starts writing the
/// joints and blocks (and the header) to `out`'s .partial on a thread of its own, which then
/// writes the runs of /geometry that geometry_sink() is given (compute_geometry's sink), as they
/// come; the sink checks each run against its blocks on the giver's thread (throwing the first
/// error), and the joints and blocks are checked meanwhile on the caller's threads. finish() waits
/// for all that (or, if no sink was asked for, checks and writes bs.geometry, if any), throws the
/// first error (the blocks' check first) and renames the file onto `out`. The bytes are
/// write_blocks'. Until finish() returns, nothing of bs may change but bs.geometry (and that only
/// if no sink was asked for). Errors of the writing thread are thrown by finish(); destroyed
/// unfinished, it waits for the thread and removes the .partial.
class BlocksFileWriter {
 public:
  /// Where the blocks come from: `made` by the caller (checked here), or `read` by read_blocks,
  /// which checked them, with nothing of them (joints, blocks) changed since: not checked again.
  enum class Blocks { made, read };
  BlocksFileWriter(const std::filesystem::path& out, const BlockSystem& bs, const Provenance& prov,
                   const WriteOptions& opt = {}, Blocks blocks = Blocks::made);
  ~BlocksFileWriter();
  BlocksFileWriter(const BlocksFileWriter&) = delete;
  BlocksFileWriter& operator=(const BlocksFileWriter&) = delete;
  /// Takes the runs of /geometry in block order (kGeometryRun blocks each, as compute_geometry
  /// hands them over), checks each and queues it for the writing thread, waiting only while the
  /// runs not yet taken hold more than 256 MiB (deflate, --compress, is slower than the geometry).
  /// Once the thread has stopped on an error, runs are dropped and finish() throws that error.
  GeometrySink geometry_sink();
  void finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Reads and checks the root attributes only (schema, version <= kSchemaVersion).
FileHeader read_header(const std::filesystem::path& in);

}  // namespace slice
