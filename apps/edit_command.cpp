// `vmas edit`: the live skeleton editor. One EditSession optimises in a worker thread; a local
// HTTP server (apps/http_server: Boost.Beast) serves the page (three.js from Debian's libjs-three),
// the shape once, the state as server-sent events, and takes edits as POSTed JSON. The protocol is
// documented in docs/editor.md.
#include <signal.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <unordered_map>

#include "commands.hpp"
#include "http_server.hpp"
#include "run_summary.hpp"
#include "vmas/edit_session.hpp"
#include "vmas/error.hpp"
#include "vmas/eval.hpp"
#include "vmas/io.hpp"
#include "vmas/vmas.hpp"

namespace po = boost::program_options;

namespace vmas::cli {

extern const char* const kEditPage;  // apps/edit_page.html, embedded by CMake

namespace {

const char* kDescription =
    "usage: vmas edit INPUT [-o OUTPUT] [--spheres N] [--port P] [--host H] [options]\n"
    "\n"
    "Skeletonizes INPUT live and serves an editor page: the optimisation keeps running while\n"
    "you remove, split and freeze spheres in the browser. Prints the page's URL as the first\n"
    "line on stdout (it holds a random token that every request needs). Saving downloads the\n"
    "skeleton and, with -o, writes OUTPUT too (.ply or .ma). Ctrl-C stops. Exit codes:\n"
    "0 stopped, 1 run error, 2 usage error.\n"
    "\n"
    "options";

constexpr const char* kThreeDirectory = "/usr/share/javascript/three";  // Debian's libjs-three
constexpr auto kUpdateInterval = std::chrono::milliseconds(1000 / 30);  // at most 30 updates/s
constexpr auto kKeepAlive = std::chrono::milliseconds(1000);
constexpr int kStreamPollMs = 50;  // longest wait for news in one call of an event stream
// Pages open at once (each event stream holds a thread and a copy of the state it sent).
constexpr int kMaxPages = 4;
// Label changes are sent as a list while it is shorter than this many, or than a quarter of
// the vertices (a listed change costs about four times a label of the full list).
constexpr std::size_t kMinListedLabels = 4096;
// With --exit-on-close: a reload (the page gone for a moment) must not stop the editor.
constexpr auto kCloseGrace = std::chrono::seconds(3);

std::string random_token() {
  std::random_device random;
  std::string token;
  const char* hex = "0123456789abcdef";
  for (int i = 0; i < 32; ++i) token += hex[random() % 16];
  return token;
}

// vmas eval's measure of what "save" would write (the live skeleton in the input's coordinates,
// against the input as vmas eval reads it): the page's ε. Taken on one core, in a thread of its
// own, whenever the skeleton holds still (paused, finished, or settled: the session has measured
// it) and differs from the one measured last. Maxima only (they are a full evaluation's), with
// the input's distance structure built once: a measurement at a million points takes a
// fraction of a second, so that the thread also stops soon.
class SaveMeasure {
 public:
  struct Figure {
    double percent = -1.0;  // < 0: none yet
    int iteration = -1;     // the session's step it measured
    std::uint64_t count = 0;  // measurements so far
    std::vector<double> spheres;  // what it measured, flat: x y z r each (working frame)
  };

  SaveMeasure(SurfaceInput input, const EditSession& session, const Frame& frame)
      : input_(std::move(input)), session_(session), frame_(frame), worker_([this] { work(); }) {}
  ~SaveMeasure() {
    stop_ = true;
    worker_.join();
  }
  Figure latest() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return latest_;
  }

