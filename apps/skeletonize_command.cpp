// `vmas skeletonize`: input shape → medial mesh (PLY or .ma), optionally per-point labels.
#include <unistd.h>

#include <algorithm>
#include <boost/program_options.hpp>
#include <chrono>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <string>

#include "commands.hpp"
#include "vmas/error.hpp"
#include "vmas/io.hpp"
#include "vmas/prepare.hpp"
#include "vmas/skeletonizer.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace po = boost::program_options;

namespace vmas::cli {
namespace {

using Clock = std::chrono::steady_clock;


double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Fails before any work is done when an output cannot possibly be written (a usage error).
void check_output_option(const std::string& path, void (*check)(const std::string&)) {
  try {
    check(path);
  } catch (const IoError& e) {
    throw InvalidOption(e.what());
  }
}

const char* kDescription =
    "usage: vmas skeletonize INPUT -o OUTPUT [--spheres N | --error E] [options]\n"
    "\n"
    "Computes a medial mesh (spheres, edges, triangles) of INPUT, a triangle mesh or point\n"
    "cloud (.off .ply .obj .xyz .txt .pcd), by variational medial axis sampling. OUTPUT is a\n"
    "PLY (vertex x y z radius, edge, face) or a .ma file (Q-MAT format).\n"
    "\n"
    "options";

// "auto", "off", or a deviation as a fraction of the diagonal ("0.005") or in percent ("0.5%").
PrepareOptions::Denoise parse_denoise(const std::string& text, double& sigma) {
  if (text == "auto") return PrepareOptions::Denoise::Auto;
  if (text == "off") return PrepareOptions::Denoise::Off;
  const bool percent = !text.empty() && text.back() == '%';
  const std::string number = percent ? text.substr(0, text.size() - 1) : text;
  std::size_t used = 0;
  try {
    sigma = std::stod(number, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != number.size())
    throw InvalidOption("--denoise must be auto, off or a noise deviation such as 0.005 or 0.5% "
                        "(got '" + text + "')");
  if (percent) sigma /= 100.0;
  return PrepareOptions::Denoise::Fixed;
}

std::string percent_of(double length, double diagonal) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2g %%", diagonal > 0.0 ? 100.0 * length / diagonal : 0.0);
  return text;
}

// Input index of every prepared point's label; -1 for points dropped on the way.
std::vector<int> labels_of_input(const std::vector<int>& labels, const std::vector<int>& kept,
                                 std::size_t input_size) {
  std::vector<int> result(input_size, -1);
  for (std::size_t i = 0; i < kept.size(); ++i) result[kept[i]] = labels[i];
  return result;
}

// Reads, skeletonizes and writes, printing the summary unless `quiet`.
void run_skeletonize(const std::string& input, const std::string& output,
                     const std::string& labels_path, SkeletonizerOptions options,
                     const ShapeOptions& shape_options, const PrepareOptions& prepare_options,
                     bool quiet) {
  const bool show_progress = !quiet && isatty(fileno(stderr));
  const auto start = Clock::now();
  CleanReport report;
  SurfaceInput surface = read_surface(input, &report);
  const std::size_t read_points = surface.points.size();
  const double read_time = seconds_since(start);
  if (!quiet) {
    std::cout << "input " << input << ": " << surface.points.size() << " points, "
              << (surface.is_mesh() ? std::to_string(surface.faces.size()) + " faces"
                                    : std::string("point cloud"))
              << (surface.has_normals() || surface.is_mesh() ? "" : ", no normals") << "\n";
    if (report.total() > 0)
      std::cout << "cleaned: removed " << report.non_finite_points << " non-finite points, "
                << report.duplicate_points << " duplicates, " << report.degenerate_faces
                << " degenerate faces, " << report.unused_points << " unused vertices\n";
  }
  const PrepareReport prepared = prepare_surface(surface, prepare_options);
  adapt_shrinking_ball(prepared, options.shrinking_ball);
  if (!quiet) {
    if (prepared.outliers > 0)
      std::cout << "outliers: removed " << prepared.outliers << " points\n";
    if (prepare_options.denoise != PrepareOptions::Denoise::Off)
      std::cout << "noise: ~" << percent_of(prepared.noise.sigma, prepared.diagonal)
                << " of the diagonal (point spacing "
                << percent_of(prepared.noise.spacing, prepared.diagonal) << ")"
                << (prepared.mls_radius > 0.0
                        ? "; smoothed (MLS radius " +
                              percent_of(prepared.mls_radius, prepared.diagonal) + ", left ~" +
                              percent_of(prepared.residual_noise, prepared.diagonal) + ")"
                        : std::string("; not smoothed"))
                << "\n";
    if (prepared.faces_dropped)
      std::cout << "faces: dropped (the smoothed vertices go on as a point cloud)\n";
    if (prepared.normals_estimated)
      std::cout << "normals: estimated and oriented (k=" << prepare_options.normals.k << ")\n";
    else if (prepared.normals_oriented)
      std::cout << "normals: given ones re-oriented (k=" << prepare_options.normals.k << ")\n";
  }
  const double prepare_time = prepared.seconds;
  if (!quiet)
    std::cout << "parameters: "
              << (options.target_spheres > 0 ? "spheres=" + std::to_string(options.target_spheres)
                                             : "error=" + std::to_string(options.error_threshold))
              << " lambda=" << options.lambda << " k=" << shape_options.k
              << " projection=" << (options.project ? "on" : "off")
              << " ball-tolerance=" << options.shrinking_ball.tolerance
#ifdef _OPENMP
              << " threads=" << omp_get_max_threads()
#endif
              << "\n";

  const auto shape_start = Clock::now();
  Skeletonizer skeletonizer(build_shape(surface, shape_options), options);
  const double shape_time = seconds_since(shape_start);
  const RunSummary summary = skeletonizer.run([&](const Progress& p) {
    if (show_progress)
      std::fprintf(stderr, "\riteration %d: %d spheres, error %.3e   ", p.iteration, p.spheres,
                   p.error);
  });
  if (show_progress) std::fprintf(stderr, "\n");
  // The count is a promise: a skeleton with fewer spheres is an error, not a result.
  if (options.target_spheres > 0 && summary.spheres < options.target_spheres)
    throw InvalidInput("cannot place " + std::to_string(options.target_spheres) + " spheres on " +
                       std::to_string(skeletonizer.shape().size()) + " usable points (placed " +
                       std::to_string(summary.spheres) + "); ask for fewer");
  // A single-view scan, an open mesh or faces that disagree in orientation have no inside, and
  // the skeleton of such data is no medial axis.
  const double enclosure = skeletonizer.projector().enclosure();
  if (!quiet)
    std::cout << "enclosure: winding number " << std::setprecision(2) << enclosure
              << std::setprecision(6) << " inside (1: closed surface)\n";
  if (enclosure < MedialProjector::kEnclosed)
    std::cerr << "vmas skeletonize: warning: " << input
              << " does not enclose a volume (winding number " << std::setprecision(2)
              << enclosure << std::setprecision(6) << " inside, 1 for a closed surface): open or "
              << "single-view scan, holes, or inconsistently oriented faces; the skeleton is "
                 "only an approximation there\n";
  const auto connectivity_start = Clock::now();
  const MedialMesh mesh = prepared.frame.to_input(skeletonizer.medial_mesh());
  const double connectivity_time = seconds_since(connectivity_start);
  const auto write_start = Clock::now();
  write_medial_mesh(output, mesh);
  if (!labels_path.empty())
    write_labels(labels_path, labels_of_input(skeletonizer.labels(), prepared.kept, read_points));
  const double write_time = seconds_since(write_start);

  if (!quiet) {
    const StageTimes& t = skeletonizer.times();
    std::cout << "result: " << mesh.spheres.size() << " spheres, " << mesh.edges.size()
              << " edges, " << mesh.faces.size() << " faces; " << summary.iterations
              << " iterations"
              << (summary.hit_max_iterations ? " (stopped by --max-iterations)"
                  : summary.converged        ? ""
                                             : " (error still changing: stopped after settling)")
              << ", total error " << summary.error << "\n"
              << "time (s): total " << seconds_since(start) << " = read " << read_time
              << ", prepare " << prepare_time << ", shape " << shape_time << ", partition "
              << t.partition << ", update " << t.update << ", projection " << t.projection
              << ", split " << t.split << ", connectivity " << connectivity_time << ", write "
              << write_time << "\n"
              << "wrote " << output << (labels_path.empty() ? "" : " and " + labels_path) << "\n";
  }
}

}  // namespace

int skeletonize_command(int argc, const char* const* argv) {
  const SkeletonizerOptions defaults;
  const ShapeOptions shape_defaults;
  const PrepareOptions prepare_defaults;
  std::string input, output, labels_path, denoise = "auto";
  SkeletonizerOptions options;
  ShapeOptions shape_options;
  PrepareOptions prepare_options;
  int threads = 0;
  po::options_description visible(kDescription);
  // clang-format off
  visible.add_options()
      ("help,h", "print this help")
      ("output,o", po::value(&output), "medial mesh to write (.ply or .ma)")
      ("spheres,n", po::value(&options.target_spheres),
       "number of medial spheres to produce (met exactly; default 100 when --error is absent)")
      ("error,e", po::value(&options.error_threshold),
       "instead of a count: split until every cluster's RMS error sqrt(E(C)) is below E "
       "(relative to the bounding-box diagonal, e.g. 0.005; scan noise sets a floor)")
      ("max-spheres", po::value(&options.max_spheres)->default_value(defaults.max_spheres),
       "with --error: never more spheres than this")
      ("lambda,l", po::value(&options.lambda)->default_value(defaults.lambda, "0.2"),
       "weight of the point-sphere term against the plane-sphere (SQEM) term")
      ("final-lambda", po::value(&options.final_lambda)->default_value(defaults.final_lambda, "0.01"),
       "lambda of the refits that end the run (spheres reach the shape's extremities)")
      ("final-rounds", po::value(&options.final_rounds)->default_value(defaults.final_rounds),
       "refits with --final-lambda after the optimisation (0: none)")
      ("k", po::value(&shape_options.k)->default_value(shape_defaults.k),
       "neighbours per point of a cloud's k-NN graph (connectivity, quadric diffusion)")
      ("normal-k", po::value(&prepare_options.normals.k)->default_value(prepare_defaults.normals.k),
       "neighbours used to estimate and orient normals of clouds that have none")
      ("estimate-normals", "estimate normals even if the file has them")
      ("denoise", po::value(&denoise)->default_value("auto"),
       "auto: measure the scan noise and, if there is any, remove outliers and smooth the "
       "points (moving least squares) before the run; off: take the points as they are; or the "
       "noise deviation itself, as a fraction of the diagonal (0.005) or in percent (0.5%)")
      ("orient-normals", "keep the file's normals but re-orient them consistently and outward "
       "(for normals with arbitrary signs, e.g. oriented towards a scanner)")
      ("labels", po::value(&labels_path), "also write the cluster of every input point (text)")
      ("no-projection", "skip the shrinking-ball correction (spheres may leave the medial axis)")
      ("max-iterations", po::value(&options.max_iterations)->default_value(defaults.max_iterations),
       "stop after this many partition/update steps")
      ("convergence", po::value(&options.convergence)->default_value(defaults.convergence, "0.0002"),
       "split (or stop) once the total error changes by less than this fraction per step")
      ("split-interval", po::value(&options.split_interval)->default_value(defaults.split_interval),
       "split at least every this many steps while spheres are missing")
      ("splits-per-round", po::value(&options.split.max_per_round)
           ->default_value(defaults.split.max_per_round),
       "with --spheres: at most this many spheres are added per split round (and at most 20 % of "
       "the count; --error grows by the 20 % alone)")
      ("denoise-angle", po::value(&options.shrinking_ball.denoise_angle_deg)
           ->default_value(defaults.shrinking_ball.denoise_angle_deg),
       "shrinking ball: ignore contacts that separate by less than this many degrees (noise); 0 "
       "disables it")
      ("ball-tolerance", po::value(&options.shrinking_ball.tolerance)
           ->default_value(defaults.shrinking_ball.tolerance, "1e-05"),
       "shrinking ball: samples this close inside the ball do not shrink it (fraction of the "
       "diagonal); raise it to about the noise level for noisy scans")
      ("threads", po::value(&threads)->default_value(0), "OpenMP threads (0: all cores)")
      ("quiet,q", "print nothing but errors");
  // clang-format on
  po::options_description hidden;
  hidden.add_options()("input", po::value(&input));
  po::options_description all;
  all.add(visible).add(hidden);
  po::positional_options_description positional;
  positional.add("input", 1);
  po::variables_map vm;
  po::store(po::command_line_parser(argc, argv).options(all).positional(positional).run(), vm);
  if (vm.count("help")) {
    std::cout
        << visible
        << "\nexample: vmas skeletonize clouds/bunny_merged_45k.xyz --spheres 60 -o bunny.ply\n";
    return 0;
  }
  po::notify(vm);
  if (input.empty()) throw po::error("missing INPUT");
  if (output.empty()) throw po::error("missing --output");
  if (vm.count("spheres") && vm.count("error"))
    throw po::error("give either --spheres or --error, not both");
  if (!vm.count("spheres") && !vm.count("error")) options.target_spheres = 100;
  if (vm.count("spheres") && options.target_spheres < 1)
    throw InvalidOption("--spheres must be at least 1 (got " +
                        std::to_string(options.target_spheres) + ")");
  if (vm.count("error") && !(options.error_threshold > 0.0))
    throw InvalidOption("--error must be positive");
  options.project = !vm.count("no-projection");
  prepare_options.denoise = parse_denoise(denoise, prepare_options.noise_sigma);
  prepare_options.estimate_normals = vm.count("estimate-normals") > 0;
  prepare_options.orient_normals = vm.count("orient-normals") > 0;
  set_threads(threads);
  options.validate();
  shape_options.validate();
  prepare_options.validate();
  check_output_option(output, check_medial_mesh_output);
  if (!labels_path.empty()) check_output_option(labels_path, check_output);
  const bool quiet = vm.count("quiet") > 0;

  // The stages do not know the file name; errors about the data should carry it.
  try {
    run_skeletonize(input, output, labels_path, options, shape_options, prepare_options, quiet);
  } catch (const InvalidInput& e) {
    throw InvalidInput(input + ": " + e.what());
  }
  return 0;
}

}  // namespace vmas::cli
