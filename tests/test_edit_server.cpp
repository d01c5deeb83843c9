// `vmas edit` over its HTTP protocol, as a browser (or another front end) speaks it: the binary
// is started on port 0, its first stdout line gives the URL, and an HTTP client edits.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <functional>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <thread>

#include "cli_fixture.hpp"
#include "test_shapes.hpp"
#include "vmas/io.hpp"
// After Eigen: httplib.h brings <resolv.h>, whose _res macro breaks Eigen's headers.
#include <httplib.h>

namespace vmas {
namespace {

using json = nlohmann::json;

class EditServer : public test::CliTest {
 protected:
  void TearDown() override {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    test::CliTest::TearDown();
  }

  // Starts `vmas edit ARGUMENTS` and reads the URL it prints first.
  void start(const std::vector<std::string>& arguments) {
    int pipe_ends[2];
    ASSERT_EQ(pipe(pipe_ends), 0);
    pid_ = fork();
    ASSERT_GE(pid_, 0);
    if (pid_ == 0) {
      dup2(pipe_ends[1], STDOUT_FILENO);
      freopen(path("stderr").c_str(), "w", stderr);
      close(pipe_ends[0]);
      std::vector<const char*> argv = {VMAS_CLI, "edit"};
      for (const std::string& a : arguments) argv.push_back(a.c_str());
      argv.push_back(nullptr);
      execv(VMAS_CLI, const_cast<char* const*>(argv.data()));
      _exit(127);
    }
    close(pipe_ends[1]);
    FILE* out = fdopen(pipe_ends[0], "r");
    char line[512] = {};
    ASSERT_NE(fgets(line, sizeof line, out), nullptr) << test::read_text(path("stderr"));
    std::smatch match;
    const std::string url = line;
    ASSERT_TRUE(std::regex_search(url, match, std::regex(R"(^http://127\.0\.0\.1:(\d+)/\?token=([0-9a-f]{32})\n$)")))
        << url;
    port_ = std::stoi(match[1]);
    token_ = match[2];
    client_ = std::make_unique<httplib::Client>("127.0.0.1", port_);
    client_->set_read_timeout(30, 0);
  }

  std::string api(const std::string& route) const { return route + "?token=" + token_; }

  httplib::Result edit(const json& body) {
    return client_->Post(api("/api/edit").c_str(), body.dump(), "application/json");
  }

  // Reads the states of one event stream until `done` says so (or `seconds` pass); returns the
  // last one.
  json state_when(const std::function<bool(const json&)>& done, int seconds = 30) {
    json last;
    std::string buffer;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
    httplib::Client events("127.0.0.1", port_);
    events.set_read_timeout(30, 0);
    events.Get(api("/api/events").c_str(), [&](const char* data, std::size_t size) {
      buffer.append(data, size);
      for (std::size_t end; (end = buffer.find("\n\n")) != std::string::npos;) {
        const std::string event = buffer.substr(0, end);
        buffer.erase(0, end + 2);
        if (event.rfind("data: ", 0) != 0) continue;
        last = json::parse(event.substr(6));
        if (done(last)) return false;
      }
      return std::chrono::steady_clock::now() < deadline;
    });
    return last;
  }

  json state_with_spheres(std::size_t count) {
    return state_when([&](const json& s) { return s["spheres"].size() == count; });
  }

