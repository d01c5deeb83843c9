// Where the IO stage's files land: every output is checked before a run (never an input, never
// another output of the run, never a device or FIFO), and the outputs of one run are written as
// one transaction (temporaries beside their targets, then renames; on any failure, a signal
// included, no temporary is left and every earlier file is intact).
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <random>
#include <stdexcept>

#include "io/internal.hpp"
#include "vmas/io.hpp"

namespace vmas {
namespace {

namespace fs = std::filesystem;
using io_internal::fail;
using io_internal::quote;

// The file a path names once its symbolic links are followed (a link keeps being a link: we
// write to its target). Relative links are relative to the link's folder.
std::string link_target(const std::string& path) {
  fs::path current = path;
  for (int hop = 0; hop < 40; ++hop) {
    std::error_code error;
    if (!fs::is_symlink(fs::symlink_status(current, error))) return current.string();
    const fs::path target = fs::read_symlink(current, error);
    if (error) fail(path, "cannot follow the symbolic link (" + error.message() + ")");
    current = target.is_absolute() ? target : current.parent_path() / target;
  }
  fail(path, "too many levels of symbolic links");
}

// A name that two spellings of the same path share (folders' links resolved, "." and ".."
// gone), for outputs that do not exist yet.
std::string canonical_name(const std::string& path) {
  std::error_code error;
  const fs::path name = fs::weakly_canonical(fs::absolute(path, error), error);
  return error ? fs::absolute(path).lexically_normal().string() : name.string();
}

struct FileIdentity {
  bool exists = false;
  dev_t device = 0;
  ino_t inode = 0;
  std::string name;  // canonical_name of the link's target
};

FileIdentity identify(const std::string& path) {
  FileIdentity identity;
  struct stat status;
  if (::stat(path.c_str(), &status) == 0) {
    identity.exists = true;
    identity.device = status.st_dev;
    identity.inode = status.st_ino;
  }
  identity.name = canonical_name(link_target(path));
  return identity;
}

bool same_file(const FileIdentity& a, const FileIdentity& b) {
  if (a.exists && b.exists) return a.device == b.device && a.inode == b.inode;
  return a.name == b.name;
}

// Creates a new empty file beside `path` under a random name (O_EXCL, so no one else uses it;
// mode 0666 lets umask decide); returns its descriptor, or -1 with errno set.
int create_temporary(const std::string& path, std::string& temporary) {
  std::random_device entropy;
  for (int attempt = 0; attempt < 100; ++attempt) {
    char suffix[16];
    std::snprintf(suffix, sizeof suffix, ".tmp-%08x", static_cast<unsigned>(entropy()));
    temporary = path + suffix;
    const int descriptor = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (descriptor >= 0 || errno != EEXIST) return descriptor;
  }
  return -1;  // errno is EEXIST
}

// What a signal handler may touch while files are written: the temporaries to remove, and
// whether a step that must not be cut short is under way (a temporary being created and
// registered, the renames): the signal then waits until it is done.
constexpr int kMaxFiles = 16;
char g_temporaries[kMaxFiles][PATH_MAX];
volatile sig_atomic_t g_temporary_count = 0;
volatile sig_atomic_t g_deferring = 0;
volatile sig_atomic_t g_pending_signal = 0;
constexpr int kCaughtSignals[] = {SIGINT, SIGTERM, SIGHUP};
struct sigaction g_previous[NSIG];
bool g_caught[NSIG];

extern "C" void on_signal_while_writing(int signal) {
  if (g_deferring) {
    g_pending_signal = signal;
    return;
  }
  for (int i = 0; i < g_temporary_count; ++i) ::unlink(g_temporaries[i]);
  g_temporary_count = 0;
  // The signal's own action, as if we had not been here: it is delivered when this returns.
  ::sigaction(signal, &g_previous[signal], nullptr);
  ::raise(signal);
}

// While alive: SIGINT, SIGTERM and SIGHUP remove the temporaries before they take effect
// (signals the process ignores, as under nohup or in a background job, stay ignored), and
// SIGXFSZ (a file size limit) is ignored, so that the write fails with "File too large"
// instead of killing the process without a word.
class SignalGuard {
 public:
  SignalGuard() {
    struct sigaction action {};
    action.sa_handler = on_signal_while_writing;
    sigemptyset(&action.sa_mask);
    for (int signal : kCaughtSignals) {
      ::sigaction(signal, nullptr, &g_previous[signal]);
      g_caught[signal] = g_previous[signal].sa_handler != SIG_IGN;
      if (g_caught[signal]) ::sigaction(signal, &action, nullptr);
    }
    struct sigaction ignore {};
    ignore.sa_handler = SIG_IGN;
    sigemptyset(&ignore.sa_mask);
    ::sigaction(SIGXFSZ, &ignore, &previous_file_size_);
  }
  ~SignalGuard() {
    for (int signal : kCaughtSignals)
      if (g_caught[signal]) ::sigaction(signal, &g_previous[signal], nullptr);
    ::sigaction(SIGXFSZ, &previous_file_size_, nullptr);
    g_temporary_count = 0;
  }
  SignalGuard(const SignalGuard&) = delete;
  SignalGuard& operator=(const SignalGuard&) = delete;

