// `vmas eval`: reconstruction error of a medial mesh against the shape it approximates.
#include <boost/program_options.hpp>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.hpp"
#include "run_summary.hpp"
#include "standard_streams.hpp"
#include "vmas/error.hpp"
#include "vmas/eval.hpp"
#include "vmas/io.hpp"
#include "vmas/vmas.hpp"

namespace po = boost::program_options;

namespace vmas::cli {
namespace {

const char* kDescription =
    "usage: vmas eval SHAPE MEDIAL [--json] [--samples N] [--seed S] [--errors FILE]\n"
    "                 [--medial-errors FILE] [--input-format EXT]\n"
    "\n"
    "Two-sided Hausdorff distance between SHAPE (a mesh or point cloud) and the reconstruction\n"
    "of MEDIAL (.ply or .ma): the union of its spheres, of the round cones of its edges and of\n"
    "the slabs of its triangles, as in the paper's Table 1. Reported in % of the bounding-box\n"
    "diagonal of SHAPE. SHAPE or MEDIAL can be - (standard input, in --input-format).\n"
    "Against a point cloud, also its openings (holes) and how far the reconstruction reaches\n"
    "past them, and how far from it the points lie at most (coverage).\n"
    "\n"
    "options";

// The files of --errors and --medial-errors (each when its path is given).
std::vector<OutputFile> error_files(const EvalResult& result, const std::string& errors_path,
                                    const std::string& medial_errors_path) {
  std::vector<OutputFile> files;
  if (!errors_path.empty()) {
    std::string text;
    char line[32];
    for (double e : result.vertex_error) {
      std::snprintf(line, sizeof line, "%.9g\n", e);
      text += line;
    }
    files.push_back({errors_path, std::move(text)});
  }
  if (!medial_errors_path.empty()) {
    std::string text = "# diagonal " + figure_text(result.diagonal) + " hausdorff " +
                       figure_text(result.hausdorff) + " surface_to_medial_max " +
                       figure_text(result.surface_to_medial_max) + " surface_to_medial_mean " +
                       figure_text(result.surface_to_medial_mean) + " medial_to_surface_max " +
                       figure_text(result.medial_to_surface_max) + " medial_to_surface_mean " +
                       figure_text(result.medial_to_surface_mean) + "\n# x y z distance\n";
    char line[128];
    for (std::size_t i = 0; i < result.boundary_samples.size(); ++i) {
      const Vec3& p = result.boundary_samples[i];
      std::snprintf(line, sizeof line, "%.9g %.9g %.9g %.9g\n", p.x(), p.y(), p.z(),
                    result.boundary_error[i]);
      text += line;
    }
    files.push_back({medial_errors_path, std::move(text)});
  }
  return files;
}

// The summary for people, but its time.
void print_evaluation(const std::string& shape_path, const SurfaceInput& shape,
                      const std::string& medial_path, const MedialMesh& medial,
                      const EvalResult& result, const OpeningReach& openings,
                      const json& topology) {
  std::cout << "shape " << shape_path << ": " << shape.points.size() << " points"
            << (shape.is_mesh() ? ", " + std::to_string(shape.faces.size()) + " faces" : "")
            << "\nmedial " << medial_path << ": " << medial.spheres.size() << " spheres, "
            << medial.edges.size() << " edges, " << medial.faces.size() << " faces\n"
            << "epsilon (two-sided Hausdorff): " << figure_text(result.percent(result.hausdorff))
            << " % of the diagonal (" << figure_text(result.diagonal) << ")\n"
            << "surface -> medial: max "
            << figure_text(result.percent(result.surface_to_medial_max)) << " %, mean "
            << figure_text(result.percent(result.surface_to_medial_mean)) << " % ("
            << result.surface_sample_count << " samples)\n"
            << "medial -> surface: max "
            << figure_text(result.percent(result.medial_to_surface_max)) << " %, mean "
            << figure_text(result.percent(result.medial_to_surface_mean)) << " % ("
            << result.boundary_sample_count << " samples)\n";
  std::cout << topology_line(topology) << "\n";
  if (!shape.is_mesh())
    std::cout << "coverage: every point within "
              << figure_text(result.percent(result.surface_to_medial_max))
              << " % of the reconstruction; " << openings.openings << " opening"
              << (openings.openings == 1 ? "" : "s")
              << (openings.openings > 0
                      ? ", reached past by " + figure_text(result.percent(openings.reach)) + " %"
                      : std::string())
              << "\n";
}

// The summary as JSON: the fields of docs/json.md.
json eval_summary(const std::string& shape_path, const std::string& medial_path,
                  const MedialMesh& medial, const EvalResult& result, const OpeningReach& openings,
                  const json& topology, double seconds) {
  json summary = {{"vmas", version()},
                  {"shape", shape_path},
                  {"medial", medial_path},
                  {"spheres", medial.spheres.size()},
                  {"edges", medial.edges.size()},
                  {"faces", medial.faces.size()}};
  summary.update(eval_figures(result, &openings));
  summary["topology"] = topology;
  summary["seconds"] = significant(seconds);
  return summary;
}

}  // namespace

int eval_command(int argc, const char* const* argv) {
  const EvalOptions defaults;
  EvalOptions options;
  std::string shape_path, medial_path, errors_path, medial_errors_path, input_format;
  int threads = 0;
  po::options_description visible(kDescription);
  // clang-format off
  visible.add_options()
      ("help,h", "print this help")
      ("json", "print one JSON object instead of the summary")
      ("samples", po::value(&options.surface_samples)->default_value(defaults.surface_samples),
       "random surface samples added to the vertices of a mesh (-1: as many as vertices)")
      ("seed", po::value(&options.seed)->default_value(defaults.seed),
       "seed of the random surface samples")
      ("spacing", po::value(&options.boundary_spacing)
           ->default_value(defaults.boundary_spacing, figure_text(defaults.boundary_spacing)),
       "distance between samples on the primitives' boundaries (fraction of the diagonal)")
      ("errors", po::value(&errors_path),
       "write the surface-to-medial distance of every input point to FILE, one per line")
      ("medial-errors", po::value(&medial_errors_path),
       "write the medial-to-surface distance of every visible sample on the reconstruction's "
       "boundary to FILE, one 'x y z distance' line each, after '#' lines giving the summary")
      ("input-format", po::value(&input_format),
       "the format of SHAPE or MEDIAL given as - (standard input): off, ply, xyz, ... or ma")
      ("threads", po::value(&threads)->default_value(0), "OpenMP threads (0: all cores)");
  // clang-format on
  po::options_description hidden;
  hidden.add_options()("shape", po::value(&shape_path))("medial", po::value(&medial_path));
  po::positional_options_description positional;
  positional.add("shape", 1).add("medial", 1);
  po::variables_map vm = parse_arguments(argc, argv, visible, hidden, positional);
  if (vm.count("help")) {
    std::cout << visible
              << "\nexample: vmas eval armadillo.off armadillo.ply --errors armadillo_err.txt"
                 " --medial-errors armadillo_medial_err.txt\n";
    return 0;
  }
  po::notify(vm);
  if (shape_path.empty() || medial_path.empty()) throw po::error("missing SHAPE or MEDIAL");
  set_threads(threads);
  options.validate();

  const auto start = std::chrono::steady_clock::now();
  if (is_standard_stream(errors_path) || is_standard_stream(medial_errors_path))
    throw po::error("--errors and --medial-errors need a file (- is not supported)");
  if (!errors_path.empty()) check_output_option(errors_path, check_output);
  if (!medial_errors_path.empty()) check_output_option(medial_errors_path, check_output);
  check_standard_input({shape_path, medial_path}, input_format);
  check_distinct_files_option({shape_path, medial_path}, {errors_path, medial_errors_path});

  SurfaceInput shape;
  with_input_file(shape_path, input_format,
                  [&](const std::string& path) { shape = read_surface(path); });
  MedialMesh medial;
  with_input_file(medial_path, input_format,
                  [&](const std::string& path) { medial = read_medial_mesh(path); });
  const EvalResult result = evaluate(shape, medial, options);
  // A cloud may be open: how the reconstruction covers it and meets its openings.
  const OpeningReach openings = opening_reach(shape, result);
  const json topology = topology_summary(
      medial_topology(medial),
      surface_genus(shape, shape.is_mesh() ? mesh_defects(shape.faces) : MeshDefects{}));
  const std::vector<OutputFile> files = error_files(result, errors_path, medial_errors_path);
  if (!files.empty()) write_files_atomically(files);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  if (vm.count("json")) {
    std::cout << json_line(eval_summary(shape_path, medial_path, medial, result, openings, topology,
                                        seconds))
              << "\n";
    return 0;
  }
  print_evaluation(shape_path, shape, medial_path, medial, result, openings, topology);
  std::cout << "time: " << figure_text(seconds) << " s"
            << (errors_path.empty() ? "" : "; wrote " + errors_path)
            << (medial_errors_path.empty() ? "" : "; wrote " + medial_errors_path) << "\n";
  return 0;
}

}  // namespace vmas::cli
