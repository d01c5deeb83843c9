// `import vmas`: the library for Python (pybind11). NumPy arrays in and out; the options are the
// CLI's (apps/run_options.cpp parses them, so names, defaults and messages are the same); the
// GIL is released while vmas computes, and Ctrl-C cancels.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <boost/program_options.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include "../commands.hpp"
#include "../run_summary.hpp"
#include "vmas/edit_session.hpp"
#include "vmas/eval.hpp"
#include "vmas/io.hpp"
#include "vmas/vmas.hpp"

namespace py = pybind11;
namespace po = boost::program_options;

namespace vmas::python {
namespace {

// --- arrays ---------------------------------------------------------------------------------

// An (N, 3) array of any real dtype and memory order, read in place (no copy beyond the one
// into vmas's own vectors).
std::vector<Vec3> rows_of(const py::handle& object, const char* name) {
  py::array array = py::array::ensure(object);
  if (!array) throw py::value_error(std::string(name) + " must be an (N, 3) array of numbers");
  if (array.ndim() != 2 || array.shape(1) != 3) {
    std::string shape = "(";
    for (py::ssize_t d = 0; d < array.ndim(); ++d)
      shape += (d ? ", " : "") + std::to_string(array.shape(d));
    throw py::value_error(std::string(name) + " must be an (N, 3) array, got shape " + shape +
                          (array.ndim() == 1 ? ",)" : ")"));
  }
  std::vector<Vec3> rows(static_cast<std::size_t>(array.shape(0)));
  const auto copy = [&](auto typed) {
    const auto view = typed.template unchecked<2>();
    for (py::ssize_t i = 0; i < view.shape(0); ++i)
      rows[i] = Vec3(double(view(i, 0)), double(view(i, 1)), double(view(i, 2)));
  };
  if (py::isinstance<py::array_t<double>>(array))
    copy(array.cast<py::array_t<double>>());
  else if (py::isinstance<py::array_t<float>>(array))
    copy(array.cast<py::array_t<float>>());
  else if (array.dtype().kind() == 'i' || array.dtype().kind() == 'u' ||
           array.dtype().kind() == 'f')
    copy(py::array_t<double, py::array::forcecast>::ensure(array));
  else
    throw py::value_error(std::string(name) + " must hold numbers (got dtype " +
                          std::string(py::str(array.dtype())) + ")");
  return rows;
}

std::vector<std::array<int, 3>> faces_of(const py::handle& object) {
  const py::array array = py::array::ensure(object);
  if (!array || array.ndim() != 2 || array.shape(1) != 3 ||
      (array.dtype().kind() != 'i' && array.dtype().kind() != 'u'))
    throw py::value_error("faces must be an (F, 3) array of integers");
  const auto indices = py::array_t<long long, py::array::forcecast>::ensure(array);
  const auto view = indices.unchecked<2>();
  std::vector<std::array<int, 3>> faces(static_cast<std::size_t>(view.shape(0)));
  for (py::ssize_t f = 0; f < view.shape(0); ++f)
    for (int c = 0; c < 3; ++c) {
      const long long index = view(f, c);
      if (index < 0 || index > INT32_MAX)
        throw py::value_error("faces: index " + std::to_string(index) + " out of range");
      faces[f][c] = static_cast<int>(index);
    }
  return faces;
}

py::array_t<double> matrix(const std::vector<Vec3>& rows) {
  py::array_t<double> out({static_cast<py::ssize_t>(rows.size()), py::ssize_t{3}});
  auto view = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (int c = 0; c < 3; ++c) view(i, c) = rows[i][c];
  return out;
}

template <std::size_t N>
py::array_t<int> index_matrix(const std::vector<std::array<int, N>>& rows) {
  py::array_t<int> out({static_cast<py::ssize_t>(rows.size()), static_cast<py::ssize_t>(N)});
  auto view = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t c = 0; c < N; ++c) view(i, c) = rows[i][c];
  return out;
}

SurfaceInput surface_of(const py::handle& points, const py::handle& normals,
                        const py::handle& faces) {
  SurfaceInput surface;
  surface.points = rows_of(points, "points");
  if (surface.points.empty()) throw py::value_error("points is empty");
  // NumPy marks a missing value with NaN or inf alike: both rows are dropped (label -1).
  for (Vec3& p : surface.points)
    if (p.array().isInf().any()) p = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  if (!normals.is_none()) {
    surface.normals = rows_of(normals, "normals");
    if (surface.normals.size() != surface.points.size())
      throw py::value_error("normals must have one row per point (" +
                            std::to_string(surface.points.size()) + "), got " +
                            std::to_string(surface.normals.size()));
  }
  if (!faces.is_none()) {
    surface.faces = faces_of(faces);
    for (const auto& face : surface.faces)
      for (int index : face)
        if (static_cast<std::size_t>(index) >= surface.points.size())
          throw py::value_error("faces: index " + std::to_string(index) + " out of range (" +
                                std::to_string(surface.points.size()) + " points)");
  }
  return surface;
}

// A path as Python gives it: str, bytes or os.PathLike.
std::string path_of(const py::handle& path) {
  return py::str(py::module_::import("os").attr("fsdecode")(path));
}

// --- options --------------------------------------------------------------------------------

// The Python spelling of a CLI flag: '_' for '-', and lambda_ (lambda is a Python keyword).
std::string keyword_of(std::string flag) {
  std::replace(flag.begin(), flag.end(), '-', '_');
  return flag == "lambda" ? flag + "_" : flag;
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// What a keyword may hold, by the CLI option it sets.
enum class Kind { Flag, Integer, Real, Denoise };

Kind kind_of(const po::option_description& option) {
  const po::value_semantic* semantic = option.semantic().get();
  if (semantic->max_tokens() == 0) return Kind::Flag;
  if (dynamic_cast<const po::typed_value<int>*>(semantic)) return Kind::Integer;
  if (dynamic_cast<const po::typed_value<double>*>(semantic)) return Kind::Real;
  return Kind::Denoise;  // the one option typed as text
}

bool is_boolean(const py::handle& value) {
  return py::isinstance<py::bool_>(value) ||
         py::isinstance(value, py::module_::import("numpy").attr("bool_"));
}

bool is_integer(const py::handle& value) {
  return !is_boolean(value) && (py::isinstance<py::int_>(value) ||
                                py::isinstance(value, py::module_::import("numpy").attr("integer")));
}

bool is_real(const py::handle& value) {
  return is_integer(value) || py::isinstance<py::float_>(value) ||
         py::isinstance(value, py::module_::import("numpy").attr("floating"));
}

std::string type_name(const py::handle& value) {
  return py::str(py::type::handle_of(value).attr("__name__"));
}

// The CLI words of one keyword (none for a flag set to False), its type checked first, as
// Python checks an argument: a TypeError naming the keyword. `caller` names the function.
std::vector<std::string> words_of(const std::string& caller, const std::string& keyword,
                                  const py::handle& value, const po::options_description& visible) {
  std::string flag = keyword;
  if (flag == "lambda_") flag.pop_back();
  std::replace(flag.begin(), flag.end(), '_', '-');
  const po::option_description* option = visible.find_nothrow(flag, false);
  if (!option || option->long_name() != flag) {
    std::string closest;
    std::size_t best = 3;  // farther names are no likely typo
    for (const auto& known : visible.options()) {
      const std::string candidate = keyword_of(known->long_name());
      const std::size_t distance = edit_distance(keyword, candidate);
      if (distance < best) best = distance, closest = candidate;
    }
    throw py::type_error(caller + "() got an unexpected keyword argument '" + keyword + "'" +
                         (closest.empty() ? "" : " (did you mean '" + closest + "'?)"));
  }
  const std::string dashed = "--" + flag;
  const auto wrong = [&](const std::string& expected) {
    return py::type_error(keyword + " must be " + expected + " (got " + type_name(value) + " " +
                          std::string(py::repr(value)) + ")");
  };
  switch (kind_of(*option)) {
    case Kind::Flag:
      if (!is_boolean(value)) throw wrong("True or False");
      return value.cast<bool>() ? std::vector<std::string>{dashed} : std::vector<std::string>{};
    case Kind::Integer:
      if (!is_integer(value)) throw wrong("an integer");
      return {dashed, py::str(py::int_(py::reinterpret_borrow<py::object>(value)))};
    case Kind::Real:
      if (!is_real(value)) throw wrong("a number");
      return {dashed, py::repr(py::float_(py::reinterpret_borrow<py::object>(value)))};
    case Kind::Denoise:
      // denoise=False: off; True: the default, auto.
      if (is_boolean(value)) return {dashed, value.cast<bool>() ? "auto" : "off"};
      if (!py::isinstance<py::str>(value) && !is_real(value))
        throw wrong("'auto', 'off', a number or a percentage such as '0.5%'");
      return {dashed, is_real(value) ? std::string(py::repr(py::float_(
                                           py::reinterpret_borrow<py::object>(value))))
                                     : std::string(py::str(value))};
  }
  return {};
}

// The Python type a keyword of that kind takes.
const char* python_type(Kind kind) {
  switch (kind) {
    case Kind::Flag: return "bool";
    case Kind::Integer: return "int";
    case Kind::Real: return "float";
    case Kind::Denoise: break;
  }
  return "str";
}

// vmas.options(): every row of the CLI's option table, as a keyword takes it.
py::list option_table() {
  cli::RunOptionValues values;
  po::options_description visible;
  cli::add_run_options(visible, values);
  py::list rows;
  for (const cli::RunOption& row : cli::run_option_table()) {
    const std::string flag = row.flag;
    const std::size_t comma = flag.find(',');
    const std::string name = flag.substr(0, comma);
    const po::option_description& option = visible.find(name, false);
    // "arg (=0.2)": the default as --help shows it.
    const std::string parameter = option.format_parameter();
    const std::size_t shown = parameter.find("(=");
    py::dict d;
    d["flag"] = "--" + name;
    d["short"] = comma == std::string::npos ? py::object(py::none())
                                            : py::object(py::str("-" + flag.substr(comma + 1)));
    d["keyword"] = keyword_of(name);
    d["field"] = row.field;
    d["type"] = python_type(kind_of(option));
    d["default"] = kind_of(option) == Kind::Flag ? py::object(py::bool_(false))
                   : shown == std::string::npos
                       ? py::object(py::none())
                       : py::object(py::str(parameter.substr(shown + 2, parameter.size() - shown - 3)));
    d["range"] = row.range;
    d["help"] = row.help;
    rows.append(std::move(d));
  }
  return rows;
}

// The keyword arguments as the CLI's flags (lambda_ -> --lambda; True -> a flag), each checked
// for its type, then parsed by the CLI's own parser: the same names, defaults, range checks and
// messages.
Options options_of(const std::string& caller, const py::dict& keywords) {
  cli::RunOptionValues values;
  po::options_description visible;
  cli::add_run_options(visible, values);
  std::vector<std::string> words = {"vmas"};
  for (const auto& [key, value] : keywords) {
    if (value.is_none()) continue;
    for (std::string& word : words_of(caller, py::str(key), value, visible))
      words.push_back(std::move(word));
  }
  std::vector<const char*> argv;
  for (const std::string& word : words) argv.push_back(word.c_str());
  try {
    po::variables_map vm;
    po::store(
        po::command_line_parser(static_cast<int>(argv.size()), argv.data())
            .options(visible)
            .style(po::command_line_style::unix_style ^ po::command_line_style::allow_guessing)
            .run(),
        vm);
    po::notify(vm);
    cli::finish_run_options(vm, values);
  } catch (const po::error_with_option_name& e) {
    // Keywords are type-checked before: what is left is a keyword given twice (lambda_ and
    // **{"lambda": ...}).
    std::string flag = e.get_option_name();
    flag.erase(0, flag.find_first_not_of('-'));
    throw InvalidOption(flag, std::string("is not valid here: ") + e.what());
  }
  return values.options;
}

// The surface and options of a call: a vmas.Surface, or arrays; spheres, error and threads
// joined to the other keywords.
struct Call {
  SurfaceInput surface;
  Options options;
};
// density= of a call: one value per point (a sequence or an array), a rule of
// vmas.density_by_rule ("curvature", "distance-to:X,Y,Z,R[,D]"), or the path (str or
// os.PathLike) of a file of one value per line. Checked as the CLI checks it.
std::vector<double> density_of(const py::handle& value, const SurfaceInput& surface) {
  const bool text = py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value);
  std::vector<double> density;
  if (text || py::isinstance(value, py::module_::import("os").attr("PathLike"))) {
    density = cli::density_of(path_of(value), surface);
  } else {
    const py::array array = py::array::ensure(value);
    if (!array || array.ndim() != 1 ||
        (array.dtype().kind() != 'f' && array.dtype().kind() != 'i' && array.dtype().kind() != 'u'))
      throw py::type_error(
          "density must be one number per point (an (N,) array), a rule "
          "('curvature', 'distance-to:X,Y,Z,R[,D]') or a file's path (got " +
          type_name(value) + ")");
    const auto numbers = py::array_t<double, py::array::forcecast>::ensure(array);
    const auto view = numbers.unchecked<1>();
    density.assign(view.data(0), view.data(0) + view.shape(0));
  }
  check_density(density, surface.points.size());
  return density;
}

Call call_of(const std::string& caller, const py::object& points, const py::object& normals,
             const py::object& faces, const py::object& spheres, const py::object& error,
             const py::object& threads, const py::kwargs& options) {
  py::dict keywords;
  py::object density = py::none();
  for (const auto& [key, value] : options) {
    const std::string name = py::str(key);
    if (name == "density_field")
      throw py::type_error(caller +
                           "() takes no density_field: read it with "
                           "vmas.read(path, density_field=NAME)");
    if (name == "density")
      density = py::reinterpret_borrow<py::object>(value);
    else
      keywords[key] = value;
  }
  keywords["spheres"] = spheres;
  keywords["error"] = error;
  keywords["threads"] = threads;
  const bool given = py::isinstance<SurfaceInput>(points) && normals.is_none() && faces.is_none();
  Call call{given ? points.cast<SurfaceInput>() : surface_of(points, normals, faces),
            options_of(caller, keywords)};
  if (!density.is_none()) call.surface.density = density_of(density, call.surface);
  return call;
}

// The constructor of a class that prepares its shape as vmas.skeletonize does: the same
// arguments and keywords (`name` in their errors).
template <class Class>
void def_prepared_init(py::class_<Class>& python_class, const char* name, const char* doc) {
  python_class.def(
      py::init([name](py::object points, py::object normals, py::object faces, py::object spheres,
                      py::object error, py::object threads, py::kwargs options) {
        Call call = call_of(name, points, normals, faces, spheres, error, threads, options);
        return std::make_unique<Class>(std::move(call.surface), call.options);
      }),
      py::arg("points"), py::arg("normals") = py::none(), py::arg("faces") = py::none(),
      py::kw_only(), py::arg("spheres") = py::none(), py::arg("error") = py::none(),
      py::arg("threads") = 0, doc);
}

// --- results --------------------------------------------------------------------------------

py::dict summary_dict(const RunSummary& s) {
  py::dict d;
  d["iterations"] = s.iterations;
  d["spheres"] = s.spheres;
  d["total_error"] = s.error;
  d["converged"] = s.converged;
  d["hit_max_iterations"] = s.hit_max_iterations;
  d["cancelled"] = s.cancelled;
  d["error_threshold_missed"] = s.error_threshold_missed;
  return d;
}

// A Result and its figures as `vmas skeletonize --json` gives them (apps/run_summary.cpp), taken
// when the run ends, while the input's size is known.
struct PythonResult {
  Result result;
  std::string summary;  // JSON
};

// JSON text as Python objects (dicts, lists, numbers), as json.loads gives them.
py::object from_json(const std::string& text) {
  return py::module_::import("json").attr("loads")(text);
}

py::object summary_of(const PythonResult& r) { return from_json(r.summary); }

py::list warnings_of(const std::vector<Warning>& warnings) {
  py::list list;
  for (const Warning& w : warnings) list.append(py::make_tuple(w.code, w.message));
  return list;
}

py::array_t<double> radii_of(const MedialMesh& mesh) {
  py::array_t<double> radii(static_cast<py::ssize_t>(mesh.spheres.size()));
  auto view = radii.mutable_unchecked<1>();
  for (std::size_t i = 0; i < mesh.spheres.size(); ++i) view(i) = mesh.spheres[i].radius;
  return radii;
}

py::array_t<double> centers_of(const MedialMesh& mesh) {
  std::vector<Vec3> centers;
  for (const Sphere& s : mesh.spheres) centers.push_back(s.center);
  return matrix(centers);
}

// A medial mesh from a Result or from anything with centers, radii, edges and faces.
MedialMesh medial_of(const py::handle& object) {
  if (py::isinstance<PythonResult>(object)) return object.cast<const PythonResult&>().result.medial_mesh;
  if (py::isinstance<MedialMesh>(object)) return object.cast<MedialMesh>();
  MedialMesh mesh;
  const std::vector<Vec3> centers = rows_of(object.attr("centers"), "centers");
  const py::array_t<double, py::array::forcecast> radii =
      py::array_t<double, py::array::forcecast>::ensure(object.attr("radii"));
  if (!radii || radii.ndim() != 1 || radii.shape(0) != static_cast<py::ssize_t>(centers.size()))
    throw py::value_error("radii must be an (M,) array, one per centre");
  for (std::size_t i = 0; i < centers.size(); ++i)
    mesh.spheres.push_back({centers[i], radii.at(i)});
  const py::array_t<long long, py::array::forcecast> edges =
      py::array_t<long long, py::array::forcecast>::ensure(object.attr("edges"));
  if (!edges || (edges.size() > 0 && (edges.ndim() != 2 || edges.shape(1) != 2)))
    throw py::value_error("edges must be an (E, 2) array of integers");
  for (py::ssize_t e = 0; edges.size() > 0 && e < edges.shape(0); ++e)
    mesh.edges.push_back({static_cast<int>(edges.at(e, 0)), static_cast<int>(edges.at(e, 1))});
  const py::object faces = object.attr("faces");
  if (py::array::ensure(faces).size() > 0) mesh.faces = faces_of(faces);
  return mesh;
}

// --- progress and Ctrl-C --------------------------------------------------------------------

// Called from vmas in the calling thread with the GIL released: takes it, looks for Ctrl-C (a
// pending KeyboardInterrupt cancels the run) and calls the user's callback, if any.
struct PythonProgress {
  py::object callback;
  bool interrupted = false;