 private:
  void work() {
    const ThreadCount one_core(1);  // the optimisation keeps the others
    std::optional<Evaluator> evaluator;  // built at the first measurement
    std::vector<double> measured;  // the spheres measured last, flat: x y z r each
    int measured_at = -1;
    // A look at the session every kLookMs, a copy of its state only when it changed.
    constexpr int kLookMs = 200;
    for (std::uint64_t version = 0; !stop_;
         std::this_thread::sleep_for(std::chrono::milliseconds(kLookMs))) {
      if (session_.wait_for_version(version, 0) == version) continue;
      const EditSnapshot s = session_.snapshot();
      version = s.version;
      const bool still = s.paused || s.finished || s.measured_at_iteration > measured_at;
      std::vector<double> spheres;
      for (const Sphere& sphere : s.spheres)
        spheres.insert(spheres.end(), {sphere.center.x(), sphere.center.y(), sphere.center.z(),
                                       sphere.radius});
      if (!still || s.finishing || spheres == measured || spheres.empty()) continue;
      if (!evaluator) {
        EvalOptions as_vmas_eval;
        as_vmas_eval.maxima_only = true;
        evaluator.emplace(input_, as_vmas_eval);
      }
      const EvalResult result = (*evaluator)(frame_.to_input(s.mesh));
      measured = std::move(spheres);
      measured_at = s.measured_at_iteration;
      const std::lock_guard<std::mutex> lock(mutex_);
      latest_ = {result.percent(result.hausdorff), s.iteration, latest_.count + 1, measured};
    }
  }