  pid_t pid_ = -1;
  int port_ = 0;
  std::string token_;
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(EditServer, EditsOverHttpChangeTheSkeletonAndSaveIt) {
  write_surface(path("capsule.xyz"), test::sample_capsule(0.2, 1.0, 3000, 53).cloud());
  start({path("capsule.xyz"), "--spheres", "6", "-o", path("saved.ply"), "--threads", "1"});

  const auto shape = client_->Get(api("/api/shape").c_str());
  ASSERT_TRUE(shape);
  ASSERT_EQ(shape->status, 200);
  const std::uint32_t points = *reinterpret_cast<const std::uint32_t*>(shape->body.data());
  const std::uint32_t faces = *reinterpret_cast<const std::uint32_t*>(shape->body.data() + 4);
  EXPECT_EQ(faces, 0u);  // a cloud
  EXPECT_EQ(shape->body.size(), 8 + 24 * static_cast<std::size_t>(points));
  EXPECT_GT(points, 2000u);

  const json first = state_when([](const json&) { return true; });
  ASSERT_TRUE(first.contains("preparation")) << first.dump();
  EXPECT_EQ(first["preparation"]["points"].get<std::uint32_t>(), points);
  EXPECT_EQ(first["preparation"]["thinned_from"], 0);
  EXPECT_TRUE(first["preparation"]["warnings"].empty());
  // A cloud's genus is unknown: no loop is extra.
  const json& topology = first["topology"];
  EXPECT_TRUE(topology["input_genus"].is_null()) << topology.dump();
  EXPECT_EQ(topology["input_genus_unknown"], "a point cloud (no faces)");
  EXPECT_EQ(topology["b0"], 1);
  EXPECT_TRUE(topology["extra_loops"].empty());
  const json grown = state_with_spheres(6);
  ASSERT_EQ(grown["spheres"].size(), 6u);
  EXPECT_TRUE(grown.contains("edges"));

  // Remove one; the count stays down.
  const std::uint64_t removed = grown["keys"][2];
  auto reply = edit({{"op", "remove"}, {"key", removed}});
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->status, 200) << reply->body;
  const json fewer = state_with_spheres(5);
  ASSERT_EQ(fewer["spheres"].size(), 5u);
  for (const auto& key : fewer["keys"]) EXPECT_NE(key.get<std::uint64_t>(), removed);

  // Freeze one, split elsewhere: the frozen sphere does not move.
  const std::uint64_t frozen = fewer["keys"][0];
  EXPECT_EQ(edit({{"op", "freeze"}, {"key", frozen}, {"frozen", true}})->status, 200);
  const json is_frozen = state_when([](const json& s) { return s["frozen"][0].get<bool>(); });
  EXPECT_EQ(edit({{"op", "split"}, {"vertex", 17}})->status, 200);
  const json split = state_when([&](const json& s) {
    return s["spheres"].size() == 6 && s["iteration"] > is_frozen["iteration"].get<int>() + 5;
  });
  ASSERT_EQ(split["spheres"].size(), 6u);
  EXPECT_EQ(split["keys"][0], frozen);
  EXPECT_EQ(split["spheres"][0], is_frozen["spheres"][0]);

  // Save: it finishes the skeleton first (as vmas skeletonize ends: final refits, refinement)
  // and pauses; the file has the spheres the page then shows.
  reply = edit({{"op", "save"}});
  ASSERT_EQ(reply->status, 200) << reply->body;
  const json save_reply = json::parse(reply->body);
  EXPECT_TRUE(save_reply["finished"].get<bool>());
  const json finished = state_when([](const json& s) { return s["finished"].get<bool>(); });
  EXPECT_TRUE(finished["paused"].get<bool>());
  EXPECT_LE(finished["error_after_finish_percent"].get<double>(),
            finished["error_before_finish_percent"].get<double>());
  EXPECT_DOUBLE_EQ(save_reply["error_percent"].get<double>(),
                   finished["error_after_finish_percent"].get<double>());
  const MedialMesh saved = read_medial_mesh(path("saved.ply"));
  EXPECT_EQ(saved.spheres.size(), save_reply["spheres"].get<std::size_t>());
  EXPECT_EQ(saved.spheres.size(), finished["spheres"].size());
  EXPECT_EQ(client_->Get(api("/api/download").c_str())->body, test::read_text(path("saved.ply")));

