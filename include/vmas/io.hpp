#pragma once
// Reading and cleaning shapes (meshes and point clouds), reading/writing medial meshes and labels.
// Every function throws IoError with a one-line message "PATH: problem" on failure; writers go
// through a temporary file and a rename, so no half-written output is ever left behind.
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "vmas/options.hpp"
#include "vmas/types.hpp"

#pragma GCC visibility push(default)  // what the public headers declare is exported

namespace vmas {

// Reads a mesh or a point cloud, chosen by extension (case-insensitive):
//   .off (OFF/NOFF/COFF, comments; a file with no faces is a cloud), .ply (ASCII or binary,
//   unknown elements and properties skipped), .obj (v/vn/f), .xyz/.txt (3 or 6 columns),
//   .pcd (ascii, binary, binary_compressed). Polygons are fan-triangulated.
// Normals: when some points carry one and others do not (NOFF or .xyz lines without normals),
// the missing ones are NaN (cleaning keeps those points, preparation estimates their normals);
// a NOFF file giving no normal at all loads as a plain cloud. OBJ `vn` lines are used only for clouds with one `vn` per `v`.
// Then cleans it (see clean_surface) and fills `report` if given. Throws IoError when the file is
// missing, unreadable, of unknown format, truncated or malformed, holds a coordinate that
// clean_surface rejects, or holds no usable point. Memory stays proportional to the file's size
// whatever its header announces.
SurfaceInput read_surface(const std::string& path, CleanReport* report = nullptr);

// Coordinates beyond this magnitude are rejected: squared distances would overflow.
constexpr double kMaxCoordinate = 1e150;

// Removes points with a NaN coordinate (scanners' "no point here"), merges exact duplicates
// (remapping faces), drops degenerate faces and, for meshes, unreferenced vertices. Normals are
// renormalised; a point whose normal is NaN, infinite or zero keeps its place with a NaN normal
// (preparation estimates it; when no point has one, the cloud has no normals). Faces with area
// below 1e-14 * (bbox diagonal)^2 are degenerate. Kept points stay in input order, each duplicate
// group keeping its first point (with the group's mean density). Throws InvalidInput if `normals`
// or `density` is neither empty nor one per point, or if a coordinate is infinite or beyond +-1e150
// (squared distances would overflow).
CleanReport clean_surface(SurfaceInput& surface);

// What makes a mesh a poor description of a solid (MeshDefects), counted over its edges. Vertex
// indices are those of a cleaned surface (never negative; InvalidInput otherwise).
MeshDefects mesh_defects(const std::vector<std::array<int, 3>>& faces);

// The same without cleaning: every point as stored (NaN ones included, so that indices match
// the file), for callers that clean later, such as vmas::skeletonize. Throws IoError for the
// reasons above except those of cleaning.
// With `density_field`, the points' density (SurfaceInput::density) from that PLY vertex property
// or PCD field, or from the last of 4 or 7 columns of an .xyz/.txt (IoError when it has none, or
// for .off and .obj, which hold none).
SurfaceInput read_surface_as_stored(const std::string& path, const std::string& density_field = {});

// A density (SurfaceInput::density) for an input of `points` points from a text file of one value
// per line, in the input's order ('#' comments and blank lines skipped). Throws IoError naming the
// file when it cannot be read, a line is not one number, or the count differs; the values
// themselves are check_density's (vmas/vmas.hpp).
std::vector<double> read_density(const std::string& path, std::size_t points);
// The same from a file's `text`, its errors naming `name`.
std::vector<double> parse_density(const std::string& name, const std::string& text,
                                  std::size_t points);

// Gives every point whose normal is missing (NaN or zero: a file that has normals for some
// points only) the normal of the plane through its k nearest neighbours (NormalOptions::k in
// vmas::skeletonize), with the sign its neighbours' given normals agree on; given normals are
// left as they are (vmas::skeletonize then gives their signs to the surface's normals:
// docs/cli.md, inputs). Throws InvalidInput for fewer than k + 1 points when a normal is missing.
void fill_missing_normals(const std::vector<Vec3>& points, std::vector<Vec3>& normals, int k);

// Writes a mesh or cloud: .ply (binary little-endian, float coordinates, with normals if
// present), .off (exact doubles; NOFF for clouds with normals, a mesh's normals are not written),
// .xyz (9 significant digits, with normals if present; faces are not written).
void write_surface(const std::string& path, const SurfaceInput& surface);
// The bytes write_surface would write to `path` (its format by the extension).
std::string surface_file(const std::string& path, const SurfaceInput& surface);

// Medial mesh: .ply (vertex x y z radius, edge vertex1 vertex2, face vertex_indices) or .ma
// (Q-MAT format: "nv ne nf", then v/e/f lines, 0-based). Spheres with a non-finite value or one
// beyond +-1e150 are an IoError.
MedialMesh read_medial_mesh(const std::string& path);
// Refuses (InvalidInput) what read_medial_mesh would refuse, and a negative radius.
void write_medial_mesh(const std::string& path, const MedialMesh& mesh);
// The bytes write_medial_mesh would write to `path` (its format by the extension).
std::string medial_mesh_file(const std::string& path, const MedialMesh& mesh);

// One cluster label per input point, one integer per line; labels_file gives the bytes.
void write_labels(const std::string& path, const std::vector<int>& labels);
std::string labels_file(const std::vector<int>& labels);

// Every writer lands its file like this: written to a temporary beside the target, then renamed
// over it (a symbolic link stays a link: its target is replaced, with the target's mode). The
// files of one call land together or not at all: on any failure, also SIGINT, SIGTERM or
// SIGHUP during the write (the signal then takes its course) and a file size limit ("file too
// large"), no temporary is left and every earlier file at those paths is intact. Throws IoError
// naming the path.
struct OutputFile {
  std::string path;
  std::string contents;
};
void write_files_atomically(const std::vector<OutputFile>& files);
void write_file_atomically(const std::string& path, const std::string& contents);

// Throw the IoError the matching writer would, without writing: for front ends that must fail
// before a long run. check_output: `path` (or its link's target) is a directory, a device, FIFO
// or socket, or its folder does not exist or cannot be written; check_medial_mesh_output also:
// the extension is not .ply or .ma.
void check_output(const std::string& path);
void check_medial_mesh_output(const std::string& path);
void check_surface_output(const std::string& path);  // also: not .ply, .off or .xyz
// The format alone (the extension), for outputs that are not files (standard output).
void check_medial_mesh_format(const std::string& path);
void check_surface_format(const std::string& path);

// Throws IoError naming the output when an output is the same file as an input (by identity:
// hard links and other spellings included) or as another output. Call it before any work.
void check_distinct_files(const std::vector<std::string>& inputs,
                          const std::vector<std::string>& outputs);

}  // namespace vmas

#pragma GCC visibility pop