  const SurfaceInput input_;  // cleaned, as vmas eval reads it
  const EditSession& session_;
  const Frame frame_;
  mutable std::mutex mutex_;  // guards latest_
  std::atomic<bool> stop_{false};
  Figure latest_;
  std::thread worker_;  // last: started once the rest is set
};

// What one page has been sent so far: the next update carries only what changed.
struct Sent {
  std::uint64_t version = 0;
  std::uint64_t save_measures = 0;  // SaveMeasure::Figure::count
  std::vector<std::array<int, 2>> edges;
  std::vector<std::array<int, 3>> faces;
  std::vector<std::uint64_t> keys;
  std::vector<int> labels;
};

// Where each sphere the page knows went: its index in the new state, -1 when it is gone. Empty
// when no sphere moved (then the labels need no renumbering).
std::vector<int> renumbering(const std::vector<std::uint64_t>& before,
                             const std::vector<std::uint64_t>& after) {
  if (before == after) return {};
  std::unordered_map<std::uint64_t, int> index_of;
  for (std::size_t i = 0; i < after.size(); ++i) index_of[after[i]] = static_cast<int>(i);
  std::vector<int> moved_to(before.size(), -1);
  bool moved = false;
  for (std::size_t i = 0; i < before.size(); ++i) {
    const auto found = index_of.find(before[i]);
    if (found != index_of.end()) moved_to[i] = found->second;
    moved = moved || moved_to[i] != static_cast<int>(i);
  }
  return moved ? moved_to : std::vector<int>{};
}

// Labels as the page holds them after this message: all of them when many changed, else a
// renumbering of the spheres (a removal shifts the ids above it) and the vertices whose sphere
// changed beyond it.
void add_labels(const EditSnapshot& s, Sent& sent, json& message) {
  if (sent.labels.size() != s.labels.size()) {
    message["labels"] = sent.labels = s.labels;
    return;
  }
  const std::vector<int> moved_to = renumbering(sent.keys, s.keys);
  if (!moved_to.empty()) {
    message["renumber"] = moved_to;
    for (int& label : sent.labels)
      if (label >= 0) label = label < static_cast<int>(moved_to.size()) ? moved_to[label] : -1;
  }
  const std::size_t most_listed = std::max(kMinListedLabels, s.labels.size() / 4);
  json changes = json::array();
  for (std::size_t v = 0; v < s.labels.size() && changes.size() <= most_listed; ++v)
    if (s.labels[v] != sent.labels[v]) changes.push_back({v, s.labels[v]});
  if (changes.size() > most_listed) {
    message.erase("renumber");
    message["labels"] = sent.labels = s.labels;
  } else if (!changes.empty()) {
    message["label_changes"] = changes;
    for (const auto& change : changes) sent.labels[change[0].get<std::size_t>()] = change[1];
  }
}

// What preparation found, for the page's first message: shown once, it does not change.
json preparation_summary(const Result& prepared, int points) {
  const PrepareReport& report = prepared.prepare;
  const double diagonal = report.diagonal > 0.0 ? report.diagonal : 1.0;
  json warnings = json::array();
  for (const Warning& w : prepared.warnings)
    warnings.push_back({{"code", w.code}, {"message", w.message}});
  return {{"points", points},
          {"thinned_from", report.thinned_from},
          {"outliers", report.outliers},
          {"stray_clusters", report.stray_clusters},
          {"noise_percent", std::round(1e4 * report.noise.sigma / diagonal) / 1e2},
          {"smoothed", report.smoothed()},
          {"noise_from_facets", report.noise_from_facets},
          {"warnings", warnings}};
}

// Spheres and points go to the page in the input's coordinates (`frame`: the working frame's).
json state_message(const EditSnapshot& s, Sent& sent, const json& preparation, const Frame& frame,
                   const SaveMeasure::Figure& save_measure) {
  json spheres = json::array();
  std::vector<double> flat;  // as SaveMeasure keeps them: whether ε is of these spheres
  for (const Sphere& sphere : s.spheres) {
    const Vec3 center = frame.to_input(sphere.center);
    spheres.push_back({center.x(), center.y(), center.z(), frame.scale * sphere.radius});
    flat.insert(flat.end(), {sphere.center.x(), sphere.center.y(), sphere.center.z(), sphere.radius});
  }
  json message = {{"version", s.version},
                  {"iteration", s.iteration},
                  {"steps_per_second", std::round(s.steps_per_second * 10.0) / 10.0},
                  {"error", s.error},
                  {"paused", s.paused},
                  {"target_spheres", s.target_spheres},
                  {"lambda", s.lambda},
                  {"dropped_edits", s.dropped_edits},
                  {"undo", s.undo_steps},
                  {"redo", s.redo_steps},
                  {"finished", s.finished},
                  {"error_before_finish_percent", 100.0 * s.error_before_finish},
                  {"error_after_finish_percent", 100.0 * s.error_after_finish},
                  {"finishing", s.finishing},
                  {"finish_phase", s.finish_phase},
                  {"finish_fraction", std::round(s.finish_fraction * 100.0) / 100.0},
                  {"cancelled_finishes", s.cancelled_finishes},
                  {"measured_error_percent", 100.0 * s.measured_error},
                  {"measured_at_iteration", s.measured_at_iteration},
                  {"save_error_percent", save_measure.percent},
                  {"save_error_at_iteration", save_measure.iteration},
                  // An edit while paused leaves the step as it was: the step cannot say this.
                  {"save_error_is_current", save_measure.count > 0 && save_measure.spheres == flat},
                  {"density_changes", s.density_changes},
                  {"keys", s.keys},
                  {"frozen", s.frozen},
                  {"spheres", spheres},
                  {"topology", edit_topology_summary(s)}};
  if (sent.version == 0 || s.mesh.edges != sent.edges) message["edges"] = sent.edges = s.mesh.edges;
  if (sent.version == 0 || s.mesh.faces != sent.faces) message["faces"] = sent.faces = s.mesh.faces;
  // Labels travel in the event itself: fetched apart, they would be of another version than the
  // changes that follow.
  add_labels(s, sent, message);
  sent.keys = s.keys;
  if (sent.version == 0) message["preparation"] = preparation;
  sent.version = s.version;
  sent.save_measures = save_measure.count;
  return message;
}

// The shape, once: little-endian uint32 vertex count, uint32 face count (0: the page draws the
// vertices the optimisation sees), float32 positions, float32 normals.
std::string shape_bytes(const Shape& shape, const std::vector<std::array<int, 3>>& faces,
                        const Frame& frame) {
  std::string bytes;
  const auto put = [&](const void* data, std::size_t size) {
    bytes.append(static_cast<const char*>(data), size);
  };
  const std::uint32_t counts[2] = {static_cast<std::uint32_t>(shape.size()),
                                   static_cast<std::uint32_t>(faces.size())};
  put(counts, sizeof counts);
  const auto put_vector = [&](const Vec3& v) {
    const float xyz[3] = {float(v.x()), float(v.y()), float(v.z())};
    put(xyz, sizeof xyz);
  };
  for (const Vec3& p : shape.points) put_vector(frame.to_input(p));
  for (const Vec3& n : shape.normals) put_vector(frame.direction_to_input(n));
  for (const auto& face : faces) {
    const std::uint32_t corners[3] = {std::uint32_t(face[0]), std::uint32_t(face[1]),
                                      std::uint32_t(face[2])};
    put(corners, sizeof corners);
  }
  return bytes;
}

// A file of Debian's three.js for the page, or "" when `name` is not one (nothing outside the
// folder, no hidden files).
std::string three_file(const std::string& name) {
  if (name.empty() || name.find("..") != std::string::npos || name[0] == '/' ||
      name.find("/.") != std::string::npos || name[0] == '.')
    return "";
  const std::string path = std::string(kThreeDirectory) + "/" + name;
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) return "";
  std::ifstream file(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(file), {});
}