  // Ctrl-C stops it cleanly.
  kill(pid_, SIGINT);
  int status = 0;
  waitpid(pid_, &status, 0);
  pid_ = -1;
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
}

// Each state carries the medial mesh's Betti numbers, the input's genus, and the triangles that
// close its cavities (kept here: --keep-cavities) by sphere index, as `faces` lists them.
TEST_F(EditServer, EachStateCarriesTheTopologyAndTheCavitiesTriangles) {
  write_surface(path("torus.off"), test::torus(1.0, 0.3, 48, 16));
  start({path("torus.off"), "--spheres", "100", "--keep-cavities", "--threads", "1"});
  json faces;
  const json s = state_when([&](const json& s) {
    if (s.contains("faces")) faces = s["faces"];
    return s["spheres"].size() == 100 && s["topology"]["b2"] > 0;
  });
  const json& topology = s["topology"];
  ASSERT_GT(topology["b2"].get<int>(), 0) << topology.dump();
  EXPECT_EQ(topology["input_genus"], json::array({1}));
  EXPECT_EQ(topology["cavity_triangles"].size(), topology["b2"].get<std::size_t>());
  for (const json& triangle : topology["cavity_triangles"])
    EXPECT_NE(std::find(faces.begin(), faces.end(), triangle), faces.end()) << triangle.dump();
  // Settled: one piece and one loop, the torus's (none extra).
  const json one = state_when(
      [](const json& s) { return s["topology"]["b0"] == 1 && s["topology"]["b1"] == 1; });
  EXPECT_EQ(one["topology"]["b0"], 1);
  EXPECT_EQ(one["topology"]["b1"], 1);
  EXPECT_TRUE(one["topology"]["extra_loops"].empty());
}

// The page's ε is what vmas eval says of the skeleton a save writes: measured whenever the
// skeleton holds still, here paused after an edit (at the step of the figure before it: only
// save_error_is_current tells the two apart).
TEST_F(EditServer, ThePagesErrorIsVmasEvalsOfWhatASaveWrites) {
  write_surface(path("capsule.xyz"), test::sample_capsule(0.2, 1.0, 3000, 53).cloud());
  start({path("capsule.xyz"), "--spheres", "8", "-o", path("saved.ply"), "--threads", "1",
         "--finish-on-save", "false"});
  ASSERT_EQ(state_with_spheres(8)["spheres"].size(), 8u);
  ASSERT_TRUE(edit({{"op", "pause"}}));
  ASSERT_TRUE(edit({{"op", "target"}, {"spheres", 7}}));  // an edit while paused
  const json paused = state_when([](const json& state) {
    return state["paused"].get<bool>() && state["spheres"].size() == 7u &&
           state["save_error_is_current"].get<bool>();
  });
  EXPECT_GT(paused["save_error_percent"].get<double>(), 0.0);
  EXPECT_EQ(paused["save_error_at_iteration"], paused["iteration"]);
  ASSERT_EQ(paused["spheres"].size(), 7u) << paused.dump();
  const auto saved = edit({{"op", "save"}});
  ASSERT_TRUE(saved);
  ASSERT_EQ(saved->status, 200) << saved->body;
  const test::CliResult eval =
      run("eval " + path("capsule.xyz") + " " + path("saved.ply") + " --json");
  ASSERT_EQ(eval.exit_code, 0) << eval.err;
  EXPECT_NEAR(paused["save_error_percent"].get<double>(),
              json::parse(eval.out)["hausdorff_percent"].get<double>(), 1e-3);
}

TEST_F(EditServer, TheDensityIsPaintedSavedAndLoadedByInputRow) {
  SurfaceInput cloud = test::sample_capsule(0.2, 1.0, 3000, 59).cloud();
  cloud.points.push_back(cloud.points[10]);  // a duplicate row: dropped, saved as 1
  cloud.normals.push_back(cloud.normals[10]);
  write_surface(path("capsule.xyz"), cloud);
  start({path("capsule.xyz"), "--spheres", "8", "--threads", "1"});
  ASSERT_EQ(state_with_spheres(8)["spheres"].size(), 8u);
  const auto uniform = client_->Get(api("/api/density").c_str());
  ASSERT_EQ(uniform->status, 200);
  ASSERT_EQ(uniform->body.size(), 3000 * sizeof(float));
  ASSERT_TRUE(edit({{"op", "density"}, {"vertex", 0}, {"radius", 0.2}, {"amount", 3.0}}));
  const json painted = state_when([](const json& state) { return state["density_changes"] == 1; });
  ASSERT_EQ(painted["density_changes"], 1) << painted.dump();
  const auto values = client_->Get(api("/api/density").c_str());
  std::vector<float> density(3000);
  std::memcpy(density.data(), values->body.data(), values->body.size());
  EXPECT_FLOAT_EQ(density[0], 4.0f);
  // The stroke reaches radius × the diagonal /api/shape gives, in its coordinates (the page's
  // brush ring).
  const auto shape = client_->Get(api("/api/shape").c_str());
  ASSERT_TRUE(shape->has_header("X-Vmas-Diagonal"));
  const double reach = 0.2 * std::stod(shape->get_header_value("X-Vmas-Diagonal"));
  const auto* xyz = reinterpret_cast<const float*>(shape->body.data() + 8);
  int inside = 0;
  for (std::size_t v = 0; v < density.size(); ++v) {
    const double distance =
        std::hypot(xyz[3 * v] - xyz[0], xyz[3 * v + 1] - xyz[1], xyz[3 * v + 2] - xyz[2]);
    if (distance < 0.99 * reach) {
      ++inside;
      EXPECT_GT(density[v], 1.0f) << v;
    }
    if (distance > 1.01 * reach) EXPECT_EQ(density[v], 1.0f) << v;
  }
  EXPECT_GT(inside, 100);
  // Saved by input row (3001 lines, the duplicate 1), loaded again as it was.
  const auto file = client_->Get(api("/api/density-file").c_str());
  ASSERT_EQ(file->status, 200);
  EXPECT_EQ(std::count(file->body.begin(), file->body.end(), '\n'), 3001);
  EXPECT_EQ(file->body.substr(0, 2), "4\n");
  ASSERT_TRUE(edit({{"op", "density-reset"}}));
  state_when([](const json& state) { return state["density_changes"] == 2; });
  ASSERT_TRUE(edit({{"op", "density-load"}, {"text", file->body}}));
  state_when([](const json& state) { return state["density_changes"] == 3; });
  const auto loaded = client_->Get(api("/api/density").c_str());
  ASSERT_EQ(loaded->body.size(), values->body.size());
  std::vector<float> reloaded(3000);
  std::memcpy(reloaded.data(), loaded->body.data(), loaded->body.size());
  for (std::size_t v = 0; v < density.size(); ++v)
    ASSERT_NEAR(reloaded[v], density[v], 1e-6 * density[v]) << v;  // 9 digits in the file
  // A file over 64 KB (numpy's savetxt: 25 bytes a row) is taken: the body limit grows with
  // the input.
  std::string long_rows;
  for (int row = 0; row < 3001; ++row) long_rows += "2.000000000000000000e+00\n";
  const auto long_file = edit({{"op", "density-load"}, {"text", long_rows}});
  ASSERT_TRUE(long_file);
  EXPECT_EQ(long_file->status, 200) << long_file->body;
  state_when([](const json& state) { return state["density_changes"] == 4; });
  const auto doubled = client_->Get(api("/api/density").c_str());
  std::vector<float> twos(3000);
  std::memcpy(twos.data(), doubled->body.data(), doubled->body.size());
  EXPECT_EQ(std::count(twos.begin(), twos.end(), 2.0f), 3000);
  const auto bad = edit({{"op", "density-load"}, {"text", "1\n2\n"}});
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
  EXPECT_NE(bad->body.find("density file: 2 density values for the input's 3001 points"),
            std::string::npos)
      << bad->body;
  const auto negative = edit({{"op", "density"}, {"vertex", 0}, {"radius", 2.0}, {"amount", 1.0}});
  EXPECT_EQ(negative->status, 400);
}

TEST_F(EditServer, RefusesRequestsWithoutTheTokenFromOtherSitesAndBadEdits) {
  write_surface(path("ball.off"), test::icosphere(Vec3::Zero(), 1.0, 3));
  start({path("ball.off"), "--spheres", "3", "--threads", "1"});
  EXPECT_EQ(client_->Get("/api/shape")->status, 403);
  EXPECT_EQ(client_->Get("/api/shape?token=0123")->status, 403);
  EXPECT_EQ(client_->Get(api("/").c_str(), {{"Origin", "http://evil.example"}})->status, 403);
  const auto page = client_->Get(api("/").c_str());
  ASSERT_EQ(page->status, 200);
  EXPECT_NE(page->body.find(token_), std::string::npos);  // the script tags carry it

  const json state = state_with_spheres(3);
  ASSERT_EQ(state["spheres"].size(), 3u);
  const auto refused = [&](const std::string& body) {
    const auto r = client_->Post(api("/api/edit").c_str(), body, "application/json");
    EXPECT_TRUE(r);
    if (!r) return std::string();
    EXPECT_GE(r->status, 400) << body;
    return r->body;
  };
  EXPECT_NE(refused("not json").find("bad edit"), std::string::npos);
  EXPECT_NE(refused(R"({"op": "explode"})").find("unknown op"), std::string::npos);
  EXPECT_NE(refused(R"({"op": "remove", "key": 99999})").find("no sphere"), std::string::npos);
  EXPECT_NE(refused(R"({"op": "split", "vertex": -4})").find("no vertex"), std::string::npos);
  EXPECT_NE(refused(R"({"op": "lambda", "times": -2})").find("factor"), std::string::npos);
  // Numbers are checked before they are narrowed (2^32 + 1 once became a count of 1).
  EXPECT_NE(refused(R"({"op": "target", "spheres": 4294967297})").find("integer"), std::string::npos);
  EXPECT_NE(refused(R"({"op": "split", "vertex": 1e20})").find("integer"), std::string::npos);
  refused(std::string(200 * 1024, 'x'));  // beyond the request size limit
  // Still running and answering.
  EXPECT_EQ(client_->Get(api("/api/shape").c_str())->status, 200);
  EXPECT_EQ(state_with_spheres(3)["spheres"].size(), 3u);
}

// Relative edits add up in arrival order (five quick +1 are +5, whatever the page last saw);
// without -o, save keeps the skeleton for the download.
TEST_F(EditServer, RelativeEditsAddUpAndSavingWithoutOutputDownloads) {
  const SurfaceInput ball = test::icosphere(Vec3::Zero(), 1.0, 3);
  write_surface(path("ball.off"), ball);
  start({path("ball.off"), "--spheres", "3", "--threads", "1"});
  EXPECT_EQ(client_->Get(api("/api/download").c_str())->status, 404);  // nothing saved yet
  // A mesh's faces go to the page after its points and normals.
  const std::string shape = client_->Get(api("/api/shape").c_str())->body;
  std::uint32_t counts[2];
  std::memcpy(counts, shape.data(), sizeof counts);
  EXPECT_EQ(counts[0], ball.points.size());
  ASSERT_EQ(counts[1], ball.faces.size());
  ASSERT_EQ(shape.size(), 8 + 24 * std::size_t(counts[0]) + 12 * std::size_t(counts[1]));
  std::uint32_t first_face[3];
  std::memcpy(first_face, shape.data() + 8 + 24 * std::size_t(counts[0]), sizeof first_face);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(first_face[c], std::uint32_t(ball.faces[0][c]));
  ASSERT_EQ(state_with_spheres(3)["spheres"].size(), 3u);
  for (int i = 0; i < 5; ++i) ASSERT_EQ(edit({{"op", "target"}, {"by", 1}})->status, 200);
  EXPECT_EQ(state_when([](const json& s) { return s["target_spheres"] == 8; })["target_spheres"], 8);
  for (int i = 0; i < 2; ++i) ASSERT_EQ(edit({{"op", "target"}, {"by", -1}})->status, 200);
  EXPECT_EQ(state_with_spheres(6)["spheres"].size(), 6u);
  const double lambda = state_when([](const json&) { return true; })["lambda"];
  ASSERT_EQ(edit({{"op", "lambda"}, {"times", 2.0}})->status, 200);
  ASSERT_EQ(edit({{"op", "lambda"}, {"times", 2.0}})->status, 200);
  EXPECT_DOUBLE_EQ(state_when([&](const json& s) {
                     return s["lambda"].get<double>() > 3 * lambda;
                   })["lambda"].get<double>(),
                   4 * lambda);

  const auto saved = edit({{"op", "save"}});
  ASSERT_EQ(saved->status, 200) << saved->body;
  const json reply = json::parse(saved->body);
  EXPECT_EQ(reply["name"], "ball_skeleton.ply");
  EXPECT_FALSE(reply.contains("path"));
  const auto download = client_->Get(api("/api/download").c_str());
  ASSERT_EQ(download->status, 200);
  write("downloaded.ply", download->body);
  EXPECT_EQ(read_medial_mesh(path("downloaded.ply")).spheres.size(),
            reply["spheres"].get<std::size_t>());
  // The same skeleton as a .ma file on request; no other format.
  const auto ma = client_->Get(api("/api/download").append("&format=ma").c_str());
  ASSERT_EQ(ma->status, 200);
  EXPECT_NE(ma->get_header_value("Content-Disposition").find("ball_skeleton.ma"), std::string::npos);
  write("downloaded.ma", ma->body);
  const MedialMesh from_ply = read_medial_mesh(path("downloaded.ply"));
  const MedialMesh from_ma = read_medial_mesh(path("downloaded.ma"));
  ASSERT_EQ(from_ma.spheres.size(), from_ply.spheres.size());
  EXPECT_EQ(from_ma.edges, from_ply.edges);
  for (std::size_t i = 0; i < from_ma.spheres.size(); ++i)
    EXPECT_NEAR(from_ma.spheres[i].radius, from_ply.spheres[i].radius, 1e-6);
  EXPECT_EQ(client_->Get(api("/api/download").append("&format=obj").c_str())->status, 400);
}

// One event stream over a removal: the page is sent where each sphere went, not every label,
// and its labels, kept up from the first event's by renumberings and changes, end as the
// server's. The error map's distances are the surface -> medial distances of those vertices.
TEST_F(EditServer, ARemovalSendsARenumberingAndTheErrorMapMeasuresEachVertex) {
  const test::Sample s = test::sample_capsule(0.2, 1.0, 6000, 59);
  SurfaceInput cloud;
  cloud.points = s.points;
  write_surface(path("capsule.xyz"), cloud);
  start({path("capsule.xyz"), "--spheres", "8", "--threads", "1"});

  std::vector<int> labels;  // as a page holds them
  bool removal_sent = false, renumbered = false, resent_all = false, paused_sent = false;
  state_when([&](const json& state) {
    if (state.contains("labels")) {
      labels = state["labels"].get<std::vector<int>>();
      resent_all = removal_sent;
    }
    if (state.contains("renumber")) {
      const std::vector<int> moved_to = state["renumber"].get<std::vector<int>>();
      for (int& label : labels)
        if (label >= 0) label = moved_to.at(label);
      renumbered = renumbered || removal_sent;
    }
    for (const auto& change : state.value("label_changes", json::array()))
      labels.at(change[0].get<std::size_t>()) = change[1];
    if (!removal_sent && state["spheres"].size() == 8 && state["iteration"].get<int>() > 40) {
      // Not the last sphere: the ones after it shift down.
      EXPECT_EQ(edit({{"op", "remove"}, {"key", state["keys"][1]}})->status, 200);
      removal_sent = true;
    } else if (removal_sent && !paused_sent && state["spheres"].size() == 7) {
      EXPECT_EQ(edit({{"op", "pause"}, {"paused", true}})->status, 200);
      paused_sent = true;
    } else if (paused_sent && state["paused"].get<bool>()) {
      const auto latest = client_->Get(api("/api/labels").c_str());
      if (latest->get_header_value("X-Vmas-Version") != std::to_string(state["version"].get<std::uint64_t>()))
        return false;  // a newer state is on its way
      std::vector<int> server(latest->body.size() / sizeof(int));
      std::memcpy(server.data(), latest->body.data(), latest->body.size());
      EXPECT_EQ(labels, server);
      return true;
    }
    return false;
  }, 60);
  ASSERT_TRUE(paused_sent) << "the removal never showed";
  EXPECT_TRUE(renumbered);
  EXPECT_FALSE(resent_all);
  for (int label : labels) EXPECT_TRUE(label >= 0 && label < 7) << label;

  // The error map after a finish: one distance per vertex, none above the measured two-sided
  // error (its surface side is the largest of these), the largest close to a sphere's size.
  ASSERT_EQ(edit({{"op", "finish"}})->status, 200);
  const json finished = state_when([](const json& s) { return s["finished"].get<bool>(); });
  const auto map = client_->Get(api("/api/errors").c_str());
  ASSERT_EQ(map->status, 200);
  ASSERT_EQ(map->body.size(), labels.size() * sizeof(float));
  std::vector<float> errors(labels.size());
  std::memcpy(errors.data(), map->body.data(), map->body.size());
  float largest = 0.0f;
  for (float e : errors) {
    ASSERT_TRUE(std::isfinite(e) && e >= 0.0f) << e;
    largest = std::max(largest, e);
  }
  EXPECT_GT(largest, 0.0f);
  EXPECT_LE(100.0 * largest, finished["error_after_finish_percent"].get<double>() + 1e-3);
}

TEST_F(EditServer, SeveralPagesSeeOneStateAndClosingTheLastStopsWithExitOnClose) {
  write_surface(path("ball.off"), test::icosphere(Vec3::Zero(), 1.0, 3));
  start({path("ball.off"), "--spheres", "4", "--threads", "1", "--exit-on-close"});
  // Two pages at once: both follow the same session.
  json first, second;
  std::thread other([&] { second = state_with_spheres(4); });
  first = state_with_spheres(4);
  other.join();
  ASSERT_EQ(first["spheres"].size(), 4u);
  ASSERT_EQ(second["spheres"].size(), 4u);
  EXPECT_EQ(first["keys"], second["keys"]);
  // Both streams are closed now: vmas stops by itself, cleanly, a few seconds later.
  int status = 0;
  pid_t done = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while ((done = waitpid(pid_, &status, WNOHANG)) == 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_EQ(done, pid_) << "still running 20 s after the last page closed";
  pid_ = -1;
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
}

// A raw TCP connection to the server, for clients no HTTP library would be.
class RawClient {
 public:
  explicit RawClient(int port) : socket_(::socket(AF_INET, SOCK_STREAM, 0)) {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<std::uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = ::connect(socket_, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
  }
  ~RawClient() { ::close(socket_); }
  RawClient(const RawClient&) = delete;
  RawClient& operator=(const RawClient&) = delete;
  bool connected() const { return connected_; }
  bool send(const std::string& bytes) {
    return ::send(socket_, bytes.data(), bytes.size(), MSG_NOSIGNAL) ==
           static_cast<ssize_t>(bytes.size());
  }
  // What arrives within `timeout`, until the server closes (closed() then says so).
  std::string receive(std::chrono::milliseconds timeout) {
    std::string got;
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      pollfd p{socket_, POLLIN, 0};
      if (left.count() <= 0 || ::poll(&p, 1, static_cast<int>(left.count())) <= 0) return got;
      char buffer[4096];
      const ssize_t n = ::recv(socket_, buffer, sizeof buffer, 0);
      if (n <= 0) {
        closed_ = true;
        return got;
      }
      got.append(buffer, static_cast<std::size_t>(n));
    }
  }
  bool closed() const { return closed_; }
  // Whether the server has not closed its side, without waiting.
  bool still_open() {
    pollfd p{socket_, POLLIN | POLLRDHUP, 0};
    return !closed_ && (::poll(&p, 1, 0) == 0 || !(p.revents & (POLLRDHUP | POLLHUP | POLLERR)));
  }

 private:
  int socket_;
  bool connected_ = false;
  bool closed_ = false;
};

// Slow and hostile clients hold a connection each, never the server: the page is served while
// 100 of them sit on half-sent headers, a request without the token gets its 403 and the
// connection closed (before its body), a header that never arrives whole is cut off, and Ctrl-C stops the server
// whatever the clients do. (How fast: scripts/test-browser prints the figures.)
TEST_F(EditServer, SlowAndHostileClientsDoNotHoldTheServer) {
  write_surface(path("ball.off"), test::icosphere(Vec3::Zero(), 1.0, 3));
  start({path("ball.off"), "--spheres", "3", "--threads", "1"});
  std::vector<std::unique_ptr<RawClient>> slow;
  for (int i = 0; i < 100; ++i) {
    slow.push_back(std::make_unique<RawClient>(port_));
    ASSERT_TRUE(slow.back()->connected());
    ASSERT_TRUE(slow.back()->send("GET / HTTP/1.1\r\nHo"));
  }
  const auto page = client_->Get(api("/").c_str());
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  const auto open = std::count_if(slow.begin(), slow.end(), [](auto& c) { return c->still_open(); });
  EXPECT_EQ(open, 100) << "the page came only after slow clients were dropped";

  RawClient stranger(port_);
  ASSERT_TRUE(stranger.send("GET /api/shape HTTP/1.1\r\nHost: x\r\n\r\n"));
  const std::string refused = stranger.receive(std::chrono::seconds(3));
  EXPECT_EQ(refused.rfind("HTTP/1.1 403", 0), 0u) << refused;
  EXPECT_TRUE(stranger.closed()) << "a connection without the token stays open";
  // ... refused on its header: the body it announces is never waited for.
  RawClient poster(port_);
  ASSERT_TRUE(poster.send("POST /api/edit HTTP/1.1\r\nHost: x\r\nContent-Length: 50000\r\n\r\n"));
  const std::string refused_post = poster.receive(std::chrono::seconds(3));
  EXPECT_EQ(refused_post.rfind("HTTP/1.1 403", 0), 0u) << refused_post;
  EXPECT_TRUE(poster.closed());

  // One byte a second, never a whole header: the server closes the connection, unanswered
  // (the loop gives up after 15 bytes, well past the server's 10 s).
  RawClient trickler(port_);
  const std::string header = "GET /?token=" + token_ + " HTTP/1.1\r\nHost: x\r\nX-Slow: ";
  std::string answered;
  for (std::size_t i = 0; i < 15 && !trickler.closed(); ++i) {
    trickler.send(header.substr(i, 1));
    answered += trickler.receive(std::chrono::milliseconds(1000));
  }
  EXPECT_TRUE(trickler.closed());
  EXPECT_EQ(answered, "");

  // An event stream open, 100 slow clients still there: Ctrl-C ends it all, exit code 0.
  std::thread stream([&] { state_when([](const json&) { return false; }); });
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  for (auto& client : slow) client->send("s");
  kill(pid_, SIGINT);
  int status = 0;
  pid_t done = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while ((done = waitpid(pid_, &status, WNOHANG)) == 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_EQ(done, pid_) << "still running 20 s after Ctrl-C";
  pid_ = -1;
  stream.join();
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
}

}  // namespace
}  // namespace vmas
