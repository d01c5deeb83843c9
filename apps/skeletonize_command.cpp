// `vmas skeletonize`: input shapes → medial meshes (PLY or .ma), optionally per-point labels.
// One input gives a full summary; several (or --output-dir) a line per file.
#include <unistd.h>

#include <algorithm>
#include <boost/program_options.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "batch_summary.hpp"
#include "commands.hpp"
#include "run_summary.hpp"
#include "standard_streams.hpp"
#include "vmas/error.hpp"
#include "vmas/eval.hpp"
#include "vmas/io.hpp"
#include "vmas/vmas.hpp"

namespace po = boost::program_options;
namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace vmas::cli {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

const char* kDescription =
    "usage: vmas skeletonize INPUT -o OUTPUT [--spheres N | --error E] [options]\n"
    "       vmas skeletonize INPUT... --output-dir DIR [--format ply|ma] [options]\n"
    "       vmas skeletonize --inputs LIST --output-dir DIR [options]\n"
    "       vmas skeletonize - --input-format xyz -o - [--format ply|ma] [options]\n"
    "\n"
    "Computes a medial mesh (spheres, edges, triangles) of INPUT, a triangle mesh or point\n"
    "cloud (.off .ply .obj .xyz .txt .pcd), by variational medial axis sampling. OUTPUT is a\n"
    "PLY (vertex x y z radius, edge, face) or a .ma file (Q-MAT format). With several inputs\n"
    "(or --output-dir) each INPUT gives DIR/NAME.ply; a file that fails does not stop the\n"
    "others, one line (or JSON line) per file is printed, and the exit code is 1 if any failed.\n"
    "Exit codes: 0 success, 1 a run failed (unreadable file, unusable data), 2 usage error.\n"
    "\n"
    "options";

std::string text_of(double value, const char* format = "%.3g") {
  char text[32];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

struct Job {
  std::string input, output, labels;
};

// Where progress goes: nowhere (--quiet, batches), a terminal line, or log lines.
enum class ProgressStyle { None, Terminal, Log };

struct Settings {
  Options options;
  DensitySource density;
  bool json = false, eval = false, quiet = false;
  std::string input_format;           // of INPUT `-`
  std::string output_format = "ply";  // of `-o -` and --output-dir: ply or ma
};

// The summary's lines about the input and its preparation.
void print_preparation(const json& s, const Settings& settings, std::ostream& out) {
  const json& noise = s["noise"];
  const json& cleaned = s["cleaned"];
  out << "input " << s["input"].get<std::string>() << ": " << s["points"] << " points, "
      << (s["faces"].get<int>() > 0 ? s["faces"].dump() + " faces" : std::string("point cloud"))
      << "\n";
  const int removed =
      cleaned["non_finite_points"].get<int>() + cleaned["duplicate_points"].get<int>() +
      cleaned["degenerate_faces"].get<int>() + cleaned["unused_vertices"].get<int>();
  if (removed > 0)
    out << "cleaned: removed " << cleaned["non_finite_points"] << " non-finite points, "
        << cleaned["duplicate_points"] << " duplicates, " << cleaned["degenerate_faces"]
        << " degenerate faces, " << cleaned["unused_vertices"] << " unused vertices\n";
  if (cleaned["missing_normals"].get<int>() > 0)
    out << "normals: " << cleaned["missing_normals"]
        << " points without a valid normal in the file got an estimated one\n";
  const json& thinning = s["thinning"];
  if (thinning["applied"].get<bool>())
    out << "thinned: " << thinning["points"] << " points take part (one per voxel of "
        << thinning["voxel_percent"] << " % of the diagonal; --max-points "
        << settings.options.prepare.max_points << ")\n";
  const json& density = s["density"];
  if (density["given"].get<bool>())
    out << "density: from " << density["min"] << " to " << density["max"]
        << " (spheres gather where it is high; docs/design.md, Density)\n";
  const json& strays = s["stray_clusters"];
  if (strays["count"].get<int>() > 0)
    out << "stray clusters: removed " << strays["count"] << " group"
        << (strays["count"].get<int>() > 1 ? "s" : "") << " of " << strays["points"]
        << " points apart from the object (--keep-strays keeps them)\n";
  const json& sampling = s["mesh_sampling"];
  if (sampling["applied"].get<bool>())
    out << "mesh: too coarse for the method (" << sampling["vertices_before"]
        << " vertices); its faces were sampled to " << sampling["vertices"]
        << " vertices (edges longer than " << sampling["edge_limit_percent"]
        << " % of the diagonal split; --no-mesh-sampling keeps the mesh as it is)\n";
  if (s["outliers"].get<int>() > 0) out << "outliers: removed " << s["outliers"] << " points\n";
  if (noise["from_facets"].get<bool>())
    out << "noise: not read (point spacing " << noise["spacing_percent"]
        << " % of the diagonal: too far apart to tell noise from facets); not smoothed\n";
  else if (noise["measured"].get<bool>())
    out << "noise: ~" << noise["deviation_percent"] << " % of the diagonal (point spacing "
        << noise["spacing_percent"] << " %)"
        << (!noise["smoothed"].get<bool>() ? std::string("; not smoothed")
            : noise["mesh_smoothing_steps"].get<int>() > 0
                ? "; smoothed along the faces (" + noise["mesh_smoothing_steps"].dump() +
                      " Taubin steps, left ~" + noise["residual_percent"].dump() + " %)"
                : "; smoothed (MLS radius " + noise["mls_radius_percent"].dump() + " %, left ~" +
                      noise["residual_percent"].dump() + " %)" +
                      (noise["thinned_points"].get<int>() > 0
                           ? ", " + noise["thinned_points"].dump() +
                                 " of its points take part (one per voxel of " +
                                 noise["thinned_voxel_percent"].dump() + " %)"
                           : std::string()));
  const json& check = noise["smoothing_check"];
  if (check["made"].get<bool>()) {
    const bool kept = check["smoothing_kept"].get<bool>();
    out << (kept ? "; the skeleton reaches " : ": smoothed, the skeleton reached ")
        << check["smoothed_reach_percent"] << " % past the points as they are and "
        << (kept ? "lies " : "lay ") << check["smoothed_cover_percent"]
        << " % from the farthest, without " << (kept ? "smoothing " : "")
        << check["unsmoothed_reach_percent"] << " % and " << check["unsmoothed_cover_percent"]
        << " %";
  }
  out << "\n";
  const std::string normals = s["normals"];
  if (normals == "estimated" || normals == "re-oriented")
    out << "normals: "
        << (normals == "estimated" ? "estimated and oriented" : "given ones re-oriented")
        << " (k=" << settings.options.prepare.normals.k << ")\n";
}

// The summary of a single run, for people.
void print_summary(const json& s, const Settings& settings, std::ostream& out) {
  print_preparation(s, settings, out);
  const Options& o = settings.options;
  out << "parameters: "
      << (o.run.target.error > 0.0 ? "error=" + text_of(o.run.target.error)
                                   : "spheres=" + std::to_string(o.run.target.count()))
      << " lambda=" << o.run.lambda << " k=" << o.shape.k
      << " projection=" << (o.run.project ? "on" : "off") << "\n";
  out << "enclosure: winding number " << s["enclosure"] << " inside (1: closed surface)";
  if (s["holes"]["count"].get<int>() > 0)
    out << "; " << s["holes"]["count"] << " hole(s), the widest " << s["holes"]["widest_percent"]
        << " % of the diagonal across";
  out << "\n";
  out << "result: " << s["spheres"] << " spheres, " << s["edges"] << " edges, " << s["medial_faces"]
      << " faces; " << s["iterations"] << " iterations"
      << (s["stopped_by_max_iterations"].get<bool>() ? " (stopped by --max-iterations)"
          : s["converged"].get<bool>()               ? ""
                                       : " (error still changing: stopped after settling)")
      << ", total error " << text_of(s["total_error"].get<double>()) << "\n";
  out << topology_line(s["topology"]) << "\n";
  const json& refine = s["refine"];
  if (refine["moves_tried"].get<int>() > 0)
    out << "refine: " << refine["moves_kept"] << " of " << refine["moves_tried"]
        << " moves kept, measured epsilon " << refine["error_before_percent"] << " % -> "
        << refine["error_after_percent"] << " %\n";
  const json& starts = s["starts"]["measured_error_percent"];
  if (starts.size() > 1) {
    // With a density, they are ranked by the error it weighs (docs/design.md, "Density").
    out << "starts: measured epsilon"
        << (s["starts"]["density_weighted"].get<bool>() ? " (density-weighted)" : "");
    for (const json& error : starts) out << (&error == &starts[0] ? " " : " / ") << error << " %";
    out << "; start " << s["starts"]["kept"] << " kept\n";
  }
  if (s.contains("eval"))
    out << "error: epsilon " << s["eval"]["hausdorff_percent"]
        << " % of the diagonal (surface -> medial " << s["eval"]["surface_to_medial_max_percent"]
        << " %, medial -> surface " << s["eval"]["medial_to_surface_max_percent"] << " %)\n";
  const json& t = s["seconds"];
  out << "time (s): total " << text_of(t["total"], "%.2f");
  const char* parts[] = {"read",         "clean",           "prepare", "shape",  "partition",
                         "update",       "projection",      "split",   "refine", "connectivity",
                         "other_starts", "smoothing_check", "write"};
  for (const char* part : parts)
    if ((part != std::string("smoothing_check") && part != std::string("other_starts")) ||
        t[part].get<double>() > 0.0)
      out << (part == parts[0] ? " = " : ", ") << part << " " << text_of(t[part], "%.2f");
  out << "\nwrote " << s["output"].get<std::string>() << "\n";
}

// What a progress report says, for one line.
std::string describe(const Progress& p) {
  char line[160];
  switch (p.phase) {
    case Progress::Phase::Preparing:
      std::snprintf(line, sizeof line, "preparing, %.0f %%", 100.0 * p.fraction);
      break;
    case Progress::Phase::Optimising:
      if (p.target_spheres > 0)
        std::snprintf(line, sizeof line, "spheres %d/%d, iteration %d, error %.3e", p.spheres,
                      p.target_spheres, p.iteration, p.error);
      else
        std::snprintf(line, sizeof line, "spheres %d, iteration %d, error %.3e", p.spheres,
                      p.iteration, p.error);
      break;
    case Progress::Phase::Settling:
      std::snprintf(line, sizeof line, "spheres %d, settling, step %d of at most %d, error %.3e",
                    p.spheres, p.round, p.rounds, p.error);
      break;
    case Progress::Phase::FinalRefit:
      std::snprintf(line, sizeof line, "final refit %d/%d", p.round, p.rounds);
      break;
    case Progress::Phase::Refining:
      std::snprintf(line, sizeof line, "refining, move %d/%d, epsilon %.3f %%", p.round, p.rounds,
                    100.0 * p.error);
      break;
    case Progress::Phase::OtherStarts:
      std::snprintf(line, sizeof line, "start %d of %d, %.0f %%", p.round, p.rounds,
                    100.0 * p.fraction);
      break;
    case Progress::Phase::SmoothingCheck:
      std::snprintf(line, sizeof line, "checking the smoothing: the points as they are, %.0f %%",
                    100.0 * p.fraction);
      break;
  }
  return line;
}

// Seconds between progress lines when stderr is not a terminal (a log file, a cluster job).
constexpr double kLogInterval = 5.0;

// Progress on stderr: on a terminal one line rewritten in place; elsewhere a line every
// kLogInterval seconds, so that logs show a long run moving.
ProgressCallback stderr_progress(const std::string& input, ProgressStyle style) {
  if (style == ProgressStyle::None) return {};
  if (style == ProgressStyle::Terminal)
    return [input](const Progress& p) {
      std::fprintf(stderr, "\r%s: %-70s", input.c_str(), describe(p).c_str());
      return true;
    };
  auto last = std::make_shared<Clock::time_point>(Clock::now());
  return [input, last](const Progress& p) {
    if (seconds_since(*last) >= kLogInterval) {
      *last = Clock::now();
      std::fprintf(stderr, "%s: %s\n", input.c_str(), describe(p).c_str());
    }
    return true;
  };
}

// Reads `job.input` (standard input for `-`, in `input_format`); errors name it as given.
SurfaceInput read_input(const Job& job, const Settings& settings) {
  SurfaceInput surface;
  with_input_file(job.input, settings.input_format, [&](const std::string& path) {
    surface = read_with_density(path, settings.density);
  });
  return surface;
}

// Reads, skeletonizes and writes one input; returns its summary. Errors about the data name
// the file. An output `-` is standard output, in `settings.output_format`.
json run_one(const Job& job, const Settings& settings, ProgressStyle progress) {
  const bool show_progress = progress == ProgressStyle::Terminal;
  const auto start = Clock::now();
  SurfaceInput surface = read_input(job, settings);
  const double read_seconds = seconds_since(start);
  const InputSize size{surface.points.size(), surface.faces.size()};
  // The metric compares with the cleaned input; without it the run may consume the surface.
  SurfaceInput cleaned;
  if (settings.eval) {
    cleaned = surface;
    clean_surface(cleaned);
  }
  Result result;
  try {
    result =
        skeletonize(std::move(surface), settings.options, stderr_progress(job.input, progress));
  } catch (const InvalidInput& e) {
    if (show_progress) std::fprintf(stderr, "\n");
    throw InvalidInput(job.input + ": " + e.what());
  }
  if (show_progress) std::fprintf(stderr, "\n");
  const auto write_start = Clock::now();
  // What went to standard output cannot be taken back: the files land only after it did.
  std::vector<OutputFile> files;
  if (is_standard_stream(job.output)) {
    write_standard_output(
        medial_mesh_file("standard output." + settings.output_format, result.medial_mesh));
  } else {
    files.push_back({job.output, medial_mesh_file(job.output, result.medial_mesh)});
  }
  if (!job.labels.empty()) files.push_back({job.labels, labels_file(result.labels)});
  write_files_atomically(files);
  const double write_seconds = seconds_since(write_start);
  for (const Warning& w : result.warnings)
    std::cerr << "vmas skeletonize: warning: " << job.input << ": " << w.message << "\n";
  RunContext run{size, job.input, job.output, read_seconds, write_seconds};
  if (!settings.eval) return run_summary(result, run);
  const EvalResult eval = evaluate(cleaned, result.medial_mesh);
  run.eval = &eval;
  return run_summary(result, run);
}

std::vector<std::string> read_input_list(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InvalidOption("inputs", path + ": cannot read it");
  std::vector<std::string> inputs;
  for (std::string line; std::getline(in, line);) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (!line.empty() && line[0] != '#') inputs.push_back(line);
  }
  return inputs;
}

// One output per input in `directory`, named after the input; two inputs of the same name
// would overwrite each other. `format`: ply or ma (checked by the caller).
std::vector<Job> batch_jobs(const std::vector<std::string>& inputs, const std::string& directory,
                            const std::string& format) {
  // Created when missing (another vmas of the same batch may be creating it too).
  std::error_code error;
  fs::create_directories(directory, error);
  if (!fs::is_directory(directory))
    throw InvalidOption("output-dir",
                        directory + ": cannot create the folder (" + error.message() + ")");
  std::vector<Job> jobs;
  std::map<std::string, std::string> taken;
  for (const std::string& input : inputs) {
    const std::string output =
        (fs::path(directory) / fs::path(input).stem()).string() + "." + format;
    const auto [previous, fresh] = taken.emplace(output, input);
    if (!fresh)
      throw UsageError(input + " and " + previous->second + " would both be written to " + output);
    check_output_option(output, check_medial_mesh_output);
    jobs.push_back({input, output, ""});
  }
  return jobs;
}

// What the command line asks for, checked.
struct Request {
  Settings settings;
  std::vector<std::string> inputs;
  std::string output, output_dir, inputs_list, labels_path, summary_path;
  std::string pending_path;  // --pending: the list of the inputs to run, written instead of running
  std::string record_why;    // --record: the error of an input whose run left no line
  bool batch = false;        // several inputs, or --output-dir
  bool resume = false;       // skip the inputs that --summary's file shows done
  bool record = false;       // take the input's line from standard input instead of running it
  // The options that shape the outputs, as --summary's file records them for --resume.
  std::vector<std::string> batch_options;
};

// The options that shape a batch's outputs, one "--name=value" each in the order given: neither
// where the results go nor how they are reported, nor --threads (results do not depend on it).
std::vector<std::string> options_shaping_outputs(const std::vector<po::option>& given) {
  static const std::vector<std::string> kNotShaping = {"output-dir", "inputs", "summary", "resume",
                                                       "pending",    "record", "json",    "quiet",
                                                       "threads",    "help"};
  std::vector<std::string> shaping;
  for (const po::option& o : given) {
    if (o.position_key >= 0 ||
        std::find(kNotShaping.begin(), kNotShaping.end(), o.string_key) != kNotShaping.end())
      continue;
    std::string text = "--" + o.string_key;
    for (std::size_t i = 0; i < o.value.size(); ++i) text += (i == 0 ? "=" : " ") + o.value[i];
    shaping.push_back(text);
  }
  return shaping;
}

// Usage errors in what the inputs are and where their outputs go.
void check_destinations(const Request& r) {
  if (r.inputs.empty()) throw po::error("missing INPUT");
  if (r.batch && !r.output.empty())
    throw po::error("give --output-dir for several inputs (--output names one file)");
  if (r.batch && r.output_dir.empty()) throw po::error("several INPUTs need --output-dir");
  if (!r.batch && r.output.empty()) throw po::error("missing --output");
  if (!r.batch && !r.summary_path.empty())
    throw po::error("--summary goes with several INPUTs or --output-dir");
  if (r.resume && r.summary_path.empty()) throw po::error("--resume needs --summary FILE");
  if (!r.pending_path.empty() && r.summary_path.empty())
    throw po::error("--pending needs --summary FILE");
  if (r.record && r.summary_path.empty()) throw po::error("--record needs --summary FILE");
  if (r.record && (r.resume || !r.pending_path.empty()))
    throw po::error("--record goes without --resume and --pending");
  if (r.record && r.inputs.size() != 1) throw po::error("--record takes one INPUT");
  if (r.batch && !r.labels_path.empty()) throw po::error("--labels takes one INPUT");
  const bool from_stdin = std::any_of(r.inputs.begin(), r.inputs.end(), is_standard_stream);
  if (from_stdin && r.batch) throw po::error("INPUT - (standard input) takes one INPUT");
  if (is_standard_stream(r.labels_path))
    throw po::error("--labels needs a file (- is not supported)");
}

// The command line read and checked; nothing when it asked for --help (printed).
std::optional<Request> read_request(int argc, const char* const* argv) {
  Request r;
  Settings& settings = r.settings;
  RunOptionValues run_values;
  po::options_description visible(kDescription);
  // clang-format off
  visible.add_options()
      ("help,h", "print this help")
      ("output,o", po::value(&r.output),
       "medial mesh to write (.ply or .ma), for one INPUT; - for standard output (the summary "
       "then goes to standard error)")
      ("output-dir", po::value(&r.output_dir), "folder of the outputs, one per INPUT (created if missing)")
      ("format", po::value(&settings.output_format)->default_value("ply"),
       "with --output-dir or -o -: ply or ma")
      ("input-format", po::value(&settings.input_format),
       "with INPUT - (standard input): its format, as a file extension (xyz, ply, off, obj, pcd)")
      ("inputs", po::value(&r.inputs_list), "read the INPUTs from this file, one path per line")
      ("labels", po::value(&r.labels_path),
       "also write the sphere of every point of the file, one per line (-1: point dropped as "
       "NaN, duplicate or outlier); one INPUT only")
      ("json", "print the summary as one JSON object (one line per INPUT with several)")
      ("summary", po::value(&r.summary_path),
       "with several INPUTs or --output-dir: also keep each INPUT's JSON line in this file, "
       "in place of its line of an earlier run (one line per INPUT; several vmas may write it "
       "at once)")
      ("resume", "with --summary: skip each INPUT whose line there has no error and the same "
       "options, and whose output is newer than it")
      ("pending", po::value(&r.pending_path),
       "with --summary: run nothing; write the INPUTs a run would run (with --resume: those not "
       "done) to this file, one per line, and print why each is to run (for launchers)")
      ("record", po::value(&r.record_why),
       "with --summary and one INPUT: run nothing; keep as INPUT's line the last JSON line on "
       "standard input (of a run of it made elsewhere), under this batch's names, or else a "
       "line saying INPUT failed with this error (for launchers)")
      ("eval", "also measure the result's reconstruction error against INPUT (as vmas eval)")
      ("quiet,q", "print nothing but errors and warnings");
  // clang-format on
  add_run_options(visible, run_values);
  po::options_description hidden;
  hidden.add_options()("input", po::value(&r.inputs));
  po::positional_options_description positional;
  positional.add("input", -1);
  std::vector<po::option> given;
  po::variables_map vm = parse_arguments(argc, argv, visible, hidden, positional, &given);
  if (vm.count("help")) {
    std::cout << visible
              << "\nexamples:\n"
                 "  vmas skeletonize clouds/bunny_merged_45k.xyz --spheres 60 -o bunny.ply\n"
                 "  vmas skeletonize scans/*.pcd --spheres 60 --output-dir skeletons --json\n"
                 "  vmas skeletonize scans/*.pcd --spheres 60 --output-dir skeletons \\\n"
                 "      --summary skeletons/summary.jsonl --resume\n";
    return std::nullopt;
  }
  po::notify(vm);
  if (!r.inputs_list.empty()) {
    const std::vector<std::string> listed = read_input_list(r.inputs_list);
    r.inputs.insert(r.inputs.end(), listed.begin(), listed.end());
  }
  r.batch = r.inputs.size() > 1 || !r.output_dir.empty();
  r.resume = vm.count("resume") > 0;
  r.record = vm.count("record") > 0;
  r.batch_options = options_shaping_outputs(given);
  check_destinations(r);
  finish_run_options(vm, run_values);
  settings.options = run_values.options;
  settings.density = run_values.density;
  if (r.batch && settings.density.is_file())
    throw po::error("--density FILE takes one INPUT (a rule or --density-field suits several)");
  settings.json = vm.count("json") > 0;
  settings.eval = vm.count("eval") > 0;
  settings.quiet = vm.count("quiet") > 0;

  const std::string& format = settings.output_format;
  if (format != "ply" && format != "ma")
    throw InvalidOption("format", "must be ply or ma (got '" + format + "')");
  check_standard_input(r.inputs, settings.input_format);
  return r;
}

// One input: its progress on standard error, its summary on standard output (standard error
// when the skeleton goes to standard output).
int run_single(const Request& r) {
  const Settings& settings = r.settings;
  const bool to_stdout = is_standard_stream(r.output);
  if (!to_stdout) check_output_option(r.output, check_medial_mesh_output);
  if (!r.labels_path.empty()) check_output_option(r.labels_path, check_output);
  check_distinct_files_option({r.inputs[0], r.inputs_list,
                               r.settings.density.is_file() ? r.settings.density.file_or_rule : ""},
                              {r.output, r.labels_path});
  const Job job{r.inputs[0], r.output, r.labels_path};
  const ProgressStyle progress = settings.quiet           ? ProgressStyle::None
                                 : isatty(fileno(stderr)) ? ProgressStyle::Terminal
                                                          : ProgressStyle::Log;
  std::ostream& report = to_stdout ? std::cerr : std::cout;
  json summary;
  try {
    summary = run_one(job, settings, progress);
  } catch (const std::exception& e) {
    // --json promises one JSON object, also on failure; the message goes to stderr as well.
    if (!settings.json) throw;
    report << json_line({{"vmas", version()}, {"input", job.input}, {"error", e.what()}}) << "\n";
    throw JsonPrinted{std::current_exception()};
  }
  if (settings.json)
    report << json_line(summary) << "\n";
  else if (!settings.quiet)
    print_summary(summary, settings, report);
  return 0;
}

// A batch's line for one input on standard output: its JSON line with --json, else a line of
// text (a failure's also with --quiet).
void print_batch_line(const Job& job, const json& line, const Settings& settings) {
  if (settings.json) {
    std::cout << json_line(line) << std::endl;
  } else if (line.contains("error")) {
    std::cout << job.input << ": failed: " << line["error"].get<std::string>() << std::endl;
  } else if (settings.quiet) {
    return;
  } else if (line.contains("skipped")) {
    std::cout << job.input << " -> " << job.output << ": up to date, skipped" << std::endl;
  } else if (line.contains("pending")) {
    std::cout << job.input << ": " << line["pending"].get<std::string>() << std::endl;
  } else {
    // By value: a line of --record is another vmas's, which may lack a field.
    const auto field = [&](const std::string& pointer) {
      return line.value(json::json_pointer(pointer), json());
    };
    const json warnings = field("/warnings");
    std::cout << job.input << " -> " << job.output << ": " << field("/spheres") << " spheres, "
              << field("/edges") << " edges, " << field("/medial_faces") << " faces, "
              << text_of(line.value(json::json_pointer("/seconds/total"), 0.0), "%.2f") << " s"
              << (line.contains("eval")
                      ? ", epsilon " + field("/eval/hausdorff_percent").dump() + " %"
                      : std::string())
              << (warnings.empty() ? "" : ", " + std::to_string(warnings.size()) + " warning(s)")
              << std::endl;
  }
}

// --record: INPUT's line as a run made elsewhere left it on standard input (the last JSON object
// with an "input" there: a run's --json output, or its summary file), with the input and output
// named as this batch names them; without one, a line saying INPUT failed with the error `why`.
json recorded_line(const Job& job, const std::string& why) {
  json line;
  for (std::string text; std::getline(std::cin, text);) {
    json parsed = json::parse(text, nullptr, false);
    if (parsed.is_object() && parsed.contains("input") && parsed["input"].is_string())
      line = std::move(parsed);
  }
  if (line.is_null()) return {{"vmas", version()}, {"input", job.input}, {"error", why}};
  line["input"] = job.input;
  if (line.contains("output")) line["output"] = job.output;
  return line;
}

// --pending FILE: the inputs a run would run (with --resume, those not done) into FILE, one per
// line, for a launcher to hand out; a line for each saying why.
void write_pending(const Request& r, const std::vector<Job>& jobs,
                   const std::map<std::string, json>& earlier) {
  std::string list;
  for (const Job& job : jobs) {
    const auto done = earlier.find(job.input);
    const std::string why = !r.resume
                                ? "no --resume"
                                : reason_to_run(done == earlier.end() ? nullptr : &done->second,
                                                r.batch_options, job.input, job.output);
    if (why.empty()) continue;
    list += job.input + '\n';
    print_batch_line(
        job, {{"vmas", version()}, {"input", job.input}, {"output", job.output}, {"pending", why}},
        r.settings);
  }
  write_file_atomically(r.pending_path, list);
}

// Several inputs: keep going after a failure, one line per file (and in --summary's file).
int run_batch(const Request& r) {
  const Settings& settings = r.settings;
  const std::vector<Job> jobs = batch_jobs(r.inputs, r.output_dir, settings.output_format);
  std::vector<std::string> outputs, read = r.inputs;
  for (const Job& job : jobs) outputs.push_back(job.output);
  read.push_back(r.inputs_list);
  for (const std::string* written : {&r.summary_path, &r.pending_path})
    if (!written->empty()) {
      check_output_option(*written, check_output);
      outputs.push_back(*written);
    }
  check_distinct_files_option(read, outputs);
  const BatchSummary summary(r.summary_path);
  const std::map<std::string, json> earlier = r.resume ? summary.read() : std::map<std::string, json>{};
  if (!r.pending_path.empty()) {
    write_pending(r, jobs, earlier);
    return 0;
  }
  const auto keep = [&](json line) {
    if (r.summary_path.empty()) return;
    line["batch_options"] = r.batch_options;
    summary.merge(line);
  };
  int failed = 0;
  for (const Job& job : jobs) {
    const auto done = earlier.find(job.input);
    if (done != earlier.end() &&
        reason_to_run(&done->second, r.batch_options, job.input, job.output).empty()) {
      print_batch_line(job, {{"vmas", version()}, {"input", job.input}, {"output", job.output},
                             {"skipped", "up to date"}}, settings);
      continue;
    }
    json line;
    if (r.record) {
      line = recorded_line(job, r.record_why);
    } else {
      try {
        line = run_one(job, settings, ProgressStyle::None);
      } catch (const std::exception& e) {
        line = {{"vmas", version()}, {"input", job.input}, {"error", e.what()}};
      }
    }
    failed += line.contains("error");
    print_batch_line(job, line, settings);
    keep(line);
  }
  // A record is one line, which says it all.
  if (failed > 0 && !r.record)
    std::cerr << "vmas skeletonize: " << failed << " of " << jobs.size() << " inputs failed\n";
  return failed > 0 ? 1 : 0;
}

}  // namespace

int skeletonize_command(int argc, const char* const* argv) {
  const std::optional<Request> request = read_request(argc, argv);
  if (!request) return 0;
  return request->batch ? run_batch(*request) : run_single(*request);
}

}  // namespace vmas::cli