  bool operator()(const Progress& p) {
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) {
      interrupted = true;
      return false;
    }
    if (callback.is_none()) return true;
    static const char* const kPhases[] = {"preparing",   "optimising", "settling",
                                          "final_refit", "refining",   "other_starts",
                                          "smoothing_check"};
    const double fraction = p.fraction;
    try {
      const py::object go_on = callback(kPhases[static_cast<int>(p.phase)], fraction);
      return go_on.is_none() || go_on.cast<bool>();
    } catch (py::error_already_set&) {
      interrupted = true;  // the callback raised: the run stops, the exception goes up
      throw;
    }
  }
};

PythonResult run_skeletonize(SurfaceInput surface, const Options& options,
                             const py::object& progress) {
  PythonProgress watch{progress};
  try {
    py::gil_scoped_release released;
    cli::RunContext run;
    run.input_size = {surface.points.size(), surface.faces.size()};
    PythonResult r{skeletonize(std::move(surface), options, std::ref(watch)), ""};
    r.summary = cli::run_summary(r.result, run).dump(-1, ' ', false,
                                                     cli::json::error_handler_t::replace);
    return r;
  } catch (const Cancelled&) {
    if (watch.interrupted && PyErr_Occurred()) throw py::error_already_set();
    throw;
  }
}

