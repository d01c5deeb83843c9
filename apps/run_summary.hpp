#pragma once
// The figures of a run as data: `vmas skeletonize --json` prints them (and reads them back for
// its summary lines), `import vmas` gives them as Result.summary. One schema in one place.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "vmas/edit_session.hpp"
#include "vmas/eval.hpp"
#include "vmas/vmas.hpp"

namespace vmas::cli {

using json = nlohmann::ordered_json;

// What was read, before the run consumed it.
struct InputSize {
  std::size_t points = 0, faces = 0;
};

// What the caller knows beyond the Result: the file names (left out when empty), the seconds
// of reading and writing, and a metric against the cleaned input (`--eval`), if measured.
struct RunContext {
  InputSize input_size;
  std::string input, output;
  double read_seconds = 0.0, write_seconds = 0.0;
  const EvalResult* eval = nullptr;
};

json run_summary(const Result& result, const RunContext& run);
// A summary as one line of JSON (text that is not UTF-8, in a file name, replaced).
std::string json_line(const json& summary);

// An evaluation's figures as every front end gives them (`vmas eval --json`, `skeletonize
// --eval`, Python's evaluate()): the diagonal, the one-sided figures in % of it, the samples
// measured and, when given, a cloud's openings and how far the reconstruction reaches past
// them; each to 6 significant digits, as `vmas eval` prints them.
json eval_figures(const EvalResult& result, const OpeningReach* openings = nullptr);
// A figure as the summaries print it: 6 significant digits; and as their JSON number.
std::string figure_text(double value);
double significant(double value);

// The `topology` object of both summaries (skeletonize's and eval's): the input's genus per
// piece when known (`input_genus`: null and `input_genus_unknown` saying why otherwise), and the
// medial mesh's Betti numbers and duplicate triangles.
json topology_summary(const MedialTopology& medial, const SurfaceGenus& input);
// The summaries' line of it: "topology: the skeleton has 1 piece, 3 loops, 0 cavities; the
// shape: 1 piece of genus 3" (or "genus unknown (why)").
std::string topology_line(const json& topology);
// An edit session's `topology` object (`vmas edit`'s state event, Python's EditSession.snapshot):
// topology_summary, and what the page marks: the loops beyond the input's genus and the triangles
// that close cavities, by sphere index into the snapshot's mesh.
json edit_topology_summary(const EditSnapshot& snapshot);

}  // namespace vmas::cli
