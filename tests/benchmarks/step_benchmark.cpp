// Latency of the live-editing loop (issue 11, item 4): one Skeletonizer::step() and one edit
// followed by a step, on the 49 698-vertex vessel mesh of ../shared/data at 200 spheres, by
// thread count; and one step on a 1 000 000-point cloud sampled from armadillo, prepared as
// vmas::skeletonize prepares it (thinned to --max-points, normals estimated): what an editor on
// a big scan steps on. Prints figures; judges nothing (the targets are in the README).
//
//   build/vmas_step_benchmark [--benchmark_repetitions=5]
#include <benchmark/benchmark.h>
#include <omp.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <random>

#include "../shared_data.hpp"
#include "vmas/io.hpp"
#include "vmas/prepare.hpp"
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
  return made;
}

vmas::Skeletonizer* settled_skeletonizer() {
  static const std::unique_ptr<vmas::Skeletonizer> skeletonizer =
      std::filesystem::exists(data_path()) ? settled(vmas::read_surface(data_path())) : nullptr;
  return skeletonizer.get();
}

vmas::Skeletonizer* settled_scan_skeletonizer() {
  static const std::unique_ptr<vmas::Skeletonizer> skeletonizer = [] {
    std::unique_ptr<vmas::Skeletonizer> made;
    if (!std::filesystem::exists(data_path("armadillo"))) return made;
    vmas::SurfaceInput cloud = sampled_cloud(vmas::read_surface(data_path("armadillo")), kScanPoints);
    vmas::prepare_surface(cloud, vmas::PrepareOptions{});
    return settled(std::move(cloud));
  }();
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

BENCHMARK(BM_Step)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EditThenStep)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StepOnAThinnedScan)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