// The stateful API: a Skeletonizer on a prepared shape (as vmas.skeletonize prepares it), its
// results in the input's coordinates and its labels by input row. Every call runs with the
// object's thread count, one at a time: a second Python thread waits for the first (a
// Skeletonizer is not safe to use from two threads at once).
// How a prepared shape maps back to its input: the frame, and the input row of every vertex.
class InputMap {
 public:
  InputMap() = default;
  InputMap(std::size_t input_points, const PreparedShape& prepared)
      : frame_(prepared.result.prepare.frame),
        input_points_(input_points),
        input_row_(prepared.result.clean.kept),
        stand_in_(prepared.result.prepare.stand_in),
        rows_(input_row_, stand_in_, input_points, prepared.shape.points.size()) {}

  // The sphere of every input row, −1 for a row that cleaning or preparation dropped.
  std::vector<int> input_labels(const std::vector<int>& labels) const {
    return vmas::input_labels(input_row_, stand_in_, labels, input_points_);
  }

  const Frame& frame() const { return frame_; }
  const InputRows& rows() const { return rows_; }  // density by input row <-> by vertex

 private:
  Frame frame_;
  std::size_t input_points_ = 0;
  std::vector<int> input_row_;  // of every cleaned point
  std::vector<int> stand_in_;   // of every cleaned point: its prepared point, or −1
  InputRows rows_;
};

