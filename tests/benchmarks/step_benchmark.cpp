// Latency of the live-editing loop (issue 11, item 4): one Skeletonizer::step() and one edit
// followed by a step, on the 49 698-vertex vessel mesh of ../shared/data at 200 spheres, by
// thread count. Prints figures; judges nothing (the targets are in the README).
//
//   build/vmas_step_benchmark [--benchmark_repetitions=5]
#include <benchmark/benchmark.h>
#include <omp.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>

#include "vmas/io.hpp"
#include "vmas/skeletonizer.hpp"

namespace {

constexpr int kSpheres = 200;

std::string data_path() {
  const char* override_dir = std::getenv("VMAS_SHARED_DATA");
  return (std::filesystem::path(override_dir ? override_dir : VMAS_SHARED_DATA) /
          "meshes/vessel.off")
      .string();
}

// Settled at 200 spheres once, then shared by every benchmark.
vmas::Skeletonizer* settled_skeletonizer() {
  static std::unique_ptr<vmas::Skeletonizer> skeletonizer = [] {
    std::unique_ptr<vmas::Skeletonizer> made;
    if (!std::filesystem::exists(data_path())) return made;
    vmas::SkeletonizerOptions options;
    options.target_spheres = kSpheres;
    made = std::make_unique<vmas::Skeletonizer>(
        vmas::build_shape(vmas::read_surface(data_path()), vmas::ShapeOptions{}), options);
    made->run();
    return made;
  }();
  return skeletonizer.get();
}

void BM_Step(benchmark::State& state) {
  vmas::Skeletonizer* skeletonizer = settled_skeletonizer();
  if (!skeletonizer) {
    state.SkipWithError(("shared data not found: " + data_path()).c_str());
    return;
  }
  omp_set_num_threads(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(skeletonizer->step());
  state.counters["vertices"] = skeletonizer->shape().size();
  state.counters["spheres"] = static_cast<double>(skeletonizer->spheres().size());
}

// What a key press costs before the page can show it: remove a sphere, add one at a vertex
// (a split under the mouse), and the step that re-settles both.
void BM_EditThenStep(benchmark::State& state) {
  vmas::Skeletonizer* skeletonizer = settled_skeletonizer();
  if (!skeletonizer) {
    state.SkipWithError(("shared data not found: " + data_path()).c_str());
    return;
  }
  omp_set_num_threads(static_cast<int>(state.range(0)));
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

}  // namespace

BENCHMARK_MAIN();
