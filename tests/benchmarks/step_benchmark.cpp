// Latency of the live-editing loop (issue 11, item 4): one Skeletonizer::step() and one edit
// followed by a step, on the 49 698-vertex vessel mesh of ../shared/data at 200 spheres, by
// thread count; and one step on a 1 000 000-point cloud sampled from armadillo, prepared as
// vmas::skeletonize prepares it (thinned to --max-points, normals estimated): what an editor on
// a big scan steps on. Prints figures; judges nothing (the targets are in the README).
//
//   build/vmas_step_benchmark [--benchmark_repetitions=5]
#include <benchmark/benchmark.h>
#include <omp.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <random>
#include <thread>

#include "../shared_data.hpp"
#include "prepare/prepare.hpp"
#include "vmas/edit_session.hpp"
#include "vmas/io.hpp"
#include "vmas/skeletonizer.hpp"

namespace {

constexpr int kSpheres = 200;

constexpr int kScanPoints = 1000000;

std::string data_path(const std::string& model = "vessel") {
  return vmas::test::shared_data("meshes/" + model + ".off");
}

// Area-weighted uniform samples of a mesh's faces, without normals (fixed seed).
vmas::SurfaceInput sampled_cloud(const vmas::SurfaceInput& mesh, int count) {
  std::vector<double> areas;
  for (const auto& f : mesh.faces)
    areas.push_back((mesh.points[f[1]] - mesh.points[f[0]])
                        .cross(mesh.points[f[2]] - mesh.points[f[0]])
                        .norm());
  std::mt19937 rng(1);
  std::discrete_distribution<std::size_t> face(areas.begin(), areas.end());
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  vmas::SurfaceInput cloud;
  for (int i = 0; i < count; ++i) {
    const auto& f = mesh.faces[face(rng)];
    double u = uniform(rng), v = uniform(rng);
    if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
    cloud.points.push_back(mesh.points[f[0]] + u * (mesh.points[f[1]] - mesh.points[f[0]]) +
                           v * (mesh.points[f[2]] - mesh.points[f[0]]));
  }
  return cloud;
}

// Settled at 200 spheres once, then shared by every benchmark of the same input.
std::unique_ptr<vmas::Skeletonizer> settled(vmas::SurfaceInput surface) {
  vmas::SkeletonizerOptions options;
  options.target.spheres = kSpheres;
  auto made = std::make_unique<vmas::Skeletonizer>(
      vmas::build_shape(surface, vmas::ShapeOptions{}), options);
  made->run();
  made->pass_over_settled(true);  // as vmas edit steps
  return made;
}

vmas::Skeletonizer* settled_skeletonizer() {
  static const std::unique_ptr<vmas::Skeletonizer> skeletonizer =
      std::filesystem::exists(data_path()) ? settled(vmas::read_surface(data_path())) : nullptr;
  return skeletonizer.get();
}

// The 1 M-point cloud as skeletonize() prepares it (thinned, normals estimated); nullptr without
// the shared data.
const vmas::SurfaceInput* prepared_scan() {
  static const std::unique_ptr<vmas::SurfaceInput> cloud = [] {
    std::unique_ptr<vmas::SurfaceInput> made;
    if (!std::filesystem::exists(data_path("armadillo"))) return made;
    made = std::make_unique<vmas::SurfaceInput>(
        sampled_cloud(vmas::read_surface(data_path("armadillo")), kScanPoints));
    vmas::prepare_surface(*made, vmas::PrepareOptions{});
    return made;
  }();
  return cloud.get();
}

vmas::Skeletonizer* settled_scan_skeletonizer() {
  static const std::unique_ptr<vmas::Skeletonizer> skeletonizer =
      prepared_scan() ? settled(*prepared_scan()) : nullptr;
  return skeletonizer.get();
}

// The skeletonizer a benchmark times, with the thread count of its argument; nullptr (the
// benchmark reported as skipped) without the shared data.
vmas::Skeletonizer* prepared_for(benchmark::State& state, vmas::Skeletonizer* skeletonizer,
                                 const std::string& model) {
  if (!skeletonizer)
    state.SkipWithError(("shared data not found: " + data_path(model)).c_str());
  else
    omp_set_num_threads(static_cast<int>(state.range(0)));
  return skeletonizer;
}

void BM_Step(benchmark::State& state) {
  vmas::Skeletonizer* skeletonizer = prepared_for(state, settled_skeletonizer(), "vessel");
  if (!skeletonizer) return;
  for (auto _ : state) benchmark::DoNotOptimize(skeletonizer->step());
  state.counters["vertices"] = skeletonizer->shape().size();
  state.counters["spheres"] = static_cast<double>(skeletonizer->spheres().size());
}

void BM_StepOnAThinnedScan(benchmark::State& state) {
  vmas::Skeletonizer* skeletonizer =
      prepared_for(state, settled_scan_skeletonizer(), "armadillo");
  if (!skeletonizer) return;
  for (auto _ : state) benchmark::DoNotOptimize(skeletonizer->step());
  state.counters["scan_points"] = kScanPoints;
  state.counters["vertices"] = skeletonizer->shape().size();
}

// What a key press costs before the page can show it: remove a sphere, add one at a vertex
// (a split under the mouse), and the step that re-settles both.
void BM_EditThenStep(benchmark::State& state) {
  vmas::Skeletonizer* skeletonizer = prepared_for(state, settled_skeletonizer(), "vessel");
  if (!skeletonizer) return;
  int vertex = 0;
  for (auto _ : state) {
    skeletonizer->remove_sphere(0);
    vertex = (vertex + 7919) % skeletonizer->shape().size();
    skeletonizer->add_sphere_at(vertex);
    benchmark::DoNotOptimize(skeletonizer->step());
  }
  state.counters["spheres"] = static_cast<double>(skeletonizer->spheres().size());
}

// The step that answers an edit, alone: its spheres' neighbours are fitted again, while the
// settled ones elsewhere are passed over (BM_Step, long settled, passes over nearly all).
void BM_StepAfterEdit(benchmark::State& state) {
  vmas::Skeletonizer* skeletonizer = prepared_for(state, settled_skeletonizer(), "vessel");
  if (!skeletonizer) return;
  int vertex = 0;
  for (auto _ : state) {
    state.PauseTiming();
    skeletonizer->remove_sphere(0);
    vertex = (vertex + 7919) % skeletonizer->shape().size();
    skeletonizer->add_sphere_at(vertex);
    state.ResumeTiming();
    benchmark::DoNotOptimize(skeletonizer->step());
  }
}

// The editor's engine alone (no page): a session on the 1 M-point scan, growing from one sphere
// to 200, then edited (a split and a removal every 100 ms for 3 s). Its published states per
// second in each phase are the updates a page could show (issue 45: at least 10).
void BM_EditSessionOnAThinnedScan(benchmark::State& state) {
  if (!prepared_scan()) {
    state.SkipWithError(("shared data not found: " + data_path("armadillo")).c_str());
    return;
  }
  using Clock = std::chrono::steady_clock;
  const auto seconds_since = [](Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
  };
  const vmas::Shape shape = vmas::build_shape(*prepared_scan(), vmas::ShapeOptions{});
  double growing = 0.0, editing = 0.0, growing_seconds = 0.0;
  for (auto _ : state) {
    vmas::SkeletonizerOptions options;
    options.target.spheres = kSpheres;
    vmas::EditSession session(shape, options, static_cast<int>(state.range(0)));
    const auto start = Clock::now();
    vmas::EditSnapshot now = session.snapshot();
    while (now.spheres.size() < static_cast<std::size_t>(kSpheres) && seconds_since(start) < 120) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      now = session.snapshot();
    }
    growing_seconds = seconds_since(start);
    growing = static_cast<double>(now.version) / growing_seconds;
    const std::uint64_t grown = now.version;
    const auto edits_start = Clock::now();
    int vertex = 0;
    while (seconds_since(edits_start) < 3.0) {
      vertex = (vertex + 7919) % shape.size();
      session.split_at(vertex);
      session.remove(now.keys.front());
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      now = session.snapshot();
    }
    editing = static_cast<double>(now.version - grown) / seconds_since(edits_start);
  }
  state.counters["vertices"] = shape.size();
  state.counters["growing_s"] = growing_seconds;
  state.counters["updates_per_s_growing"] = growing;
  state.counters["updates_per_s_editing"] = editing;
}

BENCHMARK(BM_Step)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EditSessionOnAThinnedScan)
    ->Arg(2)
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();
BENCHMARK(BM_EditThenStep)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StepAfterEdit)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StepOnAThinnedScan)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