// The shape prepared as vmas.skeletonize prepares it, and `map` back to its input; Ctrl-C stops
// the preparation.
PreparedShape prepared_for_python(SurfaceInput surface, const Options& options, InputMap& map) {
  const std::size_t rows = surface.points.size();
  PythonProgress watch{py::none()};
  try {
    py::gil_scoped_release released;
    PreparedShape prepared = prepare_shape(std::move(surface), options, std::ref(watch));
    map = InputMap(rows, prepared);
    return prepared;
  } catch (const Cancelled&) {
    if (watch.interrupted && PyErr_Occurred()) throw py::error_already_set();
    throw;
  }
}

class PythonSkeletonizer {
 public:
  PythonSkeletonizer(SurfaceInput surface, const Options& options)
      : threads_(options.threads), refine_(options.refine) {
    PreparedShape prepared = prepared_for_python(std::move(surface), options, map_);
    measure_ = refinement_eval_options(prepared);
    surface_ = std::move(prepared.surface);
    skeletonizer_ = std::make_unique<Skeletonizer>(std::move(prepared.shape), prepared.run);
  }

  // `work(skeletonizer)` with the GIL released (taken first, so that a thread waiting for the
  // lock never holds the GIL that the one working may need for its progress callback).
  template <class Work>
  auto locked(Work&& work) {
    py::gil_scoped_release released;
    std::lock_guard<std::mutex> lock(mutex_);
    const ThreadCount threads(threads_);
    return work(*skeletonizer_);
  }
  // As locked(), for work that changes the skeleton: the final refits of a run are then undone.
  template <class Work>
  auto edited(Work&& work) {
    return locked([&](Skeletonizer& s) {
      refitted_ = false;
      return work(s);
    });
  }

  RunSummary run(const ProgressCallback& progress) {
    return locked([&](Skeletonizer& s) {
      const RunSummary summary = s.run(progress);
      refitted_ = !summary.cancelled;
      return summary;
    });
  }

  // What vmas.skeletonize does after its run (vmas::finish_skeleton): the final refits unless
  // run() just made them, the refinement, and the error measured against the prepared surface.
  // Its report, and the measured error in % of the shape's diagonal.
  std::pair<FinishReport, double> finish(const ProgressCallback& progress) {
    return locked([&](Skeletonizer& s) {
      if (!evaluator_) evaluator_ = std::make_unique<Evaluator>(surface_, measure_);
      const FinishReport report = finish_skeleton(s, *evaluator_, refine_, refitted_, progress);
      refitted_ = refitted_ || !report.cancelled;
      return std::make_pair(report, 100.0 * report.error / s.shape().diagonal);
    });
  }

  std::vector<int> input_labels(const std::vector<int>& labels) const {
    return map_.input_labels(labels);
  }
  const Frame& frame() const { return map_.frame(); }

 private:
  int threads_;
  InputMap map_;
  std::mutex mutex_;
  std::unique_ptr<Skeletonizer> skeletonizer_;
  // What finish() measures against and how it refines (as vmas.skeletonize).
  SurfaceInput surface_;
  RefineOptions refine_;
  EvalOptions measure_;
  std::unique_ptr<Evaluator> evaluator_;  // built by the first finish()
  bool refitted_ = false;                 // the last change was run()'s final refits
};

// vmas.EditSession: the optimisation in a worker thread while Python edits it (the paper's
// workflow); the library's EditSession is safe to call from any thread.
class PythonEditSession {
 public:
  PythonEditSession(SurfaceInput surface, const Options& options) {
    PreparedShape prepared = prepared_for_python(std::move(surface), options, map_);
    FinishOptions finish = finish_as_skeletonize_does(prepared, options);
    session_ = std::make_unique<EditSession>(std::move(prepared.shape), prepared.run,
                                             options.threads, std::move(finish),
                                             std::move(prepared.result.input_genus));
  }
  EditSession& session() {
    if (!session_) throw InvalidArgument("the session is closed");
    return *session_;
  }
  void close() {
    py::gil_scoped_release released;  // the worker may be waiting for nothing of Python's
    session_.reset();
  }
  const InputMap& map() const { return map_; }

 private:
  InputMap map_;
  std::unique_ptr<EditSession> session_;
};


