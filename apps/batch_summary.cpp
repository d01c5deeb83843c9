#include "batch_summary.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "vmas/error.hpp"

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace vmas::cli {
namespace {

// A line of the file, and its input with the line parsed; "" (null) for a line that is not a JSON
// object with one.
struct Line {
  std::string text, input;
  json parsed;
};

std::vector<Line> read_lines(const std::string& path) {
  std::vector<Line> lines;
  std::ifstream in(path);
  for (std::string text; std::getline(in, text);) {
    if (text.empty()) continue;
    json line = json::parse(text, nullptr, false);
    if (line.is_object() && line.contains("input") && line["input"].is_string()) {
      std::string input = line["input"].get<std::string>();
      lines.push_back({text, std::move(input), std::move(line)});
    } else {
      lines.push_back({text, "", json()});
    }
  }
  return lines;
}

// An exclusive lock on `path`, created if missing, held while it lives.
class FileLock {
 public:
  explicit FileLock(const std::string& path)
      : fd_(::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644)) {
    if (fd_ < 0) throw IoError(path + ": cannot create the summary's lock (" + std::strerror(errno) + ")");
    while (::flock(fd_, LOCK_EX) != 0)
      if (errno != EINTR) {
        const std::string problem = std::strerror(errno);
        ::close(fd_);
        throw IoError(path + ": cannot lock it (" + problem + ")");
      }
  }
  ~FileLock() { ::close(fd_); }  // releases the lock
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

}  // namespace

std::map<std::string, json> BatchSummary::read() const {
  std::map<std::string, json> by_input;
  for (Line& line : read_lines(path_))
    if (!line.input.empty()) by_input[line.input] = std::move(line.parsed);
  return by_input;
}

void BatchSummary::merge(const json& line) const {
  const std::string input = line.at("input").get<std::string>();
  const FileLock lock(path_ + ".lock");
  std::vector<Line> lines = read_lines(path_);
  bool replaced = false;
  for (Line& old : lines)
    if (old.input == input) {
      old.text = line.dump();
      replaced = true;
    }
  if (!replaced) lines.push_back({line.dump(), input, json()});
  // Only the holder of the lock writes the temporary file.
  const std::string temporary = path_ + ".tmp";
  {
    std::ofstream out(temporary, std::ios::trunc);
    for (const Line& kept : lines) out << kept.text << '\n';
    out.flush();
    if (!out) throw IoError(temporary + ": cannot write the summary");
  }
  std::error_code error;
  fs::rename(temporary, path_, error);
  if (error) throw IoError(path_ + ": cannot replace the summary (" + error.message() + ")");
}

std::string reason_to_run(const json* line, const std::vector<std::string>& options,
                          const std::string& input, const std::string& output) {
  if (line == nullptr) return "not run yet";
  if (line->contains("error"))
    return "failed: " + ((*line)["error"].is_string() ? (*line)["error"].get<std::string>()
                                                      : (*line)["error"].dump());
  if (!line->contains("batch_options") || (*line)["batch_options"] != json(options))
    return "last run with other options";
  std::error_code error;
  const auto size = fs::file_size(output, error);
  if (error) return output + " is missing";
  if (size == 0) return output + " is empty";
  const auto output_time = fs::last_write_time(output, error);
  if (error) return output + " is missing";
  const auto input_time = fs::last_write_time(input, error);
  if (error) return "cannot read " + input;
  return output_time > input_time ? "" : "changed since " + output + " was written";
}

}  // namespace vmas::cli
