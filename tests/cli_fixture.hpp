#pragma once
// Running the `vmas` binary from tests: a fresh folder per test, the command's exit code and
// captured streams, and the check that an error is one line naming what is at fault.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace vmas::test {

struct CliResult {
  int exit_code;
  std::string out, err;
};

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

// A one-line error on stderr that names `what`.
inline void expect_one_line_error(const CliResult& r, const std::string& what) {
  EXPECT_FALSE(r.err.empty());
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
  EXPECT_NE(r.err.find(what), std::string::npos) << r.err;
}

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("vmas_cli_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // Runs `vmas ARGUMENTS` (VMAS_CLI is set by CMake).
  CliResult run(const std::string& arguments) const {
    const std::string command = std::string(VMAS_CLI) + " " + arguments + " > " +
                                (dir_ / "stdout").string() + " 2> " + (dir_ / "stderr").string();
    const int status = std::system(command.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_text(dir_ / "stdout"),
            read_text(dir_ / "stderr")};
  }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  void write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name) << text;
  }

  std::filesystem::path dir_;
};

}  // namespace vmas::test