// Errors: the CLI's messages, as Python exceptions. vmas.Error is the base of every one, each
// also the built-in a Python user would catch.
void def_errors(py::module_& m) {
  static py::exception<Error> error(m, "Error");
  const auto bases = [&](PyObject* builtin) {
    return py::make_tuple(error, py::handle(builtin));
  };
  static py::exception<InvalidInput> invalid_input(m, "InvalidInput", bases(PyExc_ValueError));
  static py::exception<InvalidOption> invalid_option(m, "InvalidOption", bases(PyExc_ValueError));
  static py::exception<InvalidArgument> invalid_argument(m, "InvalidArgument",
                                                         bases(PyExc_ValueError));
  static py::exception<IoError> io_error(m, "IoError", bases(PyExc_OSError));
  static py::exception<Cancelled> cancelled(m, "Cancelled", error);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InvalidOption& e) {
      // Named as the keyword argument that sets it: "final_lambda must be ...".
      std::string name = cli::flag_of(e.option());
      std::replace(name.begin(), name.end(), '-', '_');
      invalid_option((name + " " + e.problem()).c_str());
    } catch (const InvalidArgument& e) {
      invalid_argument(e.what());
    } catch (const InvalidInput& e) {
      invalid_input(e.what());
    } catch (const IoError& e) {
      io_error(e.what());
    } catch (const Cancelled& e) {
      cancelled(e.what());
    } catch (const Error& e) {
      error(e.what());
    }
  });
}

// The shapes that go in and out: vmas.Surface, vmas.MedialMesh.
void def_shapes(py::module_& m) {
  py::class_<SurfaceInput>(m, "Surface", "A shape as vmas reads it: points, normals, faces.")
      .def_property_readonly(
          "points", [](const SurfaceInput& s) { return matrix(s.points); }, "(N, 3) float64")
      .def_property_readonly(
          "normals",
          [](const SurfaceInput& s) -> py::object {
            return s.normals.empty() ? py::object(py::none()) : py::object(matrix(s.normals));
          },
          "(N, 3) float64, or None")
      .def_property_readonly(
          "faces",
          [](const SurfaceInput& s) -> py::object {
            return s.faces.empty() ? py::object(py::none()) : py::object(index_matrix(s.faces));
          },
          "(F, 3) int32, or None for a cloud")
      .def_property_readonly(
          "density",
          [](const SurfaceInput& s) -> py::object {
            if (s.density.empty()) return py::none();
            return py::array_t<double>(static_cast<py::ssize_t>(s.density.size()),
                                       s.density.data());
          },
          "(N,) float64, or None (uniform)")
      .def("__repr__", [](const SurfaceInput& s) {
        return "<vmas.Surface: " + std::to_string(s.points.size()) + " points, " +
               std::to_string(s.faces.size()) + " faces" + (s.has_normals() ? ", normals>" : ">");
      });

  py::class_<MedialMesh>(m, "MedialMesh", "Spheres joined by edges and triangles.")
      .def_property_readonly("centers", &centers_of, "(M, 3) float64")
      .def_property_readonly("radii", &radii_of, "(M,) float64")
      .def_property_readonly(
          "edges", [](const MedialMesh& mm) { return index_matrix(mm.edges); }, "(E, 2) int32")
      .def_property_readonly(
          "faces", [](const MedialMesh& mm) { return index_matrix(mm.faces); }, "(T, 3) int32");
}

// vmas.Result: what vmas.skeletonize gives, and its pickling.
void def_result(py::module_& m) {
  py::class_<PythonResult>(m, "Result", "What vmas.skeletonize gives.")
      .def_property_readonly("medial_mesh",
                             [](const PythonResult& r) { return r.result.medial_mesh; })
      .def_property_readonly(
          "centers", [](const PythonResult& r) { return centers_of(r.result.medial_mesh); },
          "(M, 3) float64: the spheres' centres")
      .def_property_readonly(
          "radii", [](const PythonResult& r) { return radii_of(r.result.medial_mesh); },
          "(M,) float64")
      .def_property_readonly(
          "edges", [](const PythonResult& r) { return index_matrix(r.result.medial_mesh.edges); },
          "(E, 2) int32: indices into centers")
      .def_property_readonly(
          "faces", [](const PythonResult& r) { return index_matrix(r.result.medial_mesh.faces); },
          "(T, 3) int32: indices into centers")
      .def_property_readonly(
          "labels",
          [](const PythonResult& r) {
            return py::array_t<int>(r.result.labels.size(), r.result.labels.data());
          },
          "(N,) int32: the sphere of every input point, -1 for a dropped one")
      .def_property_readonly(
          "warnings", [](const PythonResult& r) { return warnings_of(r.result.warnings); },
          "[(code, message)]: what the caller should know")
      .def_property_readonly("summary", &summary_of,
                             "the run's figures, as `vmas skeletonize --json` gives them (dict)")
      .def_property_readonly(
          "seconds",
          [](const PythonResult& r) {
            const py::object summary = summary_of(r);
            return py::object(summary["seconds"]);
          },
          "time per stage (dict): the summary's seconds")
      .def(
          "to_dict",
          [](const py::object& self) {
            py::dict d;
            for (const char* name :
                 {"centers", "radii", "edges", "faces", "labels", "warnings", "summary", "seconds"})
              d[name] = self.attr(name);
            return d;
          },
          "everything as a dict of arrays, lists and dicts")
      // Picklable (multiprocessing returns results so): what Python sees of it.
      .def(py::pickle(
          [](const PythonResult& r) {
            const MedialMesh& mm = r.result.medial_mesh;
            return py::make_tuple(centers_of(mm), radii_of(mm), index_matrix(mm.edges),
                                  index_matrix(mm.faces),
                                  py::array_t<int>(r.result.labels.size(), r.result.labels.data()),
                                  warnings_of(r.result.warnings), r.summary);
          },
          [](const py::tuple& state) {
            if (state.size() != 7) throw py::value_error("not a pickled vmas.Result");
            PythonResult r;
            MedialMesh& mm = r.result.medial_mesh;
            const std::vector<Vec3> centers = rows_of(state[0], "centers");
            const auto radii = state[1].cast<std::vector<double>>();
            for (std::size_t i = 0; i < centers.size() && i < radii.size(); ++i)
              mm.spheres.push_back({centers[i], radii[i]});
            for (const auto& e : state[2].cast<std::vector<std::array<int, 2>>>()) mm.edges.push_back(e);
            if (py::array::ensure(state[3]).size() > 0) mm.faces = faces_of(state[3]);
            r.result.labels = state[4].cast<std::vector<int>>();
            for (const auto& w : state[5].cast<std::vector<std::pair<std::string, std::string>>>())
              r.result.warnings.push_back({w.first, w.second});
            r.summary = state[6].cast<std::string>();
            return r;
          }))
      .def("__repr__", [](const PythonResult& r) {
        const MedialMesh& mm = r.result.medial_mesh;
        return "<vmas.Result: " + std::to_string(mm.spheres.size()) + " spheres, " +
               std::to_string(mm.edges.size()) + " edges, " + std::to_string(mm.faces.size()) +
               " faces>";
      });
}

