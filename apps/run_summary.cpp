// The figures of a run as `vmas skeletonize --json` prints them.
#include "run_summary.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace vmas::cli {
namespace {

// Lengths in % of the diagonal to two decimals; seconds to the millisecond.
double percent_of(double length, double diagonal) {
  return diagonal > 0.0 ? std::round(1e4 * length / diagonal) / 1e2 : 0.0;
}
double rounded(double seconds) { return std::round(seconds * 1e3) / 1e3; }

}  // namespace

std::string json_line(const json& summary) {
  return summary.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string figure_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

double significant(double value) { return std::strtod(figure_text(value).c_str(), nullptr); }

json eval_figures(const EvalResult& result, const OpeningReach* openings) {
  json figures = {
      {"diagonal", significant(result.diagonal)},
      {"hausdorff_percent", significant(result.percent(result.hausdorff))},
      {"surface_to_medial_max_percent", significant(result.percent(result.surface_to_medial_max))},
      {"surface_to_medial_mean_percent",
       significant(result.percent(result.surface_to_medial_mean))},
      {"medial_to_surface_max_percent", significant(result.percent(result.medial_to_surface_max))},
      {"medial_to_surface_mean_percent",
       significant(result.percent(result.medial_to_surface_mean))}};
  if (openings) {
    figures["openings"] = openings->openings;
    figures["reach_percent"] = significant(result.percent(openings->reach));
  }
  figures["surface_samples"] = result.surface_sample_count;
  figures["boundary_samples"] = result.boundary_sample_count;
  return figures;
}

json topology_summary(const MedialTopology& medial, const SurfaceGenus& input) {
  return {{"input_genus", input.known ? json(input.genus) : json()},
          {"input_genus_unknown", input.known ? std::string() : input.why},
          {"b0", medial.components},
          {"b1", medial.loops},
          {"b2", medial.cavities},
          {"duplicate_triangles", medial.duplicate_triangles}};
}

std::string topology_line(const json& topology) {
  const auto counted = [](int count, const char* one, const char* many) {
    return std::to_string(count) + " " + (count == 1 ? one : many);
  };
  std::string line = "topology: the skeleton has " +
                     counted(topology["b0"].get<int>(), "piece", "pieces") + ", " +
                     counted(topology["b1"].get<int>(), "loop", "loops") + ", " +
                     counted(topology["b2"].get<int>(), "cavity", "cavities") + "; the shape: ";
  const json& genus = topology["input_genus"];
  if (!genus.is_array())
    return line + "genus unknown (" + topology["input_genus_unknown"].get<std::string>() + ")";
  line += counted(static_cast<int>(genus.size()), "piece", "pieces") + " of genus ";
  for (std::size_t i = 0; i < genus.size(); ++i)
    line += (i ? ", " : "") + std::to_string(genus[i].get<int>());
  return line;
}

json edit_topology_summary(const EditSnapshot& snapshot) {
  json topology = topology_summary(snapshot.topology, snapshot.input_genus);
  topology["extra_loops"] = snapshot.extra_loops;
  json& cavity_triangles = topology["cavity_triangles"] = json::array();
  for (int t : snapshot.topology.closing_triangles) cavity_triangles.push_back(snapshot.mesh.faces[t]);
  return topology;
}

// The `noise` object: what was measured, and the smoothing and its check.
json noise_summary(const PrepareReport& prepared, const SmoothingCheck& check) {
  return {{"measured", prepared.noise.sigma > 0.0 || prepared.noise.spacing > 0.0},
          {"deviation_percent", percent_of(prepared.noise.sigma, prepared.diagonal)},
          {"spacing_percent", percent_of(prepared.noise.spacing, prepared.diagonal)},
          {"smoothed", prepared.smoothed()},
          {"from_facets", prepared.noise_from_facets},
          {"mls_radius_percent", percent_of(prepared.mls_radius, prepared.diagonal)},
          {"mesh_smoothing_steps", prepared.mesh_smoothing_steps},
          {"residual_percent", percent_of(prepared.residual_noise, prepared.diagonal)},
          {"thinned_points",
           prepared.smoothed_thinned_from > 0 ? prepared.kept.size() : std::size_t{0}},
          {"thinned_voxel_percent", percent_of(prepared.smoothed_voxel, prepared.diagonal)},
          {"normals_turned", prepared.normals_turned},
          {"smoothing_check",
           {{"made", check.made},
            {"smoothing_kept", check.smoothing_kept},
            {"smoothed_reach_percent", percent_of(check.smoothed_reach, 1.0)},
            {"unsmoothed_reach_percent", percent_of(check.unsmoothed_reach, 1.0)},
            {"smoothed_cover_percent", percent_of(check.smoothed_cover, 1.0)},
            {"unsmoothed_cover_percent", percent_of(check.unsmoothed_cover, 1.0)}}}};
}

// The `seconds` object: by stage, and in all.
json seconds_summary(const Timings& t, const RunContext& run) {
  return {{"read", rounded(run.read_seconds)},
          {"clean", rounded(t.clean)},
          {"prepare", rounded(t.prepare)},
          {"shape", rounded(t.shape)},
          {"partition", rounded(t.partition)},
          {"update", rounded(t.update)},
          {"projection", rounded(t.projection)},
          {"split", rounded(t.split)},
          {"refine", rounded(t.refine)},
          {"connectivity", rounded(t.connectivity)},
          {"other_starts", rounded(t.other_starts)},
          {"smoothing_check", rounded(t.smoothing_check)},
          {"write", rounded(run.write_seconds)},
          {"total", rounded(run.read_seconds + t.total + run.write_seconds)}};
}

json run_summary(const Result& result, const RunContext& run) {
  const InputSize& input = run.input_size;
  const PrepareReport& prepared = result.prepare;
  const double diagonal = prepared.diagonal * prepared.frame.scale;
  const std::string normals = input.faces > 0              ? "from faces"
                              : prepared.normals_estimated ? "estimated"
                              : prepared.normals_oriented  ? "re-oriented"
                                                           : "given";
  const RefineReport& refine = result.refine;
  json starts = json::array();
  for (double error : result.start_errors) starts.push_back(std::round(error * 1e5) / 1e3);
  json skeleton_topology = topology_summary(result.topology, result.input_genus);
  skeleton_topology["loops_filled"] = result.loops_filled;
  skeleton_topology["loops_opened"] = result.loops_opened;
  json summary = {{"vmas", version()}};
  if (!run.input.empty()) summary["input"] = run.input;
  if (!run.output.empty()) summary["output"] = run.output;
  summary.update(
      {{"points", input.points},
       {"faces", input.faces},
       {"normals", normals},
       {"cleaned",
        {{"non_finite_points", result.clean.non_finite_points},
         {"missing_normals", result.clean.missing_normals},
         {"duplicate_points", result.clean.duplicate_points},
         {"degenerate_faces", result.clean.degenerate_faces},
         {"unused_vertices", result.clean.unused_points}}},
       {"thinning",
        {{"applied", prepared.thinned_from > 0},
         {"points", prepared.kept.size() + prepared.outliers},
         {"voxel_percent", percent_of(prepared.voxel, prepared.diagonal)}}},
       {"mesh_sampling",
        {{"applied", prepared.mesh_sampled_from > 0},
         {"vertices_before", prepared.mesh_sampled_from},
         {"vertices", prepared.mesh_sampled_to},
         {"edge_limit_percent", percent_of(prepared.mesh_edge_limit, prepared.diagonal)}}},
       {"density",
        {{"given", prepared.density_given},
         {"min", prepared.density_low},
         {"max", prepared.density_high}}},
       {"outliers", prepared.outliers},
       {"stray_clusters",
        {{"count", prepared.stray_clusters}, {"points", prepared.stray_points.size()}}},
       {"noise", noise_summary(prepared, result.smoothing_check)},
       {"diagonal", diagonal},
       {"enclosure", std::round(result.enclosure * 100.0) / 100.0},
       {"holes",
        {{"count", prepared.holes.size()},
         {"widest_percent", percent_of(prepared.holes.empty() ? 0.0 : prepared.holes.front().width,
                                       prepared.diagonal)}}},
       {"components",
        {{"input", result.input_components}, {"skeleton", result.skeleton_components}}},
       {"topology", skeleton_topology},
       {"invalid_spheres",
        {{"checked", result.invalid_spheres.checked},
         {"outside", result.invalid_spheres.outside},
         {"radius_off", result.invalid_spheres.radius_off}}},
       {"measured_error_percent", std::round(result.measured_error * 1e5) / 1e3},
       {"starts",
        {{"kept", result.start_kept + 1},
         {"measured_error_percent", starts},
         {"density_weighted", result.start_errors_weighted}}},
       {"spheres", result.medial_mesh.spheres.size()},
       {"edges", result.medial_mesh.edges.size()},
       {"medial_faces", result.medial_mesh.faces.size()},
       {"iterations", result.summary.iterations},
       {"refine",
        {{"moves_tried", refine.tried},
         {"moves_kept", refine.kept},
         {"error_before_percent", percent_of(refine.error_before, prepared.diagonal)},
         {"error_after_percent", percent_of(refine.error_after, prepared.diagonal)}}},
       {"converged", result.summary.converged},
       {"stopped_by_max_iterations", result.summary.hit_max_iterations},
       {"total_error", result.summary.error}});
  json warnings = json::array();
  for (const Warning& w : result.warnings)
    warnings.push_back({{"code", w.code}, {"message", w.message}});
  summary["warnings"] = warnings;
  if (const EvalResult* eval = run.eval) summary["eval"] = eval_figures(*eval);
  summary["seconds"] = seconds_summary(result.seconds, run);
  return summary;
}

}  // namespace vmas::cli
