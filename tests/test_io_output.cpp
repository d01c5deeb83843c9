// Where outputs land (src/io/output.cpp): never over an input or a special file, all files of
// a run or none, nothing left behind by a failure or a signal.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <thread>

#include "io_fixture.hpp"
#include "vmas/error.hpp"
#include "vmas/io.hpp"

namespace vmas {
namespace {

namespace fs = std::filesystem;

class IoOutput : public test::IoTest {
 protected:
  std::string read(const std::string& name) const {
    std::ifstream in(path(name), std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }
  // Names in the folder that look like a temporary or a backup of ours.
  int leftovers() const {
    int count = 0;
    for (const auto& entry : fs::directory_iterator(dir_))
      count += entry.path().filename().string().find(".tmp-") != std::string::npos;
    return count;
  }

  // Until a writer's temporary shows up in the folder (at most 30 s).
  void wait_for_temporary() const {
    const auto start = std::chrono::steady_clock::now();
    while (leftovers() == 0 && std::chrono::steady_clock::now() - start < std::chrono::seconds(30))
      std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
};

void expect_refused(const std::vector<std::string>& inputs, const std::vector<std::string>& outputs,
                    const std::string& detail) {
  try {
    check_distinct_files(inputs, outputs);
    ADD_FAILURE() << "accepted " << outputs.back();
  } catch (const IoError& error) {
    EXPECT_NE(std::string(error.what()).find(detail), std::string::npos) << error.what();
  }
}

TEST_F(IoOutput, AnOutputIsNeverAnInputOrAnotherOutput) {
  const std::string input = write("scan.ply", "input");
  const std::string other = write("other.off", "other");
  check_distinct_files({input, other}, {path("skeleton.ply"), path("labels.txt")});
  expect_refused({input}, {input}, "is the input");
  expect_refused({input}, {(dir_ / "." / "sub" / ".." / "scan.ply").string()}, "is the input");
  fs::create_directory(path("sub"));
  expect_refused({input}, {(dir_ / "sub" / ".." / "scan.ply").string()}, "is the input");
  fs::create_hard_link(input, path("hard.ply"));
  expect_refused({input}, {path("hard.ply")}, "is the input");
  fs::create_symlink("scan.ply", path("link.ply"));
  expect_refused({input}, {path("link.ply")}, "is the input");
  expect_refused({other, input}, {path("out.ply"), path("./out.ply")}, "is also the output");
  fs::create_symlink("out.ply", path("to_out.ply"));  // dangling until written
  expect_refused({input}, {path("out.ply"), path("to_out.ply")}, "is also the output");
  EXPECT_EQ(read("scan.ply"), "input");
}

TEST_F(IoOutput, SpecialFilesAreRefusedAndLinksKept) {
  ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0600), 0);
  EXPECT_THROW(check_output(path("fifo")), IoError);
  EXPECT_THROW(write_labels(path("fifo"), {1, 2}), IoError);
  EXPECT_THROW(write_labels("/dev/null", {1, 2}), IoError);
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  EXPECT_TRUE(fs::is_fifo(path("fifo")));
  EXPECT_THROW(read_surface(path("fifo")), IoError);  // at once, not a hang

  write("target.txt", "old");
  ::chmod(path("target.txt").c_str(), 0640);
  fs::create_symlink("target.txt", path("link.txt"));
  write_labels(path("link.txt"), {3});
  EXPECT_TRUE(fs::is_symlink(path("link.txt")));
  EXPECT_EQ(read("target.txt"), "3\n");
  struct stat status;
  ASSERT_EQ(::stat(path("target.txt").c_str(), &status), 0);
  EXPECT_EQ(status.st_mode & 0777, 0640u);
  EXPECT_EQ(leftovers(), 0);
}

// Runs `action` in a child process; returns its wait status.
int in_child(const std::function<void()>& action) {
  const pid_t child = ::fork();
  if (child == 0) {
    try {
      action();
    } catch (const IoError&) {
      ::_exit(3);
    } catch (...) {
      ::_exit(4);
    }
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  return status;
}

TEST_F(IoOutput, FilesOfOneCallLandTogetherOrNotAtAll) {
  write("mesh.ply", "old mesh");
  write("labels.txt", "old labels");
  // The second file exceeds a file size limit: the first must not land either.
  const int status = in_child([&] {
    const rlimit limit{4096, 4096};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    write_files_atomically({{path("mesh.ply"), "new mesh"}, {path("labels.txt"), std::string(8192, 'x')}});
  });
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 3);  // an IoError ("file too large"), not SIGXFSZ
  EXPECT_EQ(read("mesh.ply"), "old mesh");
  EXPECT_EQ(read("labels.txt"), "old labels");
  EXPECT_EQ(leftovers(), 0);

  write_files_atomically({{path("mesh.ply"), "new mesh"}, {path("labels.txt"), "new labels"}});
  EXPECT_EQ(read("mesh.ply"), "new mesh");
  EXPECT_EQ(read("labels.txt"), "new labels");
  EXPECT_EQ(leftovers(), 0);
}

TEST_F(IoOutput, ATerminatedWriteLeavesNoTemporary) {
  write("big.ply", "old");
  const pid_t child = ::fork();
  if (child == 0) {
    const std::string contents(std::size_t{256} << 20, 'z');  // long enough to be caught at it
    write_file_atomically(path("big.ply"), contents);
    ::_exit(0);
  }
  wait_for_temporary();  // then terminate the writer
  ::kill(child, SIGTERM);
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the write ended before the signal: make it longer";
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  EXPECT_EQ(read("big.ply"), "old");
  EXPECT_EQ(leftovers(), 0);
}

// A signal the process ignores (nohup, a shell's background job) stays ignored: the write
// goes on and lands.
TEST_F(IoOutput, AnIgnoredSignalDoesNotStopTheWrite) {
  write("big.ply", "old");
  const std::size_t size = std::size_t{256} << 20;
  const pid_t child = ::fork();
  if (child == 0) {
    ::signal(SIGTERM, SIG_IGN);
    try {
      write_file_atomically(path("big.ply"), std::string(size, 'z'));
    } catch (...) {
      ::_exit(3);
    }
    ::_exit(0);
  }
  wait_for_temporary();
  ::kill(child, SIGTERM);
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_EQ(fs::file_size(path("big.ply")), size);
  EXPECT_EQ(leftovers(), 0);
}

}  // namespace
}  // namespace vmas