// vmas.Skeletonizer's state: its skeleton, points, labels and keys.
void def_skeletonizer_state(py::class_<PythonSkeletonizer>& skeletonizer) {
  using PySk = PythonSkeletonizer;
  skeletonizer
      .def(
          "medial_mesh",
          [](PySk& p) {
            return p.locked([&](Skeletonizer& s) { return p.frame().to_input(s.medial_mesh()); });
          },
          "The medial mesh now, in the input's coordinates.")
      .def_property_readonly(
          "points",
          [](PySk& p) {
            std::vector<Vec3> points = p.locked([](Skeletonizer& s) { return s.shape().points; });
            for (Vec3& point : points) point = p.frame().to_input(point);
            return matrix(points);
          },
          "(V, 3): the prepared shape's vertices, in the input's coordinates")
      .def_property_readonly(
          "vertex_labels",
          [](PySk& p) {
            const std::vector<int> labels = p.locked([](Skeletonizer& s) { return s.labels(); });
            return py::array_t<int>(labels.size(), labels.data());
          },
          "(V,) int32: the sphere of every prepared vertex (of `points`)")
      .def_property_readonly(
          "labels",
          [](PySk& p) {
            const std::vector<int> labels = p.input_labels(
                p.locked([](Skeletonizer& s) { return s.labels(); }));
            return py::array_t<int>(labels.size(), labels.data());
          },
          "(N,) int32: the sphere of every input row, -1 for a row dropped (as Result.labels)")
      .def_property_readonly(
          "keys",
          [](PySk& p) {
            const std::vector<std::uint64_t> keys =
                p.locked([](Skeletonizer& s) { return s.keys(); });
            return py::array_t<std::uint64_t>(keys.size(), keys.data());
          },
          "(M,) uint64: a key per sphere that stays with it for its life")
      .def_property_readonly(
          "total_error",
          [](PySk& p) { return p.locked([](Skeletonizer& s) { return s.total_error(); }); })
      .def_property_readonly("spheres", [](PySk& p) {
        return p.locked([](Skeletonizer& s) { return static_cast<int>(s.spheres().size()); });
      });
}

// vmas.Skeletonizer: the optimisation step by step, editable between steps.
void def_skeletonizer(py::module_& m) {
  using PySk = PythonSkeletonizer;
  py::class_<PySk> skeletonizer(
      m, "Skeletonizer",
      "The optimisation, step by step, editable between steps (the paper's dynamic editing). "
      "Vertex indices are those of the prepared shape (`points`, in the input's coordinates); "
      "`labels` are by input row. Calls from several threads take turns.");
  def_prepared_init(skeletonizer, "Skeletonizer",
                    "Prepares the shape as vmas.skeletonize does (same arguments and options) and "
                    "starts from one sphere.");
  skeletonizer
      .def(
          "step", [](PySk& p) { return p.edited([](Skeletonizer& s) { return s.step(); }); },
          "One partition + update + projection step; returns the total error.")
      .def(
          "advance",
          [](PySk& p) {
            const Turn turn = p.edited([](Skeletonizer& s) { return s.advance(); });
            py::dict d;
            d["error"] = turn.error;
            d["converged"] = turn.converged;
            d["split"] = turn.split;
            d["done"] = turn.done;
            return d;
          },
          "One turn of run()'s schedule: a step, then the split decision (dict).")
      .def(
          "run",
          [](PySk& p, py::object progress) {
            PythonProgress watch{progress};
            const RunSummary summary = p.run(std::ref(watch));
            if (watch.interrupted && PyErr_Occurred()) throw py::error_already_set();
            return summary_dict(summary);
          },
          py::arg("progress") = py::none(),
          "Turns until done, then the final refits (without the worst-case refinement of "
          "vmas.skeletonize: see finish()); returns the summary (dict).")
      .def(
          "finish",
          [](PySk& p, py::object progress) {
            PythonProgress watch{progress};
            const auto [report, percent] = p.finish(std::ref(watch));
            if (watch.interrupted && PyErr_Occurred()) throw py::error_already_set();
            py::dict d;
            d["moves_tried"] = report.refine.tried;
            d["moves_kept"] = report.refine.kept;
            d["measured_error_percent"] = percent;
            d["cancelled"] = report.cancelled;
            return d;
          },
          py::arg("progress") = py::none(),
          "What vmas.skeletonize does after its run: the final refits (unless run() just made "
          "them), the worst-case refinement (refine_moves), and the two-sided error measured as "
          "it measures it; returns moves_tried, moves_kept, measured_error_percent (of the shape's "
          "diagonal) and cancelled (dict).")
      .def(
          "split", [](PySk& p) { return p.edited([](Skeletonizer& s) { return s.split(); }); },
          "One split round; returns the spheres added.")
      .def(
          "add_sphere",
          [](PySk& p, int vertex) {
            return p.edited([&](Skeletonizer& s) { return s.add_sphere_at(vertex); });
          },
          py::arg("vertex"), "A sphere at the shrinking ball of `vertex`; returns its id.")
      .def(
          "remove_sphere",
          [](PySk& p, int id) { p.edited([&](Skeletonizer& s) { s.remove_sphere(id); }); },
          py::arg("id"), "Removes sphere `id` (later ids shift down by one; keys stay).")
      .def(
          "freeze",
          [](PySk& p, int id, bool frozen) {
            p.edited([&](Skeletonizer& s) { s.freeze(id, frozen); });
          },
          py::arg("id"), py::arg("frozen") = true,
          "A frozen sphere is neither moved, split nor removed by the optimisation.");
  def_skeletonizer_state(skeletonizer);
}