// An integer field of an edit, checked before narrowing (JSON numbers may be anything).
int integer_field(const json& edit, const char* name) {
  const json& value = edit.at(name);
  if (!value.is_number_integer() || value.get<std::int64_t>() < INT32_MIN ||
      value.get<std::int64_t>() > INT32_MAX)
    throw InvalidArgument(std::string("\"") + name + "\" must be an integer of at most 2147483647");
  return static_cast<int>(value.get<std::int64_t>());
}

// The skeleton "save" gave last, for /api/download: its file name and bytes, and the mesh for
// a download in the other format.
struct Saved {
  std::mutex mutex;
  std::string name, bytes;
  MedialMesh mesh;
};

// Runs finish() and waits until the worker has done it; false when it was dropped or cancelled.
bool finish_and_wait(EditSession& session) {
  const EditSnapshot now = session.snapshot();
  session.finish();
  for (std::uint64_t version = now.version;;) {
    version = session.wait_for_version(version, 1000);
    const EditSnapshot s = session.snapshot();
    if (s.finishes > now.finishes) return true;
    if (s.dropped_edits > now.dropped_edits || s.cancelled_finishes > now.cancelled_finishes)
      return false;
  }
}

// A density file (by input row: what `--density FILE` reads) into the session's density (by
// vertex), and back; InvalidArgument naming the problem.
std::vector<double> density_from_file(const InputRows& rows, const std::string& text) {
  std::vector<double> by_row;
  try {
    by_row = parse_density("density file", text, rows.rows());
    check_density(by_row, rows.rows());
  } catch (const IoError& e) {
    throw InvalidArgument(e.what());
  } catch (const InvalidInput& e) {
    throw InvalidArgument(std::string("density file: ") + e.what());
  }
  return rows.by_vertex(by_row);
}

std::string density_file(const InputRows& rows, const EditSnapshot& s) {
  const std::vector<double> by_row =
      s.density ? rows.by_row(*s.density) : std::vector<double>(rows.rows(), 1.0);
  std::string text;
  char value[32];
  for (double d : by_row) {
    std::snprintf(value, sizeof value, "%.9g\n", d);
    text += value;
  }
  return text;
}

