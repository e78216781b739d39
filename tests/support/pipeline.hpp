#pragma once
// The real tools chained on a data/ scene, and bad-scene checks, shared by integration tests.
#include <string>
#include <vector>

#include "support/support.hpp"

namespace test {

enum class Stage {
  joints,    // slice-joints scene -o joints.h5
  blocks,    // ... | slice-cut --prune -o blocks.h5
  geometry,  // ... | slice-vertices -o geom.h5
};

/// Runs the pipeline on data/<scene> into tmp up to `last` (Catch2 REQUIREs every exit code);
/// returns the path of the last output.
std::string run_pipeline(const TempDir& tmp, const std::string& scene, Stage last);

/// The same three tools on a scene text, written to tmp/<prefix>scene.toml: slice-joints ->
/// <prefix>joints.h5, slice-cut --prune -> <prefix>blocks.h5, slice-vertices -> <prefix>geom.h5
/// (Catch2 REQUIREs every exit code, INFO shows the tool's stderr). A prefix keeps two scenes,
/// or run_pipeline's files, apart in one tmp. Returns the path of <prefix>geom.h5.
std::string geometry_of_text(const TempDir& tmp, const std::string& scene,
                             const std::string& prefix = "");

/// Table 3's persistent scene at 2.0 m spacing, cut and pruned into tmp/b.h5 (125,313 blocks:
/// slice-vertices takes about a second to write their geometry, long enough to catch it
/// mid-write). Returns the path of b.h5.
std::string table3_2m_blocks(const TempDir& tmp);

/// Starts a built tool in the background (posix_spawn; the caller waits for it). Its pid.
int spawn_tool(const std::string& tool, const std::vector<std::string>& args);

struct BadScene {
  std::string name;                // what is wrong
  std::string text;                // the scene
  std::vector<std::string> words;  // the error line must contain each, e.g. ":6", "spacing"
};

/// slice-joints on each bad scene: exit 1, one line "slice-joints: error: bad.toml:..."
/// containing the words, no output and no .partial left.
void check_bad_scenes(const std::vector<BadScene>& cases);

/// A refused run: exit 1, one line "<tool>: error: ..." holding every word.
void check_refused(const ToolRun& r, const std::string& tool,
                   const std::vector<std::string>& words);

/// Runs an h5py script (Debian's python3) on `file`, which it sees as `f` (opened r+): to craft
/// bad files.
void edit_h5(const fs::path& file, const std::string& body);

}  // namespace test