// vmas.EditSession's pause, finish, state and end.
void def_edit_session_control(py::class_<PythonEditSession>& edit_session) {
  using PyEdit = PythonEditSession;
  edit_session
      .def(
          "pause", [](PyEdit& e, bool paused) { e.session().pause(paused); },
          py::arg("paused") = true)
      .def(
          "finish", [](PyEdit& e) { e.session().finish(); },
          "Ends as vmas.skeletonize does (final refits, refinement), then pauses.")
      .def(
          "cancel_finish", [](PyEdit& e) { e.session().cancel_finish(); },
          "Stops a finish under way: the state as it was before it (nothing when none is).")
      .def(
          "wait",
          [](PyEdit& e, std::uint64_t version, double timeout) {
            py::gil_scoped_release released;
            return e.session().wait_for_version(version, static_cast<int>(1000.0 * timeout));
          },
          py::arg("version") = 0, py::arg("timeout") = 1.0,
          "Waits until a snapshot newer than `version` is out (or `timeout` s); its version.")
      .def(
          "snapshot",
          [](PyEdit& e) {
            EditSnapshot snap;
            {
              py::gil_scoped_release released;
              snap = e.session().snapshot();
            }
            py::dict d;
            d["version"] = snap.version;
            d["iteration"] = snap.iteration;
            d["error"] = snap.error;
            d["paused"] = snap.paused;
            d["target_spheres"] = snap.target_spheres;
            d["keys"] = py::array_t<std::uint64_t>(snap.keys.size(), snap.keys.data());
            d["frozen"] = py::cast(std::vector<bool>(snap.frozen));
            d["medial_mesh"] = e.map().frame().to_input(snap.mesh);
            const std::vector<int> labels = e.map().input_labels(snap.labels);
            d["labels"] = py::array_t<int>(labels.size(), labels.data());
            d["finished"] = snap.finished;
            d["finishing"] = snap.finishing;
            d["finish_phase"] = snap.finish_phase;
            d["finish_fraction"] = snap.finish_fraction;
            d["measured_error"] = snap.measured_error;
            d["topology"] = from_json(cli::edit_topology_summary(snap).dump());
            if (snap.density) {
              const std::vector<double> density = e.map().rows().by_row(*snap.density);
              d["density"] = py::array_t<double>(static_cast<py::ssize_t>(density.size()),
                                                 density.data());
            } else {
              d["density"] = py::none();
            }
            return d;
          },
          "The state now (dict): version, iteration, error, paused, target_spheres, keys, "
          "frozen, medial_mesh (input's coordinates), labels (by input row), finished, "
          "finishing, finish_phase, finish_fraction (of that phase), measured_error, topology "
          "(as `vmas edit`'s: input_genus, b0, b1, b2, duplicate_triangles, extra_loops and "
          "cavity_triangles by sphere index), density (by input row, or None: uniform).")
      .def("close", &PyEdit::close, "Stops the worker; later calls raise vmas.InvalidArgument.")
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](PyEdit& e, py::args) { e.close(); });
}

// vmas.EditSession: the optimisation in a worker thread, edited from any thread.
void def_edit_session(py::module_& m) {
  using PyEdit = PythonEditSession;
  py::class_<PyEdit> edit_session(
      m, "EditSession",
      "The optimisation running in a worker thread while you edit it (the paper's dynamic "
      "editing, the engine of `vmas edit`): edits are queued and applied between steps; "
      "snapshot() gives the state now. Spheres are named by their keys. Any thread may call it. "
      "close() (or leaving a `with` block) stops the worker.");
  def_prepared_init(edit_session, "EditSession",
                    "Prepares the shape as vmas.skeletonize does (same arguments and options) and "
                    "starts optimising at once.");
  edit_session
      .def(
          "remove",
          [](PyEdit& e, std::uint64_t key) {
            py::gil_scoped_release released;
            e.session().remove(key);
          },
          py::arg("key"), "Removes the sphere with this key.")
      .def(
          "split_at",
          [](PyEdit& e, int vertex) {
            py::gil_scoped_release released;
            e.session().split_at(vertex);
          },
          py::arg("vertex"), "A new sphere: the shrinking ball at this prepared vertex.")
      .def(
          "freeze",
          [](PyEdit& e, std::uint64_t key, bool frozen) {
            py::gil_scoped_release released;
            e.session().freeze(key, frozen);
          },
          py::arg("key"), py::arg("frozen") = true,
          "A frozen sphere is neither moved, split nor removed by the optimisation.")
      .def(
          "set_target_spheres",
          [](PyEdit& e, int count) {
            py::gil_scoped_release released;
            e.session().set_target_spheres(count);
          },
          py::arg("count"))
      .def(
          "set_lambda",
          [](PyEdit& e, double lambda) {
            py::gil_scoped_release released;
            e.session().set_lambda(lambda);
          },
          py::arg("lambda_"))
      .def(
          "paint_density",
          [](PyEdit& e, int vertex, double radius, double amount) {
            py::gil_scoped_release released;
            e.session().paint_density(vertex, radius, amount);
          },
          py::arg("vertex"), py::arg("radius"), py::arg("amount"),
          "A brush stroke (one undo step): `amount` added to the density at this prepared "
          "vertex, falling smoothly to nothing at `radius` (a fraction of the diagonal).")
      .def(
          "set_density",
          [](PyEdit& e, const py::object& density) {
            std::vector<double> by_vertex;
            if (!density.is_none()) {
              const std::vector<double> by_row = density.cast<std::vector<double>>();
              check_density(by_row, e.map().rows().rows());
              by_vertex = e.map().rows().by_vertex(by_row);
            }
            py::gil_scoped_release released;
            e.session().set_density(std::move(by_vertex));
          },
          py::arg("density"),
          "The density of every input row (a vertex takes the mean of the rows it stands for), "
          "or None: uniform. One undo step.")
      .def("undo", [](PyEdit& e) { e.session().undo(); })
      .def("redo", [](PyEdit& e) { e.session().redo(); });
  def_edit_session_control(edit_session);
}

