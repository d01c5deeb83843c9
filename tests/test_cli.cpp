// The `vmas` command line: exit codes, one-line errors, no output left behind on failure.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "cli_fixture.hpp"
#include "test_shapes.hpp"
#include "vmas/io.hpp"
#include "vmas/vmas.hpp"

namespace vmas {
namespace {

namespace fs = std::filesystem;

using Result = test::CliResult;
using test::expect_one_line_error;
using test::read_text;

class Cli : public test::CliTest {
 protected:
  // Files in the folder besides the captured streams.
  std::size_t file_count() const {
    std::size_t count = 0;
    for (const auto& entry : fs::directory_iterator(dir_))
      count += entry.path().filename() != "stdout" && entry.path().filename() != "stderr";
    return count;
  }

  // A 20 x 20 grid of a flat square with its normals: data that encloses nothing.
  void write_plane(const std::string& name) const {
    std::ostringstream plane;
    for (int i = 0; i < 20; ++i)
      for (int j = 0; j < 20; ++j) plane << i * 0.05 << " " << j * 0.05 << " 0 0 0 1\n";
    write(name, plane.str());
  }
};

TEST_F(Cli, SkeletonizesAMeshAndWritesLabels) {
  write_surface(path("capsule.off"), test::capsule(0.2, 1.0, 8, 24));
  const Result r = run("skeletonize " + path("capsule.off") + " --spheres 6 -o " + path("out.ply") +
                       " --labels " + path("labels.txt"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("6 spheres"), std::string::npos) << r.out;
  const MedialMesh mesh = read_medial_mesh(path("out.ply"));
  EXPECT_EQ(mesh.spheres.size(), 6u);
  std::ifstream labels(path("labels.txt"));
  int label = 0, lines = 0;
  while (labels >> label) {
    EXPECT_TRUE(label >= 0 && label < 6);
    ++lines;
  }
  EXPECT_EQ(lines, static_cast<int>(read_surface(path("capsule.off")).points.size()));
}

TEST_F(Cli, LabelsCoverEveryPointOfTheFile) {
  // A NaN line (a scanner's "no point") and a repeated point: labelled -1, not left out.
  const test::Sample s = test::sample_sphere(Vec3::Zero(), 1.0, 2000, 35);
  std::ostringstream text;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    if (i == 5) text << "nan nan nan\n";
    text << s.points[i].x() << " " << s.points[i].y() << " " << s.points[i].z() << "\n";
  }
  text << s.points[0].x() << " " << s.points[0].y() << " " << s.points[0].z() << "\n";
  write("sphere.xyz", text.str());
  const Result r = run("skeletonize " + path("sphere.xyz") + " -n 2 -q -o " + path("out.ply") +
                       " --labels " + path("labels.txt"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(path("labels.txt"));
  std::vector<int> labels;
  for (int label = 0; in >> label;) labels.push_back(label);
  ASSERT_EQ(labels.size(), s.points.size() + 2);
  EXPECT_EQ(labels[5], -1);
  EXPECT_EQ(labels.back(), -1);
  EXPECT_GE(labels[0], 0);
}

// The threads that do the work wait passively at barriers unless the user chose a policy: libgomp
// prints its settings when it loads (OMP_DISPLAY_ENV), the last of them are the working process's.
TEST_F(Cli, ThreadsWaitPassivelyUnlessTheUserChoseAPolicy) {
  const auto last_spin_count = [&](const std::string& policy) {
    const std::string command = "env -u OMP_WAIT_POLICY -u GOMP_SPINCOUNT " + policy +
                                " OMP_DISPLAY_ENV=verbose " + VMAS_CLI + " --version > " +
                                path("stdout") + " 2> " + path("stderr");
    EXPECT_EQ(std::system(command.c_str()), 0);
    std::istringstream lines(test::read_text(path("stderr")));
    std::string line, last;
    while (std::getline(lines, line))
      if (line.find("GOMP_SPINCOUNT") != std::string::npos) last = line;
    return last;
  };
  EXPECT_NE(last_spin_count("").find("'0'"), std::string::npos);
  EXPECT_EQ(last_spin_count("OMP_WAIT_POLICY=active").find("'0'"), std::string::npos);
}

TEST_F(Cli, VersionAndJsonSummaryWithEval) {
  Result r = run("--version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out, "vmas " + std::string(version()) + "\n");
  write_surface(path("capsule.off"), test::capsule(0.2, 1.0, 8, 24));
  r = run("skeletonize " + path("capsule.off") + " -n 4 --json --eval -o " + path("out.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto summary = nlohmann::json::parse(r.out);
  EXPECT_EQ(summary["vmas"], version());
  EXPECT_EQ(summary["spheres"], 4);
  EXPECT_EQ(summary["input"], path("capsule.off"));
  EXPECT_TRUE(summary["warnings"].empty());
  EXPECT_GT(summary["eval"]["hausdorff_percent"].get<double>(), 0.0);
  EXPECT_LT(summary["eval"]["hausdorff_percent"].get<double>(), 10.0);
  // The figures of --eval are vmas eval's (of the skeleton before it was written in float).
  r = run("eval " + path("capsule.off") + " " + path("out.ply") + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto measured = nlohmann::json::parse(r.out);
  EXPECT_EQ(summary["eval"].size(), 8u);
  for (const auto& [key, value] : summary["eval"].items()) {
    ASSERT_TRUE(measured.contains(key)) << key;
    EXPECT_NEAR(value.get<double>(), measured[key].get<double>(),
                1e-4 * std::abs(measured[key].get<double>())) << key;
  }
  // Timings are reported, not judged here (scripts/bench measures them): every stage is listed.
  for (const char* stage :
       {"read", "clean", "prepare", "shape", "partition", "update", "projection", "split",
        "connectivity", "smoothing_check", "write", "total"})
    EXPECT_TRUE(summary["seconds"].contains(stage)) << stage;
  // A clean mesh is not smoothed, so its smoothing is not checked.
  EXPECT_FALSE(summary["noise"]["smoothing_check"]["made"].get<bool>());
}

TEST_F(Cli, WarningsAreInTheJsonToo) {
  write_plane("plane.xyz");
  const Result r = run("skeletonize " + path("plane.xyz") + " -n 3 --json -o " + path("out.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto warnings = nlohmann::json::parse(r.out)["warnings"];
  // A flat square: open, and three spheres cannot come near it (the measured error says so).
  ASSERT_EQ(warnings.size(), 2u) << warnings.dump();
  EXPECT_EQ(warnings[0]["code"], "open-surface");
  EXPECT_EQ(warnings[1]["code"], "large-error");
  const double measured = nlohmann::json::parse(r.out)["measured_error_percent"];
  EXPECT_GT(measured, 5.0);
  const std::string message = warnings[1]["message"];
  EXPECT_NEAR(std::stod(message.substr(message.find_first_of("0123456789"))), measured, 0.01)
      << message;
  EXPECT_NE(r.err.find("warning"), std::string::npos) << r.err;
}

TEST_F(Cli, AScanWithAHoleIsReportedOpen) {
  // A sphere sampled without normals, whole and with the cap above z = 0.7 cut off.
  const test::Sample sphere = test::sample_sphere(Vec3::Zero(), 1.0, 8000, 21);
  std::ostringstream whole, cut;
  for (const Vec3& p : sphere.points) {
    whole << p.x() << " " << p.y() << " " << p.z() << "\n";
    if (p.z() < 0.7) cut << p.x() << " " << p.y() << " " << p.z() << "\n";
  }
  write("whole.xyz", whole.str());
  write("cut.xyz", cut.str());
  Result r = run("skeletonize " + path("whole.xyz") + " -n 10 --json -o " + path("whole.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto summary = nlohmann::json::parse(r.out);
  EXPECT_EQ(summary["holes"]["count"], 0);
  EXPECT_TRUE(summary["warnings"].empty()) << summary["warnings"].dump() << summary.dump();
  r = run("skeletonize " + path("cut.xyz") + " -n 10 --json -o " + path("cut.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  summary = nlohmann::json::parse(r.out);
  EXPECT_EQ(summary["holes"]["count"], 1);
  // The rim: a circle of radius sqrt(1 - 0.7²) = 0.71, its box's diagonal 2.02, in a sphere's
  // bounding box of diagonal 3.3 (the cut one's is a little smaller).
  EXPECT_NEAR(summary["holes"]["widest_percent"].get<double>(), 100.0 * 2.02 / 3.3, 8.0);
  ASSERT_FALSE(summary["warnings"].empty());
  EXPECT_EQ(summary["warnings"][0]["code"], "open-surface");
  EXPECT_NE(summary["warnings"][0]["message"].get<std::string>().find("1 hole"), std::string::npos);
}

TEST_F(Cli, BatchKeepsGoingAfterABrokenFile) {
  write_surface(path("a.off"), test::capsule(0.2, 1.0, 8, 24));
  write("b.pcd", "##");
  write_surface(path("c.off"), test::icosphere(Vec3::Zero(), 1.0, 3));
  fs::create_directories(path("out"));
  const std::string inputs = path("a.off") + " " + path("b.pcd") + " " + path("c.off");
  Result r = run("skeletonize " + inputs + " -n 2 --output-dir " + path("out"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(fs::exists(path("out/a.ply")));
  EXPECT_FALSE(fs::exists(path("out/b.ply")));
  EXPECT_TRUE(fs::exists(path("out/c.ply")));
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 3) << r.out;
  EXPECT_NE(r.out.find(path("b.pcd") + ": failed: " + path("b.pcd")), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("1 of 3 inputs failed"), std::string::npos) << r.err;

  write("list.txt", path("a.off") + "\n# a comment\n" + path("b.pcd") + "\n");
  r = run("skeletonize --inputs " + path("list.txt") + " -n 2 --json --format ma --output-dir " +
          path("out"));
  EXPECT_EQ(r.exit_code, 1);
  std::istringstream lines(r.out);
  std::string first, second;
  ASSERT_TRUE(std::getline(lines, first) && std::getline(lines, second)) << r.out;
  EXPECT_EQ(nlohmann::json::parse(first)["spheres"], 2);
  EXPECT_TRUE(nlohmann::json::parse(second).contains("error"));
  EXPECT_TRUE(fs::exists(path("out/a.ma")));
}

// --summary keeps one line per input across runs; --resume skips an input whose line has no error,
// the same options and an output newer than it, and runs the others again.
TEST_F(Cli, BatchSummaryKeepsALinePerInputAndResumeSkipsWhatIsDone) {
  write_surface(path("a.off"), test::capsule(0.2, 1.0, 8, 24));
  write("b.xyz", "1 2\n");
  write_surface(path("c.off"), test::icosphere(Vec3::Zero(), 1.0, 3));
  const std::string batch = "skeletonize " + path("a.off") + " " + path("b.xyz") + " " +
                            path("c.off") + " --output-dir " + path("out") + " --summary " +
                            path("out/summary.jsonl") + " --json";
  const auto summary_lines = [&] {
    std::map<std::string, nlohmann::json> lines;
    std::istringstream in(read_text(path("out/summary.jsonl")));
    for (std::string line; std::getline(in, line);) {
      const nlohmann::json parsed = nlohmann::json::parse(line);
      lines[parsed["input"].get<std::string>()] = parsed;
    }
    return lines;
  };
  const auto skipped = [](const Result& r) {
    std::set<std::string> inputs;
    std::istringstream in(r.out);
    for (std::string line; std::getline(in, line);) {
      const nlohmann::json parsed = nlohmann::json::parse(line);
      if (parsed.contains("skipped")) inputs.insert(parsed["input"].get<std::string>());
    }
    return inputs;
  };
  EXPECT_EQ(run(batch + " -n 2").exit_code, 1);
  auto lines = summary_lines();
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[path("a.off")]["spheres"], 2);
  EXPECT_EQ(lines[path("a.off")]["batch_options"], nlohmann::json::array({"--spheres=2"}));
  EXPECT_TRUE(lines[path("b.xyz")].contains("error"));

  // Done, with the same options (--threads does not count): skipped; the broken file again.
  Result r = run(batch + " --spheres 2 --threads 1 --resume");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(skipped(r), (std::set<std::string>{path("a.off"), path("c.off")}));
  // An input newer than its output runs again.
  fs::last_write_time(path("c.off"), fs::last_write_time(path("out/c.ply")) + std::chrono::seconds(5));
  r = run(batch + " -n 2 --resume");
  EXPECT_EQ(skipped(r), std::set<std::string>{path("a.off")});
  // Other options: everything runs, and every line is replaced in place.
  write_surface(path("b.xyz"), test::icosphere(Vec3::Zero(), 1.0, 2));
  r = run(batch + " -n 3 --resume");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(skipped(r).empty());
  lines = summary_lines();
  ASSERT_EQ(lines.size(), 3u);
  for (const auto& [input, line] : lines) {
    EXPECT_EQ(line["spheres"], 3) << input;
    EXPECT_EQ(line["batch_options"], nlohmann::json::array({"--spheres=3"})) << input;
  }
}

// Several vmas merging into one summary at once (GNU parallel, a Slurm array) lose no line.
TEST_F(Cli, BatchSummaryTakesTheLinesOfRunsAtOnce) {
  constexpr int kRuns = 4, kInputsPerRun = 8;
  std::string launches;
  for (int run = 0; run < kRuns; ++run) {
    std::string inputs;
    for (int i = 0; i < kInputsPerRun; ++i) {
      inputs += " " + path("in" + std::to_string(run) + "_" + std::to_string(i) + ".off");
      write_surface(inputs.substr(1 + inputs.rfind(' ')), test::icosphere(Vec3::Zero(), 1.0, 1));
    }
    launches += std::string(VMAS_CLI) + " skeletonize" + inputs + " -n 2 --threads 1 --output-dir " +
                path("out") + " --summary " + path("summary.jsonl") + " -q & ";
  }
  ASSERT_EQ(std::system(("sh -c '" + launches + "wait'").c_str()), 0);
  std::istringstream in(read_text(path("summary.jsonl")));
  std::set<std::string> inputs;
  for (std::string line; std::getline(in, line);)
    inputs.insert(nlohmann::json::parse(line)["input"].get<std::string>());
  EXPECT_EQ(inputs.size(), static_cast<std::size_t>(kRuns * kInputsPerRun));
}

// What the launchers (scripts/skeletonize-parallel, -slurm) ask vmas instead of deciding it
// themselves: --pending FILE lists the inputs a run would run, by --resume's rule, and says why;
// --record keeps a line made elsewhere under this batch's names, or a failure for a run that
// left none.
TEST_F(Cli, BatchSummaryPendingAndRecordForLaunchers) {
  write_surface(path("a.off"), test::capsule(0.2, 1.0, 8, 24));
  write("b.xyz", "1 2\n");
  write_surface(path("c.off"), test::icosphere(Vec3::Zero(), 1.0, 2));
  const std::string batch =
      " --output-dir " + path("out") + " --summary " + path("out/summary.jsonl");
  const std::string all =
      "skeletonize " + path("a.off") + " " + path("b.xyz") + " " + path("c.off") + batch;
  const auto has = [](const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
  };
  // Nothing has run: every input is pending, and nothing but the list is written.
  Result r = run(all + " -n 2 --resume --pending " + path("todo"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_text(path("todo")),
            path("a.off") + "\n" + path("b.xyz") + "\n" + path("c.off") + "\n");
  EXPECT_TRUE(has(r.out, path("a.off") + ": not run yet")) << r.out;
  EXPECT_FALSE(fs::exists(path("out/a.ply")));
  EXPECT_FALSE(fs::exists(path("out/summary.jsonl")));
  // a done, b failed, c not run: b and c pending, and why.
  EXPECT_EQ(run("skeletonize " + path("a.off") + " " + path("b.xyz") + batch + " -n 2").exit_code,
            1);
  r = run(all + " -n 2 --resume --pending " + path("todo") + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_text(path("todo")), path("b.xyz") + "\n" + path("c.off") + "\n");
  std::istringstream lines(r.out);
  std::string first, second;
  ASSERT_TRUE(std::getline(lines, first) && std::getline(lines, second)) << r.out;
  EXPECT_EQ(nlohmann::json::parse(first)["input"], path("b.xyz"));
  EXPECT_TRUE(has(nlohmann::json::parse(first)["pending"].get<std::string>(), "failed: ")) << first;
  EXPECT_EQ(nlohmann::json::parse(second)["pending"], "not run yet");
  // Other options: a too; without --resume (a launcher's --force): every input.
  r = run(all + " -n 3 --resume --pending " + path("todo"));
  EXPECT_TRUE(has(r.out, path("a.off") + ": last run with other options")) << r.out;
  EXPECT_EQ(run(all + " -n 2 --pending " + path("todo")).exit_code, 0);
  EXPECT_EQ(read_text(path("todo")),
            path("a.off") + "\n" + path("b.xyz") + "\n" + path("c.off") + "\n");

  // c ran elsewhere (another machine, where it was ./c.off): its --json output, messages and all,
  // is kept as c's line here, with this batch's input and output.
  fs::create_directories(path("there"));
  fs::copy_file(path("c.off"), path("there/c.off"));
  r = run("skeletonize " + path("there/c.off") + " --output-dir " + path("there/out") +
          " -n 2 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  write("c.log", "a message\n" + r.out + "another\n");
  r = run("skeletonize " + path("c.off") + batch + " -n 2 --record unused < " + path("c.log"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has(r.out, path("c.off") + " -> " + path("out/c.ply") + ": 2 spheres")) << r.out;
  std::map<std::string, nlohmann::json> kept;
  std::istringstream summary(read_text(path("out/summary.jsonl")));
  for (std::string line; std::getline(summary, line);) {
    const nlohmann::json parsed = nlohmann::json::parse(line);
    kept[parsed["input"].get<std::string>()] = parsed;
  }
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_EQ(kept[path("c.off")]["output"], path("out/c.ply"));
  EXPECT_EQ(kept[path("c.off")]["spheres"], 2);
  EXPECT_EQ(kept[path("c.off")]["batch_options"], nlohmann::json::array({"--spheres=2"}));
  // Done once its output is here too (as GNU parallel's --return copies it).
  r = run(all + " -n 2 --resume --pending " + path("todo"));
  EXPECT_TRUE(has(r.out, path("c.off") + ": " + path("out/c.ply") + " is missing")) << r.out;
  fs::copy_file(path("there/out/c.ply"), path("out/c.ply"));
  r = run(all + " -n 2 --resume --pending " + path("todo"));
  EXPECT_EQ(read_text(path("todo")), path("b.xyz") + "\n");
  // A run that left no line (killed, vmas missing there): a failure with the launcher's words,
  // in place of a's good line; then a is pending again.
  write("empty.log", "Killed\n");
  r = run("skeletonize " + path("a.off") + batch + " -n 2 --record 'no summary (exit 137)' < " +
          path("empty.log"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.out, path("a.off") + ": failed: no summary (exit 137)")) << r.out;
  EXPECT_TRUE(r.err.empty()) << r.err;  // the line says it all
  EXPECT_TRUE(
      has(read_text(path("out/summary.jsonl")),
          "{\"vmas\":\"" + std::string(version()) + "\",\"input\":\"" + path("a.off") +
              "\",\"error\":\"no summary (exit 137)\",\"batch_options\":[\"--spheres=2\"]}"));
  r = run(all + " -n 2 --resume --pending " + path("todo"));
  EXPECT_EQ(read_text(path("todo")), path("a.off") + "\n" + path("b.xyz") + "\n");

  // Usage: both need a summary; --record takes one INPUT, and neither --resume nor --pending.
  for (const std::string& wrong :
       {all + " --resume --pending " + path("todo") + " --record x",
        "skeletonize " + path("a.off") + " --output-dir " + path("out") + " --pending " +
            path("todo"),
        "skeletonize " + path("a.off") + " --output-dir " + path("out") + " --record x",
        all + " --record x", "skeletonize " + path("a.off") + batch + " --resume --record x"}) {
    r = run(wrong + " -n 2 < /dev/null");
    EXPECT_EQ(r.exit_code, 2) << wrong << "\n" << r.err;
  }
}

TEST_F(Cli, BatchUsageErrors) {
  write_surface(path("a.off"), test::capsule(0.2, 1.0, 8, 24));
  fs::create_directories(path("sub"));
  write_surface(path("sub/a.off"), test::capsule(0.2, 1.0, 8, 24));
  // Several inputs need a folder; two inputs named alike would overwrite each other.
  EXPECT_EQ(run("skeletonize " + path("a.off") + " " + path("a.off") + " -o x.ply").exit_code, 2);
  Result r = run("skeletonize " + path("a.off") + " " + path("sub/a.off") + " -n 2");
  EXPECT_EQ(r.exit_code, 2);
  expect_one_line_error(r, "several INPUTs need --output-dir");
  // A summary is a batch's; --resume needs one.
  r = run("skeletonize " + path("a.off") + " -n 2 -o x.ply --summary s.jsonl");
  EXPECT_EQ(r.exit_code, 2);
  expect_one_line_error(r, "--summary goes with several INPUTs or --output-dir");
  r = run("skeletonize " + path("a.off") + " -n 2 --output-dir " + path("o") + " --resume");
  EXPECT_EQ(r.exit_code, 2);
  expect_one_line_error(r, "--resume needs --summary");
  r = run("skeletonize " + path("a.off") + " " + path("sub/a.off") + " --output-dir " +
          dir_.string());
  EXPECT_EQ(r.exit_code, 2);
  expect_one_line_error(r, "would both be written");
  // A missing output folder is created, as the batch scripts do.
  EXPECT_EQ(run("skeletonize " + path("a.off") + " -n 2 --output-dir " + path("new/sub")).exit_code,
            0);
  EXPECT_TRUE(fs::exists(path("new/sub/a.ply")));
}

// Every command refuses, before any work, an output that is one of its inputs (however
// spelled) or another of its outputs; the inputs stay as they were.
TEST_F(Cli, NoCommandWritesOverItsInput) {
  write_surface(path("a.ply"), test::capsule(0.2, 1.0, 8, 24));
  write_surface(path("b.ply"), test::icosphere(Vec3::Zero(), 1.0, 2));
  write_medial_mesh(path("m.ply"), MedialMesh{{{Vec3::Zero(), 0.5}}, {}, {}});
  const std::string a = read_text(path("a.ply")), b = read_text(path("b.ply"));
  fs::create_hard_link(path("a.ply"), path("hard.ply"));
  const std::string a_again = dir_.string() + "/./a.ply";
  for (const std::string arguments :
       {"skeletonize " + path("a.ply") + " " + path("b.ply") + " -n 2 --output-dir " + dir_.string(),
        "skeletonize " + path("a.ply") + " -n 2 -o " + a_again,
        "skeletonize " + path("a.ply") + " -n 2 -o " + path("hard.ply"),
        "skeletonize " + path("a.ply") + " -n 2 -o " + path("s.ply") + " --labels " + path("a.ply"),
        "skeletonize " + path("a.ply") + " -n 2 -o " + path("y.ply") + " --labels " + path("y.ply"),
        "eval " + path("a.ply") + " " + path("m.ply") + " --errors " + path("m.ply"),
        "eval " + path("a.ply") + " " + path("m.ply") + " --errors " + path("e.txt") +
            " --medial-errors " + path("e.txt"),
        "convert " + path("a.ply") + " " + a_again, "edit " + path("a.ply") + " -o " + a_again}) {
    const Result r = run(arguments);
    EXPECT_EQ(r.exit_code, 2) << arguments << "\n" << r.err;
    expect_one_line_error(r, "of this run");
    EXPECT_TRUE(r.out.empty()) << arguments;
  }
  EXPECT_EQ(read_text(path("a.ply")), a);
  EXPECT_EQ(read_text(path("b.ply")), b);
  EXPECT_FALSE(fs::exists(path("s.ply")) || fs::exists(path("y.ply")) || fs::exists(path("e.txt")));
}

// --json promises one JSON object on stdout, also when the single input fails.
TEST_F(Cli, JsonFailureIsJsonToo) {
  const Result r = run("skeletonize " + path("missing.off") + " --json -n 2 -o " + path("o.ply"));
  EXPECT_EQ(r.exit_code, 1);
  const auto summary = nlohmann::json::parse(r.out);
  EXPECT_EQ(summary["input"], path("missing.off"));
  EXPECT_NE(summary["error"].get<std::string>().find("no such file"), std::string::npos);
  expect_one_line_error(r, "missing.off");
}

// ... and when the command line is wrong, in every command that has --json.
TEST_F(Cli, JsonUsageErrorIsJsonToo) {
  write_surface(path("capsule.off"), test::capsule(0.2, 1.0, 8, 24));
  for (const std::string& arguments :
       {"skeletonize " + path("capsule.off") + " --json --spheres 0 -o " + path("o.ply"),
        "skeletonize " + path("capsule.off") + " --json --lambada 2 -o " + path("o.ply"),
        "eval " + path("capsule.off") + " --json"}) {
    const Result r = run(arguments);
    EXPECT_EQ(r.exit_code, 2) << arguments;
    const auto failure = nlohmann::json::parse(r.out);  // one object, nothing else
    EXPECT_EQ(failure["vmas"], version()) << arguments;
    EXPECT_FALSE(failure["error"].get<std::string>().empty()) << arguments;
    EXPECT_FALSE(fs::exists(path("o.ply")));
  }
  const Result r = run("eval " + path("missing.off") + " " + path("capsule.off") + " --json");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(nlohmann::json::parse(r.out)["error"].get<std::string>().find("missing.off"),
            std::string::npos);
}

// `-` reads standard input (in --input-format) and writes the skeleton to standard output, the
// same bytes as through files; the summary then goes to standard error.
TEST_F(Cli, StandardInputAndOutput) {
  write_surface(path("capsule.off"), test::capsule(0.2, 1.0, 8, 24));
  ASSERT_EQ(run("skeletonize " + path("capsule.off") + " -n 4 -q -o " + path("file.ply")).exit_code,
            0);
  const Result piped =
      run("skeletonize - --input-format off -n 4 --json -o - < " + path("capsule.off"));
  ASSERT_EQ(piped.exit_code, 0) << piped.err;
  EXPECT_EQ(piped.out, read_text(path("file.ply")));
  EXPECT_NE(piped.err.find("\"output\":\"-\""), std::string::npos) << piped.err;
  const Result ma =
      run("skeletonize - --input-format off -n 4 -q -o - --format ma < " + path("capsule.off"));
  EXPECT_EQ(ma.out.rfind("4 ", 0), 0u) << ma.out;  // "nv ne nf"
  // Errors name standard input; without --input-format it is a usage error.
  write("bad.ply", "not a ply\n");
  const Result bad =
      run("skeletonize - --input-format ply -n 4 -o " + path("o.ply") + " < " + path("bad.ply"));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("standard input"), std::string::npos) << bad.err;
  EXPECT_EQ(run("skeletonize - -n 4 -o " + path("o.ply") + " < " + path("bad.ply")).exit_code, 2);
  EXPECT_FALSE(fs::exists(path("o.ply")));
}

// convert and eval take `-` as skeletonize does: the same bytes, the same figures as files.
TEST_F(Cli, ConvertAndEvalTakeStandardStreams) {
  write_surface(path("capsule.off"), test::capsule(0.2, 1.0, 8, 24));
  ASSERT_EQ(run("convert " + path("capsule.off") + " " + path("file.xyz") + " -q").exit_code, 0);
  const Result piped = run("convert - - --input-format off --format xyz < " + path("capsule.off"));
  ASSERT_EQ(piped.exit_code, 0) << piped.err;
  EXPECT_EQ(piped.out, read_text(path("file.xyz")));
  EXPECT_NE(piped.err.find("- -> -"), std::string::npos) << piped.err;  // summary on stderr

  ASSERT_EQ(run("skeletonize " + path("capsule.off") + " -n 4 -q -o " + path("s.ply")).exit_code,
            0);
  const Result ma = run("convert --medial - - --input-format ply --format ma < " + path("s.ply"));
  EXPECT_EQ(ma.out.rfind("4 ", 0), 0u) << ma.err;
  const Result from_files = run("eval " + path("capsule.off") + " " + path("s.ply") + " --json");
  const Result from_stdin =
      run("eval " + path("capsule.off") + " - --input-format ply --json < " + path("s.ply"));
  ASSERT_EQ(from_stdin.exit_code, 0) << from_stdin.err;
  const auto epsilon = [](const std::string& out) {
    return out.substr(out.find("hausdorff_percent"), 30);
  };
  EXPECT_EQ(epsilon(from_stdin.out), epsilon(from_files.out));

  // Usage errors: a second -, - without its format, a format without -; errors name the stream.
  for (const std::string args :
       {std::string("eval - - --input-format off"), "eval - " + path("s.ply"),
        "convert " + path("capsule.off") + " -",
        "convert " + path("capsule.off") + " - --format obj",
        "convert " + path("capsule.off") + " " + path("o.off") + " --format off",
        "eval " + path("capsule.off") + " " + path("s.ply") + " --errors -"}) {
    const Result r = run(args + " < " + path("capsule.off"));
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
  }
  write("bad.off", "not an off\n");
  const Result bad = run("convert - " + path("o.ply") + " --input-format off < " + path("bad.off"));
  EXPECT_EQ(bad.exit_code, 1);
  expect_one_line_error(bad, "standard input");
  EXPECT_FALSE(fs::exists(path("o.ply")));
}

// --labels on a device or FIFO is refused before the run; neither is replaced.
TEST_F(Cli, SpecialFilesAreNeverReplaced) {
  write_surface(path("a.ply"), test::capsule(0.2, 1.0, 8, 24));
  ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0600), 0);
  for (const std::string target : {std::string("/dev/null"), path("fifo")}) {
    const Result r = run("skeletonize " + path("a.ply") + " -n 2 -o " + path("s.ply") +
                         " --labels " + target);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    expect_one_line_error(r, "regular files only");
  }
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  EXPECT_TRUE(fs::is_fifo(path("fifo")));
  const Result r = run("skeletonize " + path("fifo") + " -n 2 -o " + path("s.ply"));
  EXPECT_EQ(r.exit_code, 1);  // at once, not a hang
  expect_one_line_error(r, "not a regular file");
  EXPECT_FALSE(fs::exists(path("s.ply")));
}

TEST_F(Cli, OptionErrorsNameTheFlagAsTyped) {
  write_surface(path("a.off"), test::capsule(0.2, 1.0, 8, 24));
  for (const std::string option :
       {"--lambda -1", "--normal-k 1", "--ball-tolerance 2", "--k 500", "--final-lambda -2",
        "--max-points 5", "--splits-per-round 0", "--denoise-angle 400", "--refine-moves -1"}) {
    const Result r = run("skeletonize " + path("a.off") + " -o " + path("o.ply") + " " + option);
    EXPECT_EQ(r.exit_code, 2) << option;
    expect_one_line_error(r, option.substr(0, option.find(' ')) + " must");
  }
}

TEST_F(Cli, FarFromTheOriginOrOutsizedGivesTheSameSkeleton) {
  // Georeferenced data: a capsule 1e8 away from the origin, and the same capsule in other units.
  const SurfaceInput capsule = test::capsule(0.2, 1.0, 8, 24);
  for (const auto& [offset, scale] :
       {std::pair{Vec3(1e8, -1e8, 5e7), 1.0}, std::pair{Vec3(0.0, 0.0, 0.0), 1e-6},
        std::pair{Vec3(3e3, 0.0, 0.0), 1e5}}) {
    SurfaceInput moved = capsule;
    for (Vec3& p : moved.points) p = offset + scale * p;
    write_surface(path("moved.off"), moved);
    const Result r = run("skeletonize " + path("moved.off") + " --spheres 6 -o " + path("out.ply"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const MedialMesh mesh = read_medial_mesh(path("out.ply"));
    ASSERT_EQ(mesh.spheres.size(), 6u);
    for (const Sphere& s : mesh.spheres) {
      const Vec3 c = (s.center - offset) / scale;  // back in the capsule's own units
      EXPECT_LT(std::hypot(c.x(), c.y()), 0.02) << "offset " << offset.x() << ", scale " << scale;
      EXPECT_GT(s.radius / scale, 0.1) << "offset " << offset.x() << ", scale " << scale;
      EXPECT_LT(s.radius / scale, 0.21) << "offset " << offset.x() << ", scale " << scale;
    }
  }
}

TEST_F(Cli, WritesMaByExtension) {
  write_surface(path("sphere.off"), test::icosphere(Vec3::Zero(), 1.0, 3));
  const Result r = run("skeletonize " + path("sphere.off") + " -n 1 -q -o " + path("out.ma"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out.empty());
  const MedialMesh mesh = read_medial_mesh(path("out.ma"));
  ASSERT_EQ(mesh.spheres.size(), 1u);
  EXPECT_NEAR(mesh.spheres[0].radius, 1.0, 0.02);
}

TEST_F(Cli, HelpAndUsageErrors) {
  EXPECT_EQ(run("--help").exit_code, 0);
  EXPECT_EQ(run("skeletonize --help").exit_code, 0);
  EXPECT_EQ(run("").exit_code, 2);
  EXPECT_EQ(run("frobnicate").exit_code, 2);
  write_surface(path("sphere.off"), test::icosphere(Vec3::Zero(), 1.0, 2));
  const std::string input = path("sphere.off");
  const std::size_t files = file_count();
  Result r = run("skeletonize " + input + " --spheres 0 -o " + path("out.ply"));
  EXPECT_EQ(r.exit_code, 2);
  expect_one_line_error(r, "spheres");
  r = run("skeletonize " + input + " --lambda -1 -o " + path("out.ply"));
  EXPECT_EQ(r.exit_code, 2);
  expect_one_line_error(r, "lambda");
  r = run("skeletonize " + input + " --spheres 3 -o " + dir_.string());
  EXPECT_EQ(r.exit_code, 2);
  expect_one_line_error(r, "directory");
  r = run("skeletonize " + input + " --spheres 3 -o " + path("out.obj"));
  EXPECT_EQ(r.exit_code, 2);
  expect_one_line_error(r, ".ply or .ma");
  r = run("skeletonize " + input + " --spheres 3");
  EXPECT_EQ(r.exit_code, 2);
  expect_one_line_error(r, "--output");
  r = run("skeletonize " + input + " --spheres 3 --error 0.01 -o " + path("out.ply"));
  EXPECT_EQ(r.exit_code, 2);
  r = run("skeletonize " + input + " --bogus -o " + path("out.ply"));
  EXPECT_EQ(r.exit_code, 2);
  r = run("skeletonize " + input + " --spheres many -o " + path("out.ply"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(file_count(), files);  // no output written by any of these
}

TEST_F(Cli, BadInputFilesGiveOneLineErrorsAndNoOutput) {
  write("empty.off", "");
  write("unknown.stl", "solid x\n");
  write("nan.xyz", "nan 0 0\n0 nan 0\n");
  write("text.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n");
  write("five.xyz", "0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n");  // too few to estimate normals
  const std::size_t files = file_count();
  for (const std::string name :
       {"missing.off", "empty.off", "unknown.stl", "nan.xyz", "text.ply", "five.xyz"}) {
    const Result r = run("skeletonize " + path(name) + " --spheres 3 -o " + path("out.ply"));
    EXPECT_EQ(r.exit_code, 1) << name;
    expect_one_line_error(r, name);
  }
  EXPECT_EQ(file_count(), files);
}

// PCL's reader crashed on these (exit 139) or allocated gigabytes (tests/corpus).
TEST_F(Cli, MalformedPcdAndSizeBombsAreRunErrors) {
  write("x.pcd", "x");
  const std::string corpus = std::string(VMAS_SOURCE_DIR) + "/tests/corpus/";
  for (const std::string input : {path("x.pcd"), corpus + "pcd_points_bomb_binary.pcd",
                                  corpus + "pcd_points_bomb_compressed.pcd"}) {
    const Result r = run("skeletonize " + input + " --spheres 10 -o " + path("out.ply"));
    EXPECT_EQ(r.exit_code, 1) << input;
    expect_one_line_error(r, input);
  }
  EXPECT_FALSE(fs::exists(path("out.ply")));
}

TEST_F(Cli, UnwritableOutputFolderFailsBeforeReading) {
  write_surface(path("sphere.off"), test::icosphere(Vec3::Zero(), 1.0, 2));
  const Result r = run("skeletonize " + path("sphere.off") + " -n 3 -o /proc/vmas_out.ply");
  EXPECT_EQ(r.exit_code, 2);
  expect_one_line_error(r, "/proc/vmas_out.ply");
  EXPECT_TRUE(r.out.empty()) << r.out;  // nothing read or computed
}

TEST_F(Cli, TooFewPointsForTheSphereCountIsAnError) {
  write("tiny.xyz",
        "0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n1 1 0 0 0 1\n0 0 1 0 0 1\n"
        "1 0 1 0 0 1\n0 1 1 0 0 1\n1 1 1 0 0 1\n");
  const Result r = run("skeletonize " + path("tiny.xyz") + " --spheres 50 -o " + path("out.ply"));
  EXPECT_EQ(r.exit_code, 2);
  expect_one_line_error(r, "spheres");
  EXPECT_FALSE(fs::exists(path("out.ply")));
}

TEST_F(Cli, ReorientsInwardNormalsOnRequest) {
  SurfaceInput cloud = test::icosphere(Vec3::Zero(), 1.0, 4);
  cloud.faces.clear();
  for (const Vec3& p : cloud.points) cloud.normals.push_back(-p);  // all pointing inward
  write_surface(path("inward.xyz"), cloud);
  const Result r =
      run("skeletonize " + path("inward.xyz") + " --orient-normals -n 1 -o " + path("out.ma"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("re-oriented"), std::string::npos) << r.out;
  const MedialMesh mesh = read_medial_mesh(path("out.ma"));
  ASSERT_EQ(mesh.spheres.size(), 1u);
  EXPECT_LT(mesh.spheres[0].center.norm(), 0.05);
  EXPECT_NEAR(mesh.spheres[0].radius, 1.0, 0.05);
}

TEST_F(Cli, OpenSurfaceGetsAWarning) {
  write_plane("plane.xyz");
  const Result r = run("skeletonize " + path("plane.xyz") + " --spheres 3 -o " + path("out.ply"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("open"), std::string::npos) << r.err;
}

TEST_F(Cli, ClosedSampledSurfaceGetsNoWarning) {
  const test::Sample s = test::sample_sphere(Vec3::Zero(), 1.0, 3000, 31);
  SurfaceInput cloud;
  cloud.points = s.points;
  write_surface(path("sphere.xyz"), cloud);
  const Result r = run("skeletonize " + path("sphere.xyz") + " --spheres 3 -o " + path("out.ply"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("not smoothed"), std::string::npos) << r.out;
}

TEST_F(Cli, HalfSphereScanIsNotClosed) {
  // A single view of a ball: its near half only.
  SurfaceInput cloud;
  for (const Vec3& p : test::sample_sphere(Vec3::Zero(), 1.0, 4000, 32).points)
    if (p.z() > 0.0) cloud.points.push_back(p);
  write_surface(path("half.xyz"), cloud);
  const Result r = run("skeletonize " + path("half.xyz") + " --spheres 3 -o " + path("out.ply"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("does not enclose a volume"), std::string::npos) << r.err;
}

TEST_F(Cli, NoisyCloudIsMeasuredAndSmoothed) {
  const test::Sample s = test::sample_sphere(Vec3::Zero(), 1.0, 5000, 33);
  SurfaceInput cloud;
  cloud.points = test::with_noise(s.points, 0.02, 34);
  write_surface(path("noisy.xyz"), cloud);
  Result r = run("skeletonize " + path("noisy.xyz") + " --spheres 2 -o " + path("out.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("noise: ~"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("smoothed (MLS radius"), std::string::npos) << r.out;
  r = run("skeletonize " + path("noisy.xyz") + " --spheres 2 -o " + path("out.ply") +
          " --denoise off");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("noise: ~"), std::string::npos) << r.out;
  r = run("skeletonize " + path("noisy.xyz") + " --spheres 2 -o " + path("out.ply") +
          " --denoise 0.5%");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("smoothed (MLS radius"), std::string::npos) << r.out;
}

TEST_F(Cli, BadDenoiseValueIsAUsageError) {
  write_surface(path("capsule.off"), test::capsule(0.2, 1.0, 8, 24));
  for (const char* value : {"sometimes", "0.5%%", "-1", "0.7"}) {
    const Result r = run("skeletonize " + path("capsule.off") + " --spheres 2 -o " +
                         path("out.ply") + " --denoise " + value);
    EXPECT_EQ(r.exit_code, 2) << value;
    expect_one_line_error(r, "denoise");
    EXPECT_EQ(file_count(), 1u) << value;  // the input only
  }
}

// docs/cli.md's table of `vmas skeletonize` lists every option of its --help, with the same
// default, and no other: the help is the option table, the docs follow it.
TEST_F(Cli, TheDocumentedOptionsAreTheHelpsWithTheirDefaults) {
  const Result r = run("skeletonize --help");
  ASSERT_EQ(r.exit_code, 0);
  std::map<std::string, std::string> help;  // flag -> default ("" when none)
  const std::regex help_line(R"(^  (?:-\w \[ )?--([\w-]+)(?: \])?(?: arg)?(?: \(=([^)]*)\))?)");
  // Without a default value, the text may say it: "default 100 when --error is absent".
  const std::regex said_default(R"(default (\d[\d.e-]*))");
  std::istringstream help_text(r.out);
  std::string flag, text;
  const auto take_said_default = [&] {
    std::smatch m;
    if (!flag.empty() && help[flag].empty() && std::regex_search(text, m, said_default))
      help[flag] = m[1];
  };
  for (std::string line; std::getline(help_text, line);) {
    std::smatch m;
    if (std::regex_search(line, m, help_line)) {
      take_said_default();
      flag = m[1];
      help[flag] = m[2];
      text = line;
    } else {
      text += " " + line;
    }
  }
  take_said_default();
  std::ifstream docs_file(std::string(VMAS_SOURCE_DIR) + "/docs/cli.md");
  ASSERT_TRUE(docs_file) << "docs/cli.md";
  std::map<std::string, std::string> docs;
  const std::regex row(R"(^\| `(?:-\w, )?--([\w-]+)[^`]*` \| ([^|]*) \|)");
  bool in_skeletonize = false;
  for (std::string line; std::getline(docs_file, line);) {
    if (line.rfind("## ", 0) == 0) in_skeletonize = line.find("vmas skeletonize") != std::string::npos;
    std::smatch m;
    if (in_skeletonize && std::regex_search(line, m, row)) docs[m[1]] = m[2];
  }
  ASSERT_GT(help.size(), 30u);
  // The same number however it is written ("1e-05", "1e-5"); "off" and "—" are no default.
  const auto same_default = [](const std::string& in_help, std::string in_docs) {
    if (in_docs == "—" || in_docs == "off") return in_help.empty() || in_help == "0";
    try {
      return std::stod(in_help) == std::stod(in_docs);
    } catch (const std::exception&) {
      return in_help == in_docs;
    }
  };
  for (const auto& [flag, value] : help) {
    if (flag == "help") continue;
    if (!docs.count(flag)) {
      ADD_FAILURE() << "--" << flag << " is not in docs/cli.md";
      continue;
    }
    EXPECT_TRUE(same_default(value, docs[flag]))
        << "--" << flag << ": help says " << value << ", docs/cli.md " << docs[flag];
  }
  for (const auto& [flag, value] : docs)
    EXPECT_TRUE(help.count(flag)) << "docs/cli.md lists --" << flag << ", which is no option";
}

}  // namespace
}  // namespace vmas
