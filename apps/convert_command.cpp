// `vmas convert`: rewrites a shape or a medial mesh in another format, through the library's own
// readers and writers (so that scripts need no reader of their own).
#include <boost/program_options.hpp>
#include <cstddef>
#include <iostream>
#include <string>

#include "commands.hpp"
#include "standard_streams.hpp"
#include "vmas/io.hpp"
#include "vmas/vmas.hpp"

namespace po = boost::program_options;

namespace vmas::cli {
namespace {

const char* kDescription =
    "usage: vmas convert INPUT OUTPUT [--medial] [-q] [--input-format EXT] [--format EXT]\n"
    "\n"
    "Reads the shape INPUT (.off .ply .obj .xyz .txt .pcd) as vmas does, i.e. cleaned (NaN\n"
    "points dropped, duplicates merged, degenerate faces and unused vertices removed), and\n"
    "writes it to OUTPUT (.off with exact coordinates, .ply binary float, .xyz). With --medial,\n"
    "INPUT and OUTPUT are medial meshes (.ply or .ma). INPUT - reads standard input (in\n"
    "--input-format), OUTPUT - writes standard output (in --format; the summary then goes to\n"
    "standard error). Exit codes: 0 success, 1 run error (unreadable input, write failure),\n"
    "2 usage error.\n"
    "\n"
    "options";

}  // namespace

int convert_command(int argc, const char* const* argv) {
  std::string input, output, input_format, output_format;
  po::options_description visible(kDescription);
  // clang-format off
  visible.add_options()
      ("help,h", "print this help")
      ("medial", "INPUT and OUTPUT are medial meshes (.ply or .ma)")
      ("quiet,q", "print nothing but errors")
      ("input-format", po::value(&input_format),
       "the format of INPUT - (standard input): an extension vmas reads (off, ply, xyz, ...)")
      ("format", po::value(&output_format),
       "the format of OUTPUT - (standard output): ply, off or xyz (ply or ma with --medial)");
  // clang-format on
  po::options_description hidden;
  hidden.add_options()("input", po::value(&input))("output", po::value(&output));
  po::positional_options_description positional;
  positional.add("input", 1).add("output", 1);
  po::variables_map vm = parse_arguments(argc, argv, visible, hidden, positional);
  if (vm.count("help")) {
    std::cout << visible
              << "\nexamples:\n  vmas convert scan.pcd scan.off\n"
                 "  cat scan.xyz | vmas convert - - --input-format xyz --format ply > scan.ply\n";
    return 0;
  }
  po::notify(vm);
  if (input.empty() || output.empty()) throw po::error("missing INPUT or OUTPUT");
  check_standard_input({input}, input_format);
  const bool to_stdout = is_standard_stream(output);
  if (to_stdout && output_format.empty())
    throw po::error("OUTPUT - (standard output) needs --format");
  if (!to_stdout && !output_format.empty())
    throw po::error("--format is for OUTPUT - (standard output)");
  // Standard output is written as a file named like this would be.
  const std::string target = to_stdout ? "standard output." + output_format : output;
  const bool medial_meshes = vm.count("medial") > 0;
  if (to_stdout)
    check_output_option(target, medial_meshes ? check_medial_mesh_format : check_surface_format);
  else
    check_output_option(target, medial_meshes ? check_medial_mesh_output : check_surface_output);
  check_distinct_files_option({input}, {output});

  std::string summary, bytes;
  if (medial_meshes) {
    MedialMesh medial;
    with_input_file(input, input_format,
                    [&](const std::string& path) { medial = read_medial_mesh(path); });
    bytes = medial_mesh_file(target, medial);
    summary = std::to_string(medial.spheres.size()) + " spheres, " +
              std::to_string(medial.edges.size()) + " edges, " +
              std::to_string(medial.faces.size()) + " faces";
  } else {
    CleanReport report;
    SurfaceInput shape;
    with_input_file(input, input_format,
                    [&](const std::string& path) { shape = read_surface(path, &report); });
    // Points the file gave no valid normal keep their place: written with an estimated one.
    if (report.missing_normals > 0) fill_missing_normals(shape.points, shape.normals, NormalOptions{}.k);
    bytes = surface_file(target, shape);
    summary = std::to_string(shape.points.size()) + " points" +
              (shape.is_mesh() ? ", " + std::to_string(shape.faces.size()) + " faces" : "") +
              (shape.has_normals() ? ", with normals" : "");
    const std::size_t removed =
        report.non_finite_points + report.duplicate_points + report.unused_points;
    if (report.total() > 0)
      summary += " (cleaning removed " + std::to_string(removed) + " points, " +
                 std::to_string(report.degenerate_faces) + " faces)";
  }
  if (to_stdout)
    write_standard_output(bytes);
  else
    write_file_atomically(output, bytes);
  if (!vm.count("quiet"))
    (to_stdout ? std::cerr : std::cout) << input << " -> " << output << ": " << summary << "\n";
  return 0;
}

}  // namespace vmas::cli
