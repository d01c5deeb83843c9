// The options of a run, shared by `vmas skeletonize` and `vmas edit`: everything in
// vmas::Options, spelled as on the command line.
#include <filesystem>
#include <string>
#include <utility>

#include "commands.hpp"
#include "standard_streams.hpp"
#include "vmas/error.hpp"
#include "vmas/io.hpp"

namespace po = boost::program_options;

namespace vmas::cli {
namespace {

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
    throw InvalidOption("denoise",
                        "must be auto, off or a noise deviation such as 0.005 or 0.5% "
                        "(got '" +
                            text + "')");
  if (percent) sigma /= 100.0;
  return PrepareOptions::Denoise::Fixed;
}

// The field of vmas::Options each flag of add_run_options sets.
constexpr std::pair<const char*, const char*> kFieldFlags[] = {
    {"run.target.spheres", "spheres"},
    {"run.target.error", "error"},
    {"run.max_spheres", "max-spheres"},
    {"run.lambda", "lambda"},
    {"run.final_lambda", "final-lambda"},
    {"run.final_rounds", "final-rounds"},
    {"refine.max_moves", "refine-moves"},
    {"refine.min_gain", "refine-min-gain"},
    {"shape.k", "k"},
    {"prepare.normals.k", "normal-k"},
    {"prepare.max_points", "max-points"},
    {"prepare.noise_sigma", "denoise"},
    {"run.max_iterations", "max-iterations"},
    {"run.convergence", "convergence"},
    {"run.split_interval", "split-interval"},
    {"run.split.max_per_round", "splits-per-round"},
    {"run.shrinking_ball.denoise_angle_deg", "denoise-angle"},
    {"run.shrinking_ball.tolerance", "ball-tolerance"},
    {"starts", "starts"},
    {"threads", "threads"}};

// The options of add_run_options that say how the input is prepared (thinning, normals, strays,
// mesh sampling, density, noise), in their place in --help.
void add_preparation_options(po::options_description& visible, RunOptionValues& values) {
  const Options defaults;
  // clang-format off
  visible.add_options()
      ("max-points", po::value(&values.options.prepare.max_points)
           ->default_value(defaults.prepare.max_points),
       "a cloud with more points is thinned to about this many, one per voxel, for the run; "
       "every point still gets a label (0: every point takes part)")
      ("estimate-normals", "estimate normals even if the file has them")
      ("keep-strays", "keep groups of points apart from the object (stray clusters of at most 1 % "
       "of the points, several spacings from the rest), which are otherwise removed")
      ("no-mesh-sampling", "keep a coarse mesh's vertices as they are; by default a mesh whose "
       "vertices are too sparse for the method (long, thin faces) has its faces sampled")
      ("density", po::value(&values.density.file_or_rule),
       "where the skeleton should be finer: a text file of one value >= 0 per input point, in "
       "the input's order, or a rule: curvature (1 where flattest, up to 4 at the 5 % most "
       "curved points) or distance-to:X,Y,Z,R[,D] (D, 4 unless given, within R of X,Y,Z; 1 "
       "elsewhere). With --spheres the spheres gather where it is high (4: about 4x the spheres "
       "per area of 1; 0: as few as the budget allows); with --error the threshold there is "
       "divided by it")
      ("density-field", po::value(&values.density.field),
       "the density from the input itself: a PLY vertex property or PCD field of this name, or "
       "the last column of an .xyz of 4 or 7 columns")
      ("denoise", po::value(&values.denoise)->default_value("auto"),
       "auto: measure the scan noise and, if there is any, remove outliers and smooth the "
       "points (moving least squares) before the run; off: take the points as they are; or the "
       "noise deviation itself, as a fraction of the diagonal (0.005) or in percent (0.5%)")
      ("orient-normals", "orient the file's normals consistently and outward instead of keeping "
       "their signs (for normals with arbitrary signs, e.g. oriented towards a scanner)");
  // clang-format on
}

}  // namespace