// One POSTed edit; returns the reply's JSON. Throws InvalidArgument (or json errors) for a bad one.
// "save" keeps the skeleton for /api/download and, with -o, writes OUTPUT too; with
// `finish_on_save` it finishes the skeleton first (unless it is finished already).
json apply_edit(EditSession& session, const json& edit, const std::string& output,
                const std::string& download_name, const Frame& frame, bool finish_on_save,
                Saved& saved, const InputRows& rows) {
  if (!edit.is_object() || !edit.contains("op") || !edit["op"].is_string())
    throw InvalidArgument("an edit is a JSON object with an \"op\"");
  const std::string op = edit["op"];
  // The page shows the finish's progress and then its result: an edit meanwhile would change
  // what it is about to show.
  if (op != "cancel" && op != "pause" && session.finishing())
    throw InvalidArgument("a finish is under way: wait for it, or cancel it (Esc)");
  // "key": one sphere; "keys": several, one edit (one undo step).
  const auto keys = [&] {
    return edit.contains("keys") ? edit["keys"].get<std::vector<std::uint64_t>>()
                                 : std::vector<std::uint64_t>{edit.at("key").get<std::uint64_t>()};
  };
  if (op == "remove") {
    session.remove(keys());
  } else if (op == "split") {
    session.split_at(integer_field(edit, "vertex"));
  } else if (op == "freeze") {
    session.freeze(keys(), edit.value("frozen", true));
  } else if (op == "pause") {
    session.pause(edit.value("paused", true));
  } else if (op == "undo") {
    session.undo();
  } else if (op == "redo") {
    session.redo();
  } else if (op == "finish") {
    session.finish();
  } else if (op == "cancel") {
    session.cancel_finish();
  } else if (op == "target") {
    if (edit.contains("by"))
      session.change_target_spheres(integer_field(edit, "by"));
    else
      session.set_target_spheres(integer_field(edit, "spheres"));
  } else if (op == "lambda") {
    if (edit.contains("times"))
      session.scale_lambda(edit.at("times").get<double>());
    else
      session.set_lambda(edit.at("value").get<double>());
  } else if (op == "density") {
    session.paint_density(integer_field(edit, "vertex"), edit.at("radius").get<double>(),
                          edit.at("amount").get<double>());
  } else if (op == "density-reset") {
    session.set_density({});
  } else if (op == "density-load") {
    session.set_density(density_from_file(rows, edit.at("text").get<std::string>()));
  } else if (op == "save") {
    if (finish_on_save && !session.snapshot().finished && !finish_and_wait(session))
      throw InvalidArgument("the skeleton could not be finished before saving");
    const EditSnapshot s = session.snapshot();
    const MedialMesh mesh = frame.to_input(s.mesh);
    const std::string name = output.empty() ? download_name : output;
    std::string bytes = medial_mesh_file(name, mesh);
    if (!output.empty()) write_file_atomically(output, bytes);
    {
      const std::lock_guard<std::mutex> lock(saved.mutex);
      saved.name = std::filesystem::path(name).filename().string();
      saved.bytes = std::move(bytes);
      saved.mesh = mesh;
    }
    json reply = {{"ok", true},
                  {"spheres", s.spheres.size()},
                  {"name", saved.name},
                  {"finished", s.finished}};
    if (s.finished) reply["error_percent"] = 100.0 * s.error_after_finish;
    if (!output.empty()) reply["path"] = output;
    return reply;
  } else {
    throw InvalidArgument("unknown op '" + op + "'");
  }
  return {{"ok", true}};
}

// Every request needs the token (query or X-Vmas-Token header); a request from another site's
// page (its Origin) is refused even with it. Either way the connection is then closed.
HttpServer::Guard token_guard(const std::string& token) {
  return [token](const HttpRequest& req, HttpResponse& res) {
    const auto query_token = req.query.find("token");
    const std::string given =
        query_token != req.query.end() ? query_token->second : req.header("x-vmas-token");
    if (given != token) {
      res.json_error(403, "missing or wrong token: open the URL that vmas edit printed");
      return false;
    }
    // The page's own origin is the address it was loaded from (with --host 0.0.0.0, another
    // machine's name for this one): the Host header of the same request.
    const std::string page_origin = req.header("origin");
    if (!page_origin.empty() && page_origin != "http://" + req.header("host")) {
      res.json_error(403, "requests from " + page_origin + " are refused");
      return false;
    }
    return true;
  };
}

}  // namespace

