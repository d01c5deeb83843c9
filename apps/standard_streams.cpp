#include "standard_streams.hpp"

#include <unistd.h>

#include <algorithm>
#include <boost/program_options.hpp>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "vmas/error.hpp"

namespace vmas::cli {
namespace {

// Standard input copied to a temporary file; removed when done.
class StdinCopy {
 public:
  explicit StdinCopy(const std::string& extension) {
    const char* folder = std::getenv("TMPDIR");
    std::string name =
        std::string(folder && *folder ? folder : "/tmp") + "/vmas-stdin-XXXXXX." + extension;
    const int file = mkstemps(name.data(), static_cast<int>(extension.size() + 1));
    if (file < 0)
      throw IoError("standard input: cannot create a temporary file in " + name + ": " +
                    std::strerror(errno));
    path_ = name;
    std::vector<char> buffer(1 << 16);
    for (;;) {
      const ssize_t got = read(STDIN_FILENO, buffer.data(), buffer.size());
      if (got == 0) break;
      if (got < 0 && errno == EINTR) continue;
      if (got < 0) fail(file, "cannot read it");
      for (ssize_t done = 0; done < got;) {
        const ssize_t put = write(file, buffer.data() + done, static_cast<std::size_t>(got - done));
        if (put < 0 && errno == EINTR) continue;
        if (put < 0) fail(file, "cannot copy it to " + path_);
        done += put;
      }
    }
    if (close(file) != 0) fail(-1, "cannot copy it to " + path_);
  }
  ~StdinCopy() { std::remove(path_.c_str()); }
  StdinCopy(const StdinCopy&) = delete;
  StdinCopy& operator=(const StdinCopy&) = delete;
  const std::string& path() const { return path_; }

 private:
  [[noreturn]] void fail(int file, const std::string& what) {
    const std::string reason = std::strerror(errno);
    if (file >= 0) close(file);
    std::remove(path_.c_str());
    throw IoError("standard input: " + what + " (" + reason + ")");
  }
  std::string path_;
};

}  // namespace

void with_input_file(const std::string& path, const std::string& format,
                     const std::function<void(const std::string&)>& use) {
  if (!is_standard_stream(path)) return use(path);
  const StdinCopy copy(format);
  try {
    use(copy.path());
  } catch (const IoError& e) {
    std::string message = e.what();
    for (std::size_t at; (at = message.find(copy.path())) != std::string::npos;)
      message.replace(at, copy.path().size(), "standard input");
    throw IoError(message);
  }
}

void write_standard_output(const std::string& bytes) {
  if (std::fwrite(bytes.data(), 1, bytes.size(), stdout) != bytes.size() ||
      std::fflush(stdout) != 0)
    throw IoError(std::string("standard output: cannot write (") + std::strerror(errno) + ")");
}

void check_standard_input(const std::vector<std::string>& inputs, const std::string& input_format) {
  namespace po = boost::program_options;
  const auto dashes = std::count_if(inputs.begin(), inputs.end(), is_standard_stream);
  if (dashes > 1) throw po::error("only one input can be - (standard input)");
  if (dashes == 1 && input_format.empty())
    throw po::error("INPUT - (standard input) needs --input-format");
  if (dashes == 0 && !input_format.empty())
    throw po::error("--input-format is for INPUT - (standard input)");
}

}  // namespace vmas::cli
