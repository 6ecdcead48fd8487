// Tiled, out-of-core and streaming runs of the command line: the out-of-core
// output is the in-memory tiled output byte for byte, temporary files never
// outlive the run, and a failing tile leaves nothing at the output path.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "cli_fixture.h"

namespace fs = std::filesystem;

namespace detexture {
namespace {

class CliTiling : public test::CliFixture {
 protected:
  CliTiling() : CliFixture("detexture_cli_tiling_") {}
  void SetUp() override {
    CliFixture::SetUp();
    fs::create_directories(dir_ / "tmp");
  }
  bool temp_empty() const { return fs::is_empty(dir_ / "tmp"); }
  // 8k points of a bumpy sphere, made once per test.
  void make_cloud(const std::string& extra = "") {
    ASSERT_EQ(run("synth --shape sphere --texture bumps -n 8000 --ground-truth-points 100 -o " +
                  path("in.ply") + " " + extra),
              0)
        << stderr_;
  }
};

TEST_F(CliTiling, SynthInBlocksWritesTheSameBytes) {
  make_cloud();
  ASSERT_EQ(run("synth --shape sphere --texture bumps -n 8000 --ground-truth-points 100 -o " +
                path("blocks.ply") + " --block 3001"),
            0)
      << stderr_;
  EXPECT_EQ(bytes("in.ply"), bytes("blocks.ply"));
  EXPECT_EQ(bytes("in.gt.ply"), bytes("blocks.gt.ply"));
}

TEST_F(CliTiling, OutOfCoreIsTheInMemoryTiledRunByteForByte) {
  make_cloud();
  const std::string common = " -q -r 0.1 --tile 0.6 --halo 2r";
  ASSERT_EQ(run(path("in.ply") + " -o " + path("mem.ply") + common), 0) << stderr_;
  ASSERT_EQ(run(path("in.ply") + " -o " + path("ooc.ply") + common + " --temp-dir " + path("tmp") +
                " --stats " + path("stats.json")),
            0)
      << stderr_;
  const std::string mem = bytes("mem.ply"), ooc = bytes("ooc.ply");
  EXPECT_FALSE(mem.empty());
  EXPECT_TRUE(mem == ooc);
  EXPECT_TRUE(temp_empty());
  // The per-tile log: 2 x 2 x 2 tiles of 0.6 over the sphere of diameter 1.
  const std::string stats = bytes("stats.json");
  EXPECT_NE(stats.find("\"grid\": [2, 2, 2]"), std::string::npos) << stats;
  EXPECT_NE(stats.find("\"tiles_run\": 8"), std::string::npos) << stats;
  EXPECT_NE(stats.find("\"core_points\""), std::string::npos);
}

TEST_F(CliTiling, OutOfCoreWithoutNormalsAndFloats) {
  make_cloud("--float --no-normals");
  const std::string common = " -q -f -r 0.1 --tile 0.6 --halo 2r";
  ASSERT_EQ(run(path("in.ply") + " -o " + path("mem.ply") + common), 0) << stderr_;
  ASSERT_EQ(run(path("in.ply") + " -o " + path("ooc.ply") + common + " --temp-dir " + path("tmp")),
            0)
      << stderr_;
  EXPECT_TRUE(bytes("mem.ply") == bytes("ooc.ply"));
  EXPECT_TRUE(temp_empty());
}

// A tile refused by the memory guard fails the run: exit 5, a message naming
// the tile, no output and no temporary files.
TEST_F(CliTiling, AFailedTileLeavesNothingBehind) {
  make_cloud();
  EXPECT_EQ(run(path("in.ply") + " -o " + path("out.ply") +
                " -q -r 0.1 --tile 0.6 --memory-limit 100k --temp-dir " + path("tmp")),
            5)
      << stderr_;
  EXPECT_NE(stderr_.find("tile "), std::string::npos) << stderr_;
  EXPECT_FALSE(fs::exists(path("out.ply")));
  EXPECT_TRUE(temp_empty());
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_EQ(entry.path().filename().string().find(".out.ply"), std::string::npos) << entry.path();
}

// r from the texture scale: the out-of-core run estimates it on its sample,
// which is the whole cloud up to 1M points (in spatial order, as in memory).
TEST_F(CliTiling, OutOfCoreEstimatesRFromAWholeSample) {
  make_cloud();
  ASSERT_EQ(run(path("in.ply") + " -o " + path("mem.ply") + " -q --tile 0.6"), 0) << stderr_;
  ASSERT_EQ(
      run(path("in.ply") + " -o " + path("ooc.ply") + " -q --tile 0.6 --temp-dir " + path("tmp")),
      0)
      << stderr_;
  EXPECT_TRUE(bytes("mem.ply") == bytes("ooc.ply"));
}

// --memory-limit alone: the whole cloud fits 8 MiB (8k points at ~340 B per
// point with r = 0.05), so the run is the plain one; it does not fit 3 MiB,
// so the run goes in tiles, each within the budget.
TEST_F(CliTiling, MemoryLimitChoosesTiles) {
  make_cloud();
  const std::string common = " -q -f -r 0.05 --halo 2r --stats " + path("stats.json");
  ASSERT_EQ(run(path("in.ply") + " -o " + path("plain.ply") + common + " --memory-limit 8M"), 0)
      << stderr_;
  EXPECT_EQ(bytes("stats.json").find("\"tiling\""), std::string::npos);
  ASSERT_EQ(run(path("in.ply") + " -o " + path("tiled.ply") + common + " --memory-limit 3M"), 0)
      << stderr_;
  const std::string stats = bytes("stats.json");
  EXPECT_NE(stats.find("\"tiling\""), std::string::npos) << stats;
  EXPECT_NE(stats.find("largest fitting"), std::string::npos) << stats;
  // A halo holding more than the budget: no tiles fit, and the plain run's
  // memory guard refuses (exit 5); with --tile auto the tiling says so.
  EXPECT_EQ(run(path("in.ply") + " -o " + path("no.ply") + " -q -r 0.1 --memory-limit 4M"), 5);
  EXPECT_NE(stderr_.find("the neighborhoods would need"), std::string::npos) << stderr_;
  EXPECT_EQ(run(path("in.ply") + " -o " + path("no.ply") +
                " -q -r 0.1 --memory-limit 4M "
                "--tile auto"),
            5);
  EXPECT_NE(stderr_.find("no tile size fits"), std::string::npos) << stderr_;
}

// SIGINT, SIGTERM and SIGHUP during an out-of-core run remove the tile bins
// and the hidden output, and exit 128 + the signal.
TEST_F(CliTiling, SignalsRemoveTheTileBins) {
  ASSERT_EQ(run("synth --shape sphere --texture bumps -n 60000 --ground-truth-points 100 -o " +
                path("in.ply")),
            0);
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    const std::string out = path("out.ply"), in = path("in.ply"), tmp = path("tmp");
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      std::freopen("/dev/null", "w", stderr);
      execl(DETEXTURE_CLI_PATH, DETEXTURE_CLI_PATH, in.c_str(), "-o", out.c_str(), "-q", "-r",
            "0.05", "--tile", "0.3", "--temp-dir", tmp.c_str(), "--threads", "1",
            static_cast<char*>(nullptr));
      _exit(99);
    }
    bool sent = false;
    int status = 0;
    const auto t0 = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(120)) {
      if (waitpid(pid, &status, WNOHANG) == pid) break;
      if (!sent && !temp_empty()) {
        bool bins = false;
        for (const auto& d : fs::directory_iterator(dir_ / "tmp"))
          bins = bins || !fs::is_empty(d.path());
        if (bins) {
          kill(pid, sig);
          sent = true;
        }
      }
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    if (!sent) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      FAIL() << "the tile bins never showed";
    }
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 128 + sig);
    EXPECT_TRUE(temp_empty());
    EXPECT_FALSE(fs::exists(out));
    for (const auto& entry : fs::directory_iterator(dir_))
      EXPECT_EQ(entry.path().filename().string().find(".out.ply"), std::string::npos);
  }
}

TEST_F(CliTiling, OutOfCoreRefusesWhatItCannotDo) {
  make_cloud();
  EXPECT_EQ(run(path("in.ply") + " -o " + path("out.xyz") + " -q -r 0.1 --temp-dir " + path("tmp")),
            2);
  EXPECT_EQ(run(path("in.ply") + " -o " + path("out.ply") +
                " -q -r 0.1 --texture-fields --temp-dir " + path("tmp")),
            2);
  EXPECT_TRUE(temp_empty());
}

}  // namespace
}  // namespace detexture