std::string flag_of(const std::string& option) {
  for (const auto& [field, flag] : kFieldFlags)
    if (option == field) return flag;
  return option;
}

void add_run_options(po::options_description& visible, RunOptionValues& values) {
  const Options defaults;
  // clang-format off
  visible.add_options()
      ("spheres,n", po::value(&values.options.run.target.spheres),
       "number of medial spheres to produce (met exactly, at most the number of usable points; "
       "default 100 when --error is absent)")
      ("error,e", po::value(&values.options.run.target.error),
       "instead of a count: split until every cluster's RMS error sqrt(E(C)) is below E "
       "(relative to the bounding-box diagonal, e.g. 0.005; scan noise sets a floor)")
      ("max-spheres", po::value(&values.options.run.max_spheres)->default_value(defaults.run.max_spheres),
       "with --error: never more spheres than this, nor than usable points (also the largest "
       "--spheres)")
      ("lambda,l", po::value(&values.options.run.lambda)->default_value(defaults.run.lambda, "0.2"),
       "weight of the point-sphere term against the plane-sphere (SQEM) term")
      ("final-lambda", po::value(&values.options.run.final_lambda)
           ->default_value(defaults.run.final_lambda, "0.01"),
       "lambda of the refits that end the run (spheres reach the shape's extremities)")
      ("final-rounds", po::value(&values.options.run.final_rounds)
           ->default_value(defaults.run.final_rounds),
       "refits with --final-lambda after the optimisation (0: none)")
      ("refine-moves", po::value(&values.options.refine.max_moves)
           ->default_value(defaults.refine.max_moves),
       "after the run, up to this many moves of a sphere to where the reconstruction error "
       "(two-sided Hausdorff) is largest, each kept only if the measured error drops (0: off)")
      ("refine-min-gain", po::value(&values.options.refine.min_gain)
           ->default_value(defaults.refine.min_gain, "0.01"),
       "stop refining after two moves in a row that lowered the error by less than this fraction")
      ("k", po::value(&values.options.shape.k)->default_value(defaults.shape.k),
       "neighbours per point of a cloud's k-NN graph (connectivity, quadric diffusion)")
      ("normal-k", po::value(&values.options.prepare.normals.k)
           ->default_value(defaults.prepare.normals.k),
       "neighbours used to estimate and orient normals of clouds that have none");
  add_preparation_options(visible, values);
  visible.add_options()
      ("no-projection", "skip the shrinking-ball correction (spheres may leave the medial axis)")
      ("keep-cavities", "keep the triangles that close cavities of the skeleton (closed pockets "
       "of triangles that the medial axis of a solid never has), which are otherwise left out")
      ("no-coarse-start", "with --spheres: grow the spheres on the whole shape from the start "
       "instead of on a coarsened copy (slower)")
      ("max-iterations", po::value(&values.options.run.max_iterations)
           ->default_value(defaults.run.max_iterations),
       "stop after this many partition/update steps")
      ("convergence", po::value(&values.options.run.convergence)
           ->default_value(defaults.run.convergence, "0.0002"),
       "split (or stop) once the total error changes by less than this fraction per step")
      ("split-interval", po::value(&values.options.run.split_interval)
           ->default_value(defaults.run.split_interval),
       "split at least every this many steps while spheres are missing")
      ("splits-per-round", po::value(&values.options.run.split.max_per_round)
           ->default_value(defaults.run.split.max_per_round),
       "with --spheres: at most this many spheres are added per split round, or 5 % of the count "
       "when that is more (and at most 20 % of the count; --error grows by the 20 % alone)")
      ("denoise-angle", po::value(&values.options.run.shrinking_ball.denoise_angle_deg)
           ->default_value(defaults.run.shrinking_ball.denoise_angle_deg),
       "shrinking ball: ignore contacts that separate by less than this many degrees (noise); 0 "
       "disables it")
      ("ball-tolerance", po::value(&values.options.run.shrinking_ball.tolerance)
           ->default_value(defaults.run.shrinking_ball.tolerance, "1e-05"),
       "shrinking ball: samples this close inside the ball do not shrink it (fraction of the "
       "diagonal); raised automatically for smoothed scans")
      ("starts", po::value(&values.options.starts)->default_value(defaults.starts),
       "optimisations, each from the shape's own frame turned differently (results do not depend "
       "on how the input is placed); the one with the least measured error is kept, unless its "
       "skeleton has more pieces than the input (1: less time)")
      ("threads", po::value(&values.options.threads)->default_value(0), "OpenMP threads (0: all cores)");
  // clang-format on
}

