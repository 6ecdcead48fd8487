// A fixture for tests that run the detexture command as a user does: a
// fresh folder per test (removed afterwards), the command run through the
// shell with stdout and stderr captured, and the exit code returned.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace detexture::test {

class CliFixture : public ::testing::Test {
 protected:
  /// The folder is the system's temporary folder / (prefix + test name).
  explicit CliFixture(std::string prefix) : prefix_(std::move(prefix)) {}

  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           (prefix_ + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  static std::string bytes_of(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  std::string bytes(const std::string& name) const { return bytes_of(path(name)); }

  /// Runs the CLI with args through the shell (so `shell_prefix` may set
  /// ulimits or the environment); returns the exit code and keeps stderr in
  /// stderr_ (stdout goes to stdout.txt in the folder).
  int run(const std::string& args, const std::string& shell_prefix = "") {
    const std::string cmd = shell_prefix + std::string(DETEXTURE_CLI_PATH) + " " + args + " > " +
                            path("stdout.txt") + " 2> " + path("stderr.txt");
    const int status = std::system(cmd.c_str());
    stderr_ = bytes("stderr.txt");
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  std::filesystem::path dir_;
  std::string stderr_;

 private:
  std::string prefix_;
};

}  // namespace detexture::test
