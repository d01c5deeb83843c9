// The options of a run, shared by `vmas skeletonize` and `vmas edit`: everything in
// vmas::Options, spelled as on the command line.
#include <filesystem>
#include <string>
#include <iterator>
#include <vector>

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

// clang-format off
const RunOption kRunOptions[] = {
    {"spheres,n", "run.target.spheres", ">= 1",
     [](RunOptionValues& v, const Options&) -> po::value_semantic* {
       return po::value(&v.options.run.target.spheres); },
     "number of medial spheres to produce (met exactly, at most the number of usable points; "
     "default 100 when --error is absent)"},
    {"error,e", "run.target.error", "(0, 1)",
     [](RunOptionValues& v, const Options&) -> po::value_semantic* {
       return po::value(&v.options.run.target.error); },
     "instead of a count: split until every cluster's RMS error sqrt(E(C)) is below E "
     "(relative to the bounding-box diagonal, e.g. 0.005; scan noise sets a floor)"},
    {"max-spheres", "run.max_spheres", ">= 1",
     [](RunOptionValues& v, const Options& d) -> po::value_semantic* {
       return po::value(&v.options.run.max_spheres)->default_value(d.run.max_spheres); },
     "with --error: never more spheres than this, nor than usable points (also the largest "
     "--spheres)"},
    {"lambda,l", "run.lambda", "[0, 1e6]",
     [](RunOptionValues& v, const Options& d) -> po::value_semantic* {
       return po::value(&v.options.run.lambda)->default_value(d.run.lambda, "0.2"); },
     "weight of the point-sphere term against the plane-sphere (SQEM) term"},
    {"final-lambda", "run.final_lambda", "[0, 1e6]",
     [](RunOptionValues& v, const Options& d) -> po::value_semantic* {
       return po::value(&v.options.run.final_lambda)->default_value(d.run.final_lambda, "0.01"); },
     "lambda of the refits that end the run (spheres reach the shape's extremities)"},
    {"final-rounds", "run.final_rounds", "[0, 100]",
     [](RunOptionValues& v, const Options& d) -> po::value_semantic* {
       return po::value(&v.options.run.final_rounds)->default_value(d.run.final_rounds); },
     "refits with --final-lambda after the optimisation (0: none)"},
    {"refine-moves", "refine.max_moves", "[0, 1000]",
     [](RunOptionValues& v, const Options& d) -> po::value_semantic* {
       return po::value(&v.options.refine.max_moves)->default_value(d.refine.max_moves); },
     "after the run, up to this many moves of a sphere to where the reconstruction error "
     "(two-sided Hausdorff) is largest, each kept only if the measured error drops (0: off)"},
    {"refine-min-gain", "refine.min_gain", "[0, 1)",
     [](RunOptionValues& v, const Options& d) -> po::value_semantic* {
       return po::value(&v.options.refine.min_gain)->default_value(d.refine.min_gain, "0.01"); },
     "stop refining after two moves in a row that lowered the error by less than this fraction"},
    {"k", "shape.k", "[3, 100]",
     [](RunOptionValues& v, const Options& d) -> po::value_semantic* {
       return po::value(&v.options.shape.k)->default_value(d.shape.k); },
     "neighbours per point of a cloud's k-NN graph (connectivity, quadric diffusion)"},
    {"normal-k", "prepare.normals.k", "[3, 200]",
     [](RunOptionValues& v, const Options& d) -> po::value_semantic* {
       return po::value(&v.options.prepare.normals.k)->default_value(d.prepare.normals.k); },
     "neighbours used to estimate and orient normals of clouds that have none"},
    // How the input is prepared: thinning, normals, strays, mesh sampling, density, noise.
    {"max-points", "prepare.max_points", "0 | >= 1000",
     [](RunOptionValues& v, const Options& d) -> po::value_semantic* {
       return po::value(&v.options.prepare.max_points)->default_value(d.prepare.max_points); },
     "a cloud with more points is thinned to about this many, one per voxel, for the run; "
     "every point still gets a label (0: every point takes part)"},
    {"estimate-normals", "prepare.estimate_normals", "", nullptr,
     "estimate normals even if the file has them"},
    {"keep-strays", "prepare.remove_stray_clusters", "", nullptr,
     "keep groups of points apart from the object (stray clusters of at most 1 % of the points, "
     "several spacings from the rest), which are otherwise removed"},
    {"no-mesh-sampling", "prepare.sample_coarse_meshes", "", nullptr,
     "keep a coarse mesh's vertices as they are; by default a mesh whose vertices are too sparse "
     "for the method (long, thin faces) has its faces sampled"},
    {"density", "", "",
     [](RunOptionValues& v, const Options&) -> po::value_semantic* {
       return po::value(&v.density.file_or_rule); },
     "where the skeleton should be finer: a text file of one value >= 0 per input point, in the "
     "input's order, or a rule: curvature (1 where flattest, up to 4 at the 5 % most curved "
     "points) or distance-to:X,Y,Z,R[,D] (D, 4 unless given, within R of X,Y,Z; 1 elsewhere). "
     "With --spheres the spheres gather where it is high (4: about 4x the spheres per area of 1; "
     "0: as few as the budget allows); with --error the threshold there is divided by it"},
    {"density-field", "", "",
     [](RunOptionValues& v, const Options&) -> po::value_semantic* {
       return po::value(&v.density.field); },
     "the density from the input itself: a PLY vertex property or PCD field of this name, or the "
     "last column of an .xyz of 4 or 7 columns"},
    {"denoise", "prepare.noise_sigma", "auto | off | [0, 0.5)",
     [](RunOptionValues& v, const Options&) -> po::value_semantic* {
       return po::value(&v.denoise)->default_value("auto"); },
     "auto: measure the scan noise and, if there is any, remove outliers and smooth the points "
     "(moving least squares) before the run; off: take the points as they are; or the noise "
     "deviation itself, as a fraction of the diagonal (0.005) or in percent (0.5%)"},
    {"orient-normals", "prepare.orient_normals", "", nullptr,
     "orient the file's normals consistently and outward instead of keeping their signs (for "
     "normals with arbitrary signs, e.g. oriented towards a scanner)"},
    {"no-projection", "run.project", "", nullptr,
     "skip the shrinking-ball correction (spheres may leave the medial axis)"},
    {"keep-cavities", "run.open_cavities", "", nullptr,
     "keep the triangles that close cavities of the skeleton (closed pockets of triangles that "
     "the medial axis of a solid never has), which are otherwise left out"},
    {"keep-loops", "loops_to_genus", "", nullptr,
     "keep the skeleton's loops as cluster adjacency makes them; by default a closed mesh's "
     "skeleton gets as many as the mesh's genus: extra ones (rings of spheres around a tube) "
     "filled with triangles, missing ones opened"},
    {"no-coarse-start", "run.coarse_start", "", nullptr,
     "with --spheres: grow the spheres on the whole shape from the start instead of on a "
     "coarsened copy (slower)"},
    {"max-iterations", "run.max_iterations", ">= 1",
     [](RunOptionValues& v, const Options& d) -> po::value_semantic* {
       return po::value(&v.options.run.max_iterations)->default_value(d.run.max_iterations); },
     "stop after this many partition/update steps"},
    {"convergence", "run.convergence", "[0, 1)",
     [](RunOptionValues& v, const Options& d) -> po::value_semantic* {
       return po::value(&v.options.run.convergence)->default_value(d.run.convergence, "0.0002"); },
     "split (or stop) once the total error changes by less than this fraction per step"},
    {"split-interval", "run.split_interval", ">= 1",
     [](RunOptionValues& v, const Options& d) -> po::value_semantic* {
       return po::value(&v.options.run.split_interval)->default_value(d.run.split_interval); },
     "split at least every this many steps while spheres are missing"},
    {"splits-per-round", "run.split.max_per_round", ">= 1",
     [](RunOptionValues& v, const Options& d) -> po::value_semantic* {
       return po::value(&v.options.run.split.max_per_round)
           ->default_value(d.run.split.max_per_round); },
     "with --spheres: at most this many spheres are added per split round, or 5 % of the count "
     "when that is more (and at most 20 % of the count; --error grows by the 20 % alone)"},
    {"denoise-angle", "run.shrinking_ball.denoise_angle_deg", "[0, 180)",
     [](RunOptionValues& v, const Options& d) -> po::value_semantic* {
       return po::value(&v.options.run.shrinking_ball.denoise_angle_deg)
           ->default_value(d.run.shrinking_ball.denoise_angle_deg); },
     "shrinking ball: ignore contacts that separate by less than this many degrees (noise); 0 "
     "disables it"},
    {"ball-tolerance", "run.shrinking_ball.tolerance", "[0, 0.1)",
     [](RunOptionValues& v, const Options& d) -> po::value_semantic* {
       return po::value(&v.options.run.shrinking_ball.tolerance)
           ->default_value(d.run.shrinking_ball.tolerance, "1e-05"); },
     "shrinking ball: samples this close inside the ball do not shrink it (fraction of the "
     "diagonal); raised automatically for smoothed scans"},
    {"starts", "starts", "[1, 8]",
     [](RunOptionValues& v, const Options& d) -> po::value_semantic* {
       return po::value(&v.options.starts)->default_value(d.starts); },
     "optimisations, each from the shape's own frame turned differently (results do not depend "
     "on how the input is placed); the one with the least measured error is kept, unless its "
     "skeleton has more pieces than the input (1: less time)"},
    {"threads", "threads", ">= 0",
     [](RunOptionValues& v, const Options&) -> po::value_semantic* {
       return po::value(&v.options.threads)->default_value(0); },
     "OpenMP threads (0: all cores)"},
};
// clang-format on

// The long name of a row's flag ("lambda,l": "lambda").
std::string long_name(const RunOption& row) {
  const std::string flag = row.flag;
  return flag.substr(0, flag.find(','));
}

}  // namespace

std::string flag_of(const std::string& option) {
  for (const RunOption& row : kRunOptions)
    if (*row.field != '\0' && option == row.field) return long_name(row);
  return option;
}

const std::vector<RunOption>& run_option_table() {
  static const std::vector<RunOption> table(std::begin(kRunOptions), std::end(kRunOptions));
  return table;
}

void add_run_options(po::options_description& visible, RunOptionValues& values) {
  const Options defaults;
  for (const RunOption& row : kRunOptions) {
    if (row.value)
      visible.add_options()(row.flag, row.value(values, defaults), row.help);
    else
      visible.add_options()(row.flag, row.help);
  }
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
  options.loops_to_genus = vm.count("keep-loops") == 0;
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
    throw UsageError(e.what());
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
    throw UsageError(e.what());
  }
}

}  // namespace vmas::cli