// vmas.skeletonize: the CLI's run in one call.
void def_skeletonize(py::module_& m) {
  m.def("options", &option_table,
        "Every keyword option of skeletonize(), Skeletonizer() and EditSession(), as `vmas "
        "skeletonize --help` lists it: a dict per option with flag, short, keyword, field (of "
        "the C++ vmas::Options), type (bool, int, float, str), default (as --help shows it; "
        "None for none), range (what is accepted) and help.");

  m.def(
      "skeletonize",
      [](py::object points, py::object normals, py::object faces, py::object spheres,
         py::object error, py::object threads, py::object progress, py::kwargs options) {
        Call call = call_of("skeletonize", points, normals, faces, spheres, error, threads,
                            options);
        return run_skeletonize(std::move(call.surface), call.options, progress);
      },
      py::arg("points"), py::arg("normals") = py::none(), py::arg("faces") = py::none(),
      py::kw_only(), py::arg("spheres") = py::none(), py::arg("error") = py::none(),
      py::arg("threads") = 0, py::arg("progress") = py::none(),
      R"(Skeletonizes a point cloud or a mesh, exactly as `vmas skeletonize` does.

points:   (N, 3) array of float32/float64 (any memory order; NaN rows are dropped), or a
          vmas.Surface from vmas.read
normals:  (N, 3) array, or None (estimated and oriented outward)
faces:    (F, 3) integer array for a triangle mesh, or None for a cloud
density:  where the skeleton should be finer: one value >= 0 per point ((N,) array), a rule
          ("curvature", "distance-to:X,Y,Z,R[,D]") or a file of one value per line; None
          (default) or a vmas.Surface's own density (vmas.read(path, density_field=NAME))
spheres:  spheres to produce (default 100 when error is None), or
error:    split until every cluster's RMS error is below this fraction of the diagonal
threads:  OpenMP threads (0: all cores)
progress: callable(phase, fraction) -> bool, called from this thread; False cancels. The
          phases, in order (some may be skipped): "preparing", "optimising" (spheres added),
          "settling", "final_refit", "refining", "other_starts", "smoothing_check"; the
          fraction rises from 0 to 1 once in each
options:  every option of `vmas skeletonize --help`, spelled with '_' for '-': lambda_ (or
          **{"lambda": 0.1}), final_lambda, final_rounds, refine_moves, k, normal_k,
          max_points, denoise ("auto", "off", 0.005 or "0.5%"), estimate_normals=True,
          orient_normals=True, no_projection=True, ...

Returns a vmas.Result. Raises vmas.InvalidOption (a ValueError naming the option),
vmas.InvalidInput (data that cannot give the skeleton asked for), ValueError for arrays of the
wrong shape, KeyboardInterrupt on Ctrl-C.)");
}

// Reading and writing as the CLI does.
void def_io(py::module_& m) {
  m.def(
      "read",
      [](const py::object& path, const py::object& density_field) {
        const std::string file = path_of(path);
        const std::string field =
            density_field.is_none() ? "" : std::string(py::str(density_field));
        py::gil_scoped_release released;
        return cli::read_with_density(file, cli::DensitySource{{}, field});
      },
      py::arg("path"), py::kw_only(), py::arg("density_field") = py::none(),
      "Reads a shape (.off .ply .obj .xyz .txt .pcd) as `vmas skeletonize` does: every point "
      "as stored, so that Result.labels index the file's points; with density_field, the "
      "points' density from that PLY property or PCD field (or an .xyz's last of 4 or 7 "
      "columns), as Surface.density. Raises vmas.IoError (an OSError) naming the file.");

  m.def(
      "write",
      [](const py::object& path, py::object medial) {
        const std::string file = path_of(path);
        const MedialMesh mesh = medial_of(medial);
        py::gil_scoped_release released;
        write_medial_mesh(file, mesh);
      },
      py::arg("path"), py::arg("medial"),
      "Writes a medial mesh (a Result, a MedialMesh or anything with centers, radii, edges, "
      "faces) as .ply or .ma, atomically, as the CLI writes it.");

  m.def(
      "density_by_rule",
      [](const py::object& points, const std::string& rule) {
        const SurfaceInput surface = py::isinstance<SurfaceInput>(points)
                                         ? points.cast<SurfaceInput>()
                                         : surface_of(points, py::none(), py::none());
        std::vector<double> density;
        {
          py::gil_scoped_release released;
          density = density_by_rule(surface, rule);
        }
        return py::array_t<double>(static_cast<py::ssize_t>(density.size()), density.data());
      },
      py::arg("points"), py::arg("rule"),
      "The density a rule gives the points ((N, 3) array or vmas.Surface): 'curvature' or "
      "'distance-to:X,Y,Z,R[,D]', as `vmas skeletonize --density RULE` makes it.");

  m.def(
      "read_medial",
      [](const py::object& path) {
        const std::string file = path_of(path);
        py::gil_scoped_release released;
        return read_medial_mesh(file);
      },
      py::arg("path"), "Reads a medial mesh (.ply or .ma).");
}

// Measuring as `vmas eval` does.
void def_evaluate(py::module_& m) {
  m.def(
      "evaluate",
      [](py::object shape, py::object medial, py::object faces) {
        const SurfaceInput surface = py::isinstance<SurfaceInput>(shape)
                                         ? shape.cast<SurfaceInput>()
                                         : surface_of(shape, py::none(), faces);
        const MedialMesh mesh = medial_of(medial);
        EvalResult r;
        OpeningReach openings;
        {
          py::gil_scoped_release released;
          SurfaceInput cleaned = surface;
          clean_surface(cleaned);
          r = evaluate(cleaned, mesh);
          openings = opening_reach(cleaned, r);
        }
        py::dict d = from_json(cli::eval_figures(r, &openings).dump());
        const MedialTopology topology = medial_topology(mesh);
        py::dict betti;
        betti["b0"] = topology.components;
        betti["b1"] = topology.loops;
        betti["b2"] = topology.cavities;
        betti["duplicate_triangles"] = topology.duplicate_triangles;
        d["topology"] = betti;
        return d;
      },
      py::arg("shape"), py::arg("medial"), py::arg("faces") = py::none(),
      "The figures of `vmas eval`: the two-sided Hausdorff distance between a shape (a "
      "vmas.Surface, or an (N, 3) array and optional faces) and the reconstruction of a medial "
      "mesh, in % of the shape's diagonal, and against a cloud its openings and how far the "
      "reconstruction reaches past them (dict).");
}

}  // namespace
}  // namespace vmas::python

PYBIND11_MODULE(vmas, m) {
  using namespace vmas::python;
  m.doc() =
      "Skeletons by variational medial axis sampling: a point cloud (with or without normals) "
      "or a triangle mesh in, a medial mesh of spheres, edges and triangles out.";
  m.attr("__version__") = vmas::version();

  def_errors(m);
  def_shapes(m);
  def_result(m);
  def_skeletonizer(m);
  def_edit_session(m);
  def_skeletonize(m);
  def_io(m);
  def_evaluate(m);
}