void finish_run_options(const po::variables_map& vm, RunOptionValues& values) {
  Options& options = values.options;
  // 0 is the library's "not given": given on the command line it is out of range.
  const Target& target = options.run.target;
  if (vm.count("spheres") && target.spheres < 1)
    throw InvalidOption("spheres",
                        "must be at least 1 (got " + std::to_string(target.spheres) + ")");
  if (vm.count("error") && !(target.error > 0.0)) throw InvalidOption("error", "must be positive");
  options.run.project = !vm.count("no-projection");
  options.run.coarse_start = !vm.count("no-coarse-start");
  options.run.open_cavities = vm.count("keep-cavities") == 0;
  options.prepare.denoise = parse_denoise(values.denoise, options.prepare.noise_sigma);
  options.prepare.estimate_normals = vm.count("estimate-normals") > 0;
  options.prepare.remove_stray_clusters = vm.count("keep-strays") == 0;
  options.prepare.sample_coarse_meshes = vm.count("no-mesh-sampling") == 0;
  options.prepare.orient_normals = vm.count("orient-normals") > 0;
  options.validate();
  const DensitySource& density = values.density;
  if (vm.count("density") && density.file_or_rule.empty())
    throw InvalidOption("density", "needs a file or a rule");
  if (vm.count("density-field") && density.field.empty())
    throw InvalidOption("density-field", "needs a field name");
  if (!density.file_or_rule.empty() && !density.field.empty())
    throw InvalidOption("density", "cannot go with --density-field: give one");
  if (density.is_rule()) density_by_rule(SurfaceInput{}, density.file_or_rule);  // its syntax
}

bool DensitySource::is_rule() const { return is_density_rule(file_or_rule); }

std::vector<double> density_of(const std::string& file_or_rule, const SurfaceInput& surface) {
  if (is_density_rule(file_or_rule)) return density_by_rule(surface, file_or_rule);
  if (!std::filesystem::exists(file_or_rule))
    throw IoError(file_or_rule +
                  ": no such file (nor a density rule: curvature, "
                  "distance-to:X,Y,Z,R[,D])");
  return read_density(file_or_rule, surface.points.size());
}

SurfaceInput read_with_density(const std::string& path, const DensitySource& source) {
  SurfaceInput surface = read_surface_as_stored(path, source.field);
  std::string from = path + ": field '" + source.field + "'";
  if (!source.file_or_rule.empty()) {
    surface.density = density_of(source.file_or_rule, surface);
    from = source.file_or_rule;
  }
  try {
    if (!surface.density.empty()) check_density(surface.density, surface.points.size());
  } catch (const InvalidInput& e) {
    throw IoError(from + ": " + e.what());
  }
  return surface;
}

void check_output_option(const std::string& path, void (*check)(const std::string&)) {
  try {
    check(path);
  } catch (const IoError& e) {
    throw InvalidOption(e.what());
  }
}

void check_distinct_files_option(const std::vector<std::string>& inputs,
                                 const std::vector<std::string>& outputs) {
  const auto given = [](const std::vector<std::string>& paths) {
    std::vector<std::string> kept;
    for (const std::string& path : paths)
      if (!path.empty() && !is_standard_stream(path)) kept.push_back(path);
    return kept;
  };
  try {
    check_distinct_files(given(inputs), given(outputs));
  } catch (const IoError& e) {
    throw InvalidOption(e.what());
  }
}

}  // namespace vmas::cli
