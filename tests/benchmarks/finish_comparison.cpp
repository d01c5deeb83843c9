// The editor's finished skeleton against vmas skeletonize's (issue 21, item 3): for every mesh of
// Table 1 at the paper's sphere count, the two-sided Hausdorff distance (vmas eval's measure, %
// of the input's diagonal) of the CLI's result, of the editor's skeleton after its optimisation
// has run for 4 s, and of that skeleton after EditSession::finish(). Prints figures; judges
// nothing.
//
//   build/vmas_finish_comparison [MODEL ... | FILE:SPHERES ...]
// e.g. FILE:SPHERES = armadillo_1000000.ply:200 (scripts/bench --scaling writes such clouds).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "../shared_data.hpp"
#include "vmas/edit_session.hpp"
#include "vmas/eval.hpp"
#include "vmas/io.hpp"
#include "vmas/vmas.hpp"

namespace {

using namespace vmas;

const std::map<std::string, int> kPaperSpheres = {
    {"armadillo", 83}, {"bear", 45},  {"bug", 75},       {"chair", 117},
    {"dolphin", 51},   {"dove", 76},  {"elephant", 117}, {"fertility", 98},
    {"pinion", 230},   {"plane", 86}, {"santa", 90},     {"vessel", 99}};

double percent(const SurfaceInput& input, const MedialMesh& medial) {
  const EvalResult result = evaluate(input, medial);
  return result.percent(result.hausdorff);
}

void compare(const std::string& model, const std::string& file, int spheres) {
  const SurfaceInput input = read_surface(file);
  Options options;
  options.run.target.spheres = spheres;
  options.threads = 2;
  const double cli = percent(input, skeletonize(input, options).medial_mesh);
  PreparedShape prepared = prepare_shape(input, options);
  const Frame frame = prepared.result.prepare.frame;
  const FinishOptions finish = finish_as_skeletonize_does(prepared, options);
  EditSession session(std::move(prepared.shape), prepared.run, options.threads, finish);
  const auto start = std::chrono::steady_clock::now();
  EditSnapshot s = session.snapshot();
  while (static_cast<int>(s.spheres.size()) < spheres ||
         std::chrono::steady_clock::now() - start < std::chrono::seconds(4)) {
    session.wait_for_version(s.version, 200);
    s = session.snapshot();
  }
  const double live = percent(input, frame.to_input(s.mesh));
  session.finish();
  while (s.finishes == 0) {
    session.wait_for_version(s.version, 200);
    s = session.snapshot();
  }
  const double finished = percent(input, frame.to_input(s.mesh));
  std::printf("%-10s %4d  CLI %.3f  editor live %.3f  finished %.3f  (finished - CLI %+.3f)\n",
              model.c_str(), spheres, cli, live, finished, finished - cli);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  if (!std::filesystem::exists(test::shared_data("meshes"))) {
    std::fprintf(stderr, "shared data not found: %s\n", test::shared_data("meshes").c_str());
    return 1;
  }
  std::vector<std::string> models;
  for (int i = 1; i < argc; ++i) models.push_back(argv[i]);
  if (models.empty())
    for (const auto& [model, spheres] : kPaperSpheres) models.push_back(model);
  std::printf("ε %% of the diagonal (vmas eval's measure); spheres: the paper's count\n");
  for (const std::string& model : models) {
    const std::size_t colon = model.rfind(':');
    if (colon != std::string::npos) {
      compare(std::filesystem::path(model.substr(0, colon)).filename().string(),
              model.substr(0, colon), std::stoi(model.substr(colon + 1)));
      continue;
    }
    const auto found = kPaperSpheres.find(model);
    if (found == kPaperSpheres.end()) {
      std::fprintf(stderr, "unknown model %s\n", model.c_str());
      return 1;
    }
    compare(model, test::shared_data("meshes/" + model + ".off"), found->second);
  }
  return 0;
}
