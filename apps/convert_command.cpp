// `vmas convert`: rewrites a shape or a medial mesh in another format, through the library's own
// readers and writers (so that scripts need no reader of their own).
#include <boost/program_options.hpp>
#include <cstddef>
#include <iostream>
#include <string>

#include "commands.hpp"
#include "vmas/normals.hpp"
#include "vmas/io.hpp"

namespace po = boost::program_options;

namespace vmas::cli {
namespace {

const char* kDescription =
    "usage: vmas convert INPUT OUTPUT [--medial] [-q]\n"
    "\n"
    "Reads the shape INPUT (.off .ply .obj .xyz .txt .pcd) as vmas does, i.e. cleaned (NaN\n"
    "points dropped, duplicates merged, degenerate faces and unused vertices removed), and\n"
    "writes it to OUTPUT (.off with exact coordinates, .ply binary float, .xyz). With --medial,\n"
    "INPUT and OUTPUT are medial meshes (.ply or .ma). Exit codes: 0 success, 1 run error\n"
    "(unreadable input, write failure), 2 usage error.\n"
    "\n"
    "options";

}  // namespace

int convert_command(int argc, const char* const* argv) {
  std::string input, output;
  po::options_description visible(kDescription);
  visible.add_options()("help,h", "print this help")(
      "medial", "INPUT and OUTPUT are medial meshes (.ply or .ma)")("quiet,q",
                                                                    "print nothing but errors");
  po::options_description hidden;
  hidden.add_options()("input", po::value(&input))("output", po::value(&output));
  po::positional_options_description positional;
  positional.add("input", 1).add("output", 1);
  po::variables_map vm = parse_arguments(argc, argv, visible, hidden, positional);
  if (vm.count("help")) {
    std::cout << visible << "\nexample: vmas convert scan.pcd scan.off\n";
    return 0;
  }
  po::notify(vm);
  if (input.empty() || output.empty()) throw po::error("missing INPUT or OUTPUT");
  check_distinct_files_option({input}, {output});

  std::string summary;
  if (vm.count("medial")) {
    check_output_option(output, check_medial_mesh_output);
    const MedialMesh medial = read_medial_mesh(input);
    write_medial_mesh(output, medial);
    summary = std::to_string(medial.spheres.size()) + " spheres, " +
              std::to_string(medial.edges.size()) + " edges, " +
              std::to_string(medial.faces.size()) + " faces";
  } else {
    check_output_option(output, check_surface_output);
    CleanReport report;
    SurfaceInput shape = read_surface(input, &report);
    // Points the file gave no valid normal keep their place: written with an estimated one.
    if (report.missing_normals > 0) fill_missing_normals(shape.points, shape.normals, {});
    write_surface(output, shape);
    summary = std::to_string(shape.points.size()) + " points" +
              (shape.is_mesh() ? ", " + std::to_string(shape.faces.size()) + " faces" : "") +
              (shape.has_normals() ? ", with normals" : "");
    const std::size_t removed =
        report.non_finite_points + report.duplicate_points + report.unused_points;
    if (report.total() > 0)
      summary += " (cleaning removed " + std::to_string(removed) + " points, " +
                 std::to_string(report.degenerate_faces) + " faces)";
  }
  if (!vm.count("quiet")) std::cout << input << " -> " << output << ": " << summary << "\n";
  return 0;
}

}  // namespace vmas::cli
