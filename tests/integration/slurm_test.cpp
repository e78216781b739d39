// Issue 14 item 4: the workflow runs on SLURM. The test starts a single-node cluster on this
// machine with the users' script pipelines/slurm-local (munged, slurmctld, slurmd, all state in
// a temporary folder), runs a 3-seed sweep through pipelines/profiles/slurm, checks that every
// job ran as a SLURM job, and stops the daemons by their pid files. It needs root (slurmd runs
// the jobs) and Debian's slurm-wlm and munge (pipelines/test installs them, and slurm-local
// installs what is missing); without them it fails, it does not skip (exclude it by hand with
// ctest -E SLURM where that is wanted).
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <csignal>
#include <map>
#include <regex>
#include <set>
#include <string>

#include "support/support.hpp"

namespace {

using test::fs::path;

const path kRoot = path(SLICE_TEST_DATA_DIR).parent_path().parent_path();
const path kCluster = kRoot / "pipelines" / "slurm-local";

// Starts the cluster in `dir`; stops it when it goes out of scope, whatever the test did.
class Cluster {
 public:
  explicit Cluster(const path& dir) : dir_(dir) {
    const path log = dir.parent_path() / "cluster-start.log";
    const int code =
        test::run_shell(test::shell_quote(kCluster) + " start " + test::shell_quote(dir) + " > " +
                        test::shell_quote(log) + " 2>&1");
    INFO(test::read_bytes(log));
    REQUIRE(code == 0);
    started_ = true;
  }
  ~Cluster() { stop(); }
  Cluster(const Cluster&) = delete;
  Cluster& operator=(const Cluster&) = delete;

  int stop() {
    if (!started_) return 0;
    started_ = false;
    return test::run_shell(test::shell_quote(kCluster) + " stop " + test::shell_quote(dir_));
  }
  // The daemons' pids, from their pid files.
  std::map<std::string, pid_t> pids() const {
    std::map<std::string, pid_t> p;
    for (const char* name : {"munged", "slurmctld", "slurmd"}) {
      p[name] = static_cast<pid_t>(
          std::stol(test::read_bytes(dir_ / "run" / (std::string(name) + ".pid"))));
    }
    return p;
  }
  std::string env() const { return "SLURM_CONF=" + test::shell_quote(dir_ / "slurm.conf") + " "; }

 private:
  path dir_;
  bool started_ = false;
};

}  // namespace

TEST_CASE("the workflow runs a 3-seed sweep on a single-node SLURM cluster",
          "[tools][workflow][slurm]") {
  INFO("needs root: slurmd runs the jobs (run the tests as root, or ctest -E SLURM)");
  REQUIRE(geteuid() == 0);
  test::TempDir tmp;
  Cluster cluster(tmp / "cluster");
  const auto pids = cluster.pids();

  const path scene = test::test_data_path("sweep.toml");
  test::write_text(tmp / "config.yaml", "scenes:\n  sweep: " + scene.string() +
                                            "\nseeds: 3\nout: " + (tmp / "out").string() +
                                            "\ntools: " + SLICE_TOOLS_DIR +
                                            "\nexports: []\nplots: false\nsummary: true\nthreads: 1\n");
  const path log = tmp / "snakemake.log";
  const int code = test::run_shell(
      "cd " + test::shell_quote(tmp.path()) + " && " + cluster.env() + "snakemake -s " +
      test::shell_quote(kRoot / "pipelines" / "Snakefile") + " --profile " +
      test::shell_quote(kRoot / "pipelines" / "profiles" / "slurm") + " --configfile " +
      test::shell_quote(tmp / "config.yaml") + " > " + test::shell_quote(log) + " 2>&1");
  INFO(test::read_bytes(log));
  REQUIRE(code == 0);

  // Every job of the sweep (3 x joints, cut, vertices; one summary) ran under SLURM: slurmd
  // wrote its output to slurm-logs/<rule>-<SLURM job id>.out, and the controller knows the job
  // as completed.
  std::multiset<std::string> rules;
  std::set<long> job_ids;
  const std::regex name(R"(([a-z_]+)-([0-9]+)\.out)");
  for (const auto& entry : test::fs::directory_iterator(tmp / "slurm-logs")) {
    const std::string file = entry.path().filename().string();
    std::smatch m;
    REQUIRE(std::regex_match(file, m, name));
    rules.insert(m[1]);
    job_ids.insert(std::stol(m[2]));
    const std::string out = test::read_bytes(entry.path());
    CAPTURE(file, out);
    CHECK_THAT(out, Catch::Contains("rule " + m[1].str() + ":"));
    CHECK_THAT(out, Catch::Contains("1 of 1 steps (100%) done"));
    const path state = tmp / ("job-" + m[2].str());
    REQUIRE(test::run_shell(cluster.env() + "scontrol show job " + m[2].str() + " > " +
                            test::shell_quote(state) + " 2>&1") == 0);
    CHECK_THAT(test::read_bytes(state), Catch::Contains("JobState=COMPLETED"));
  }
  CHECK(rules.count("joints") == 3);
  CHECK(rules.count("cut") == 3);
  CHECK(rules.count("vertices") == 3);
  CHECK(rules.count("summary") == 1);
  CHECK(job_ids.size() == 10);

  const std::string table =
      test::read_bytes(tmp / "out" / "sweep" / "summary" / "realizations.csv");
  CHECK(std::count(table.begin(), table.end(), '\n') == 4);  // header + 3 seeds

  // The daemons this test started are gone once stopped.
  REQUIRE(cluster.stop() == 0);
  for (const auto& [daemon, pid] : pids) {
    CAPTURE(daemon);
    CHECK(kill(pid, 0) == -1);
  }
}