int edit_command(int argc, const char* const* argv) {
  RunOptionValues run_values;
  std::string input, output, host = "127.0.0.1";
  int port = 0;
  bool finish_on_save = true;
  po::options_description visible(kDescription);
  // clang-format off
  visible.add_options()
      ("help,h", "print this help")
      ("output,o", po::value(&output), "medial mesh that saving writes (.ply or .ma)")
      ("host", po::value(&host)->default_value(host),
       "address to listen on (the default, loopback, lets no other machine in)")
      ("port", po::value(&port)->default_value(0), "port to listen on (0: any free one)")
      ("exit-on-close", "stop when the last page has been closed for 3 s")
      ("finish-on-save", po::value(&finish_on_save)->default_value(true),
       "saving finishes the skeleton first (the final refits and the worst-case refinement, as "
       "vmas skeletonize ends; then the editor pauses): true or false");
  // clang-format on
  add_run_options(visible, run_values);
  po::options_description hidden;
  hidden.add_options()("input", po::value(&input));
  po::positional_options_description positional;
  positional.add("input", 1);
  po::variables_map vm = parse_arguments(argc, argv, visible, hidden, positional);
  if (vm.count("help")) {
    std::cout << visible << "\nexample:\n  vmas edit armadillo.off --spheres 40 -o armadillo.ply\n";
    return 0;
  }
  po::notify(vm);
  if (input.empty()) throw po::error("missing INPUT");
  if (port < 0 || port > 65535) throw InvalidOption("port", "must be between 0 and 65535");
  finish_run_options(vm, run_values);
  if (!output.empty()) check_output_option(output, check_medial_mesh_output);
  check_distinct_files_option({input}, {output});
  const bool exit_on_close = vm.count("exit-on-close") > 0;

  // Ctrl-C and TERM are taken by a thread of their own (blocked here, before any thread starts).
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  sigaddset(&stop_signals, SIGUSR1);  // sent by this program to end the watcher
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  if (!std::filesystem::is_regular_file(std::string(kThreeDirectory) + "/three.min.js"))
    throw IoError(std::string(kThreeDirectory) +
                  "/three.min.js: not found (the page needs Debian's libjs-three)");

  SurfaceInput stored = read_with_density(input, run_values.density);
  const std::size_t input_rows = stored.points.size();
  // Listening first: a port in use or a foreign address fails before the input is prepared. A
  // body may hold a density file of the input (density-load): room for 32 bytes a row, JSON's
  // escapes included (numpy's savetxt writes 25).
  HttpLimits limits;
  limits.body_bytes += 32 * input_rows;
  HttpServer server(limits);
  const std::string token = random_token();
  std::atomic<int> pages{0};           // event streams open now
  std::atomic<bool> page_seen{false};  // ... and ever
  int bound = 0;
  try {
    bound = server.bind(host, port);
  } catch (const std::runtime_error& e) {
    throw InvalidInput(e.what());
  }
  const std::string url_host = host.find(':') != std::string::npos ? "[" + host + "]" : host;
  const std::string origin = "http://" + url_host + ":" + std::to_string(bound);
  SurfaceInput as_eval_reads = stored;
  clean_surface(as_eval_reads);
  PreparedShape prepared = prepare_shape(std::move(stored), run_values.options);
  const InputRows density_rows(prepared.result.clean.kept, prepared.result.prepare.stand_in,
                               input_rows, prepared.shape.size());
  const Frame frame = prepared.result.prepare.frame;
  const json preparation = preparation_summary(prepared.result, prepared.shape.size());
  const std::vector<std::array<int, 3>> faces = prepared.surface.faces;  // a mesh's: same vertices
  // Finishing an untouched session also runs vmas skeletonize's starts (and keeps the better).
  const FinishOptions finish = finish_as_skeletonize_does(prepared, run_values.options);
  EditSession session(std::move(prepared.shape), prepared.run, run_values.options.threads, finish,
                      prepared.result.input_genus);
  const SaveMeasure save_measure(std::move(as_eval_reads), session, frame);
  const std::string shape = shape_bytes(session.shape(), faces, frame);

  server.set_guard(token_guard(token));
  std::string page = kEditPage;  // its script tags carry the token too
  for (std::size_t at; (at = page.find("TOKEN_PLACEHOLDER")) != std::string::npos;)
    page.replace(at, std::strlen("TOKEN_PLACEHOLDER"), token);
  server.route("GET", "/", [&](const HttpRequest&, HttpResponse& res) {
    res.content_type = "text/html; charset=utf-8";
    res.body = page;
  });
  server.route("GET", "/three/*", [&](const HttpRequest& req, HttpResponse& res) {
    res.body = three_file(req.path.substr(std::strlen("/three/")));
    if (res.body.empty()) return res.json_error(404, "no such file: " + req.path);
    res.content_type = "text/javascript";
  });
  // With the diagonal that relative lengths (the brush's radius, the error map) are fractions of,
  // in the input's units.
  const std::string diagonal = json(frame.scale * session.shape().diagonal).dump();
  server.route("GET", "/api/shape", [&](const HttpRequest&, HttpResponse& res) {
    res.content_type = "application/octet-stream";
    res.body = shape;
    res.headers.emplace_back("X-Vmas-Diagonal", diagonal);
  });
  server.route("GET", "/api/labels", [&](const HttpRequest&, HttpResponse& res) {
    const EditSnapshot s = session.snapshot();
    res.content_type = "application/octet-stream";
    res.body.assign(reinterpret_cast<const char*>(s.labels.data()), s.labels.size() * sizeof(int));
    res.headers.emplace_back("X-Vmas-Version", std::to_string(s.version));
  });
  // The heat map's distances: computed on request, from the latest state, in this connection's
  // thread (the optimisation goes on meanwhile).
  server.route("GET", "/api/errors", [&](const HttpRequest&, HttpResponse& res) {
    const EditSnapshot s = session.snapshot();
    const std::vector<float> errors = session.vertex_errors(s.mesh);
    res.content_type = "application/octet-stream";
    res.body.assign(reinterpret_cast<const char*>(errors.data()), errors.size() * sizeof(float));
    res.headers.emplace_back("X-Vmas-Version", std::to_string(s.version));
  });
  server.route("GET", "/api/events", [&](const HttpRequest&, HttpResponse& res) {
    // A page that has just closed keeps its place until its stream notices (within a poll): a
    // new one (a reload) waits that long rather than being refused.
    for (int poll = 0; pages >= kMaxPages && poll < 4 && !server.stopping(); ++poll)
      std::this_thread::sleep_for(std::chrono::milliseconds(kStreamPollMs));
    if (pages >= kMaxPages)
      return res.json_error(503, "too many pages open (" + std::to_string(kMaxPages) + ")");
    ++pages;
    page_seen = true;
    auto sent = std::make_shared<Sent>();
    auto last = std::make_shared<std::chrono::steady_clock::time_point>();
    res.content_type = "text/event-stream";
    res.headers.emplace_back("Cache-Control", "no-store");
    // At most 30 updates a second, a comment after a second without one keeps the stream open.
    // Each call waits briefly and may return nothing: between calls the server looks for a
    // closed page or a stop.
    res.next = [&, sent, last](std::string& event) {
      using Clock = std::chrono::steady_clock;
      if (Clock::now() < *last + kUpdateInterval) {
        std::this_thread::sleep_until(*last + kUpdateInterval);
        return true;
      }
      const std::uint64_t version = session.wait_for_version(sent->version, kStreamPollMs);
      const SaveMeasure::Figure measured = save_measure.latest();
      if (version > sent->version || measured.count != sent->save_measures)
        event = "data: " +
                state_message(session.snapshot(), *sent, preparation, frame, measured).dump() +
                "\n\n";
      else if (Clock::now() - *last >= kKeepAlive)
        event = ": keep-alive\n\n";
      else
        return true;
      *last = Clock::now();
      return true;
    };
    res.done = [&] { --pages; };
  });
  // The painted density: per vertex for the page (float32, 1 where uniform), per input row as a
  // file `--density FILE` reads again.
  server.route("GET", "/api/density", [&](const HttpRequest&, HttpResponse& res) {
    const EditSnapshot s = session.snapshot();
    std::vector<float> values(session.shape().points.size(), 1.0f);
    if (s.density) std::copy(s.density->begin(), s.density->end(), values.begin());
    res.content_type = "application/octet-stream";
    res.body.assign(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
    res.headers.emplace_back("X-Vmas-Density-Changes", std::to_string(s.density_changes));
  });
  server.route("GET", "/api/density-file", [&](const HttpRequest&, HttpResponse& res) {
    const EditSnapshot s = session.snapshot();
    res.content_type = "text/plain";
    res.headers.emplace_back("Content-Disposition",
                             "attachment; filename=\"" + std::filesystem::path(input).stem().string() +
                                 "_density.txt\"");
    res.body = density_file(density_rows, s);
  });
  Saved saved;
  const std::string download_name = std::filesystem::path(input).stem().string() + "_skeleton.ply";
  server.route("POST", "/api/edit", [&](const HttpRequest& req, HttpResponse& res) {
    try {
      res.content_type = "application/json";
      res.body = apply_edit(session, json::parse(req.body), output, download_name, frame,
                            finish_on_save, saved, density_rows)
                     .dump();
    } catch (const json::exception& e) {
      res.json_error(400, std::string("bad edit: ") + e.what());
    } catch (const Error& e) {
      res.json_error(400, e.what());
    }
  });
  // ?format=ply or ?format=ma: the saved skeleton in that format (named after the saved file).
  server.route("GET", "/api/download", [&](const HttpRequest& req, HttpResponse& res) {
    const std::lock_guard<std::mutex> lock(saved.mutex);
    if (saved.bytes.empty()) return res.json_error(404, "nothing saved yet");
    std::filesystem::path name = saved.name;
    const auto format = req.query.find("format");
    if (format != req.query.end() && format->second != "ply" && format->second != "ma")
      return res.json_error(400, "format must be ply or ma (got '" + format->second + "')");
    const bool converted = format != req.query.end() && "." + format->second != name.extension();
    if (converted) name.replace_extension("." + format->second);
    res.headers.emplace_back("Content-Disposition",
                             "attachment; filename=\"" + name.string() + "\"");
    res.content_type = "application/octet-stream";
    res.body = converted ? medial_mesh_file(name.string(), saved.mesh) : saved.bytes;
  });

  std::atomic<bool> stopping{false};
  const auto stop = [&] {
    stopping = true;
    server.stop();  // also before serve() has started: it then returns at once
  };
  std::thread signal_watcher([&] {
    int signal = 0;
    sigwait(&stop_signals, &signal);
    if (signal != SIGUSR1) stop();
  });
  std::thread close_watcher([&] {
    auto empty_since = std::chrono::steady_clock::now();
    while (!stopping) {
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      if (pages > 0 || !page_seen)
        empty_since = std::chrono::steady_clock::now();
      else if (exit_on_close && std::chrono::steady_clock::now() - empty_since > kCloseGrace)
        stop();
    }
  });

  std::cout << origin << "/?token=" << token << std::endl;
  std::cerr << "vmas edit: " << input << ", " << session.shape().size()
            << " points; open the URL above; Ctrl-C stops\n";
  server.serve();
  stopping = true;
  pthread_kill(signal_watcher.native_handle(), SIGUSR1);
  signal_watcher.join();
  close_watcher.join();
  return 0;
}

}  // namespace vmas::cli