  // Registers a temporary for removal on a signal.
  static void add_temporary(const std::string& temporary) {
    std::snprintf(g_temporaries[g_temporary_count], PATH_MAX, "%s", temporary.c_str());
    g_temporary_count = g_temporary_count + 1;
  }

 private:
  struct sigaction previous_file_size_ {};
};

// Holds signals back (on any thread) for its lifetime, then lets a held one take its course.
struct Deferred {
  Deferred() { g_deferring = 1; }
  ~Deferred() {
    g_deferring = 0;
    if (g_pending_signal != 0) {
      const int signal = g_pending_signal;
      g_pending_signal = 0;
      on_signal_while_writing(signal);
    }
  }
  Deferred(const Deferred&) = delete;
  Deferred& operator=(const Deferred&) = delete;
};

// create_temporary, the new file registered with the guard before a signal can strike.
int create_registered_temporary(const std::string& target, std::string& temporary) {
  const Deferred deferred;
  const int descriptor = create_temporary(target, temporary);
  const int error = errno;
  if (descriptor >= 0) SignalGuard::add_temporary(temporary);
  errno = error;
  return descriptor;
}

// Writes all of `contents` to a new temporary beside `target`, with the mode of the file it
// replaces; returns "" or the reason it failed.
std::string write_temporary(const std::string& target, const std::string& contents,
                            std::string& temporary) {
  const int descriptor = create_registered_temporary(target, temporary);
  if (descriptor < 0) {
    temporary.clear();  // the name tried last is not ours
    return std::strerror(errno);
  }
  std::string problem;
  struct stat existing;
  if (::stat(target.c_str(), &existing) == 0) ::fchmod(descriptor, existing.st_mode & 07777);
  for (std::size_t written = 0; written < contents.size() && problem.empty();) {
    const ssize_t result =
        ::write(descriptor, contents.data() + written, contents.size() - written);
    if (result >= 0)
      written += static_cast<std::size_t>(result);
    else if (errno != EINTR)
      problem = errno == EFBIG ? "file too large" : std::strerror(errno);
  }
  if (::close(descriptor) != 0 && problem.empty()) problem = std::strerror(errno);
  return problem;
}

std::mutex g_writing;  // one transaction at a time: the signal handler's lists are global

// The file `path` stands for (its link's target), failing when it is a directory or a special
// file or when its folder does not exist.
std::string checked_target(const std::string& path) {
  const std::string target = link_target(path);
  std::error_code error;
  const fs::file_status status = fs::status(target, error);
  if (fs::is_directory(status)) fail(path, "cannot write: is a directory");
  if (fs::exists(status) && !fs::is_regular_file(status))
    fail(path, "cannot write: is " + io_internal::file_kind(status.type()) +
                   "; vmas writes regular files only");
  const fs::path folder = fs::path(target).parent_path();
  if (!folder.empty() && !fs::is_directory(folder, error))
    fail(path, "cannot write: folder " + quote(folder.string()) + " does not exist");
  return target;
}

}  // namespace

void check_output(const std::string& path) {
  const std::string target = checked_target(path);
  // Only creating a file tells for sure: access(W_OK) passes for root and misses some mounts.
  const std::lock_guard<std::mutex> lock(g_writing);
  const SignalGuard guard;
  std::string temporary;
  const int descriptor = create_registered_temporary(target, temporary);
  if (descriptor < 0) {
    const std::string reason = std::strerror(errno);
    const std::string folder = fs::path(target).parent_path().string();
    fail(path, "cannot write in folder " + quote(folder.empty() ? "." : folder) + " (" + reason +
                   ")");
  }
  ::close(descriptor);
  ::unlink(temporary.c_str());
}

void check_medial_mesh_format(const std::string& path) {
  const std::string extension = io_internal::lower_extension(path);
  if (extension != ".ply" && extension != ".ma")
    fail(path, "cannot write a medial mesh as " + quote(extension) + " (expected .ply or .ma)");
}

void check_surface_format(const std::string& path) {
  const std::string extension = io_internal::lower_extension(path);
  if (extension != ".ply" && extension != ".off" && extension != ".xyz")
    fail(path, "cannot write " + quote(extension) + " files (expected .ply, .off or .xyz)");
}

void check_medial_mesh_output(const std::string& path) {
  check_output(path);
  check_medial_mesh_format(path);
}

void check_surface_output(const std::string& path) {
  check_output(path);
  check_surface_format(path);
}

void check_distinct_files(const std::vector<std::string>& inputs,
                          const std::vector<std::string>& outputs) {
  std::vector<FileIdentity> read;
  for (const std::string& input : inputs) read.push_back(identify(input));
  std::vector<FileIdentity> written;
  for (std::size_t o = 0; o < outputs.size(); ++o) {
    const FileIdentity output = identify(outputs[o]);
    for (std::size_t i = 0; i < inputs.size(); ++i)
      if (same_file(output, read[i]))
        fail(outputs[o], "is the input " + quote(inputs[i]) +
                             " of this run; vmas never writes over what it reads");
    for (std::size_t other = 0; other < written.size(); ++other)
      if (same_file(output, written[other]))
        fail(outputs[o], "is also the output " + quote(outputs[other]) + " of this run");
    written.push_back(output);
  }
}

void write_files_atomically(const std::vector<OutputFile>& files) {
  if (static_cast<int>(files.size()) > kMaxFiles)
    throw std::logic_error("write_files_atomically: at most 16 files at once");
  std::vector<std::string> targets;
  for (const OutputFile& file : files) targets.push_back(checked_target(file.path));
  const std::lock_guard<std::mutex> lock(g_writing);
  std::vector<std::string> temporaries(files.size()), backups(files.size());
  std::string problem, not_restored;
  std::size_t failed = 0;  // the file `problem` is about
  {
    const SignalGuard guard;
    for (; failed < files.size() && problem.empty(); ++failed)
      problem = write_temporary(targets[failed], files[failed].contents, temporaries[failed]);
    if (!problem.empty()) --failed;

    // The renames, with signals held back: every file lands, or the earlier ones come back
    // from hard links taken before (an error here is rare: the folder changed under us). A
    // file that existed and could not be linked (no hard links on that file system) stays
    // as the new one if a later rename fails: the message says so.
    std::size_t renamed = 0;
    if (problem.empty()) {
      const Deferred deferred;
      std::vector<bool> existed(files.size(), false);
      for (std::size_t i = 0; i < files.size(); ++i) {
        existed[i] = ::access(targets[i].c_str(), F_OK) == 0;
        backups[i] = temporaries[i] + ".old";
        if (!existed[i] || ::link(targets[i].c_str(), backups[i].c_str()) != 0) backups[i].clear();
      }
      for (; renamed < files.size(); ++renamed)
        if (std::rename(temporaries[renamed].c_str(), targets[renamed].c_str()) != 0) {
          problem = std::strerror(errno);
          failed = renamed;
          break;
        }
      if (!problem.empty())
        for (std::size_t i = 0; i < renamed; ++i) {
          if (!backups[i].empty()) {
            if (std::rename(backups[i].c_str(), targets[i].c_str()) == 0)
              backups[i].clear();
            else
              not_restored += "; the earlier " + targets[i] + " is kept as " + backups[i];
          } else if (!existed[i]) {
            ::unlink(targets[i].c_str());
          } else {
            not_restored += "; " + targets[i] + " was replaced";
          }
        }
      for (std::size_t i = 0; i < files.size(); ++i)
        if (!backups[i].empty() && (problem.empty() || i >= renamed)) ::unlink(backups[i].c_str());
    }
    for (std::size_t i = renamed; i < files.size(); ++i)
      if (!temporaries[i].empty()) ::unlink(temporaries[i].c_str());
  }
  if (!problem.empty())
    fail(files[failed].path, "cannot write (" + problem + ")" + not_restored);
}

void write_file_atomically(const std::string& path, const std::string& contents) {
  write_files_atomically({{path, contents}});
}

}  // namespace vmas
