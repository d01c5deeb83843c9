#include "vmas/edit_session.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <string>
#include <thread>

#include "eval/envelope.hpp"
#include "optimise/partition.hpp"
#include "optimise/topology.hpp"
#include "vmas/error.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace vmas {

namespace {

using Clock = std::chrono::steady_clock;

// A settled skeleton is still stepped (edits nearby must re-settle it), but no faster than the
// page is updated (30/s): spheres may trade a few vertices for ever without converging, and an
// editor left open would otherwise keep a core busy for nothing.
constexpr auto kSettledStepPause = std::chrono::milliseconds(33);
// A settled skeleton is measured at most this often (the page shows the error).
constexpr auto kMeasureInterval = std::chrono::seconds(2);

// Whether two meshes are the same to the bit (the topology of one is that of the other).
bool same_mesh(const MedialMesh& a, const MedialMesh& b) {
  return a.edges == b.edges && a.faces == b.faces &&
         std::equal(a.spheres.begin(), a.spheres.end(), b.spheres.begin(), b.spheres.end(),
                    same_sphere);
}

}  // namespace

// The session behind EditSession: the worker thread, the queue of edits and the undo history.
struct EditSession::Impl {
  Impl(Shape shape, const SkeletonizerOptions& options, int threads, FinishOptions finish,
       SurfaceGenus input_genus);
  ~Impl();  // stops the worker

  struct Edit {
    enum class Kind {
      Remove,
      Split,
      Freeze,
      Target,
      TargetBy,
      Lambda,
      LambdaTimes,
      Pause,
      Undo,
      Redo,
      Finish,
      PaintDensity,
      SetDensity
    } kind;
    std::vector<std::uint64_t> keys;  // Remove, Freeze
    int value = 0;
    double number = 0.0;
    double amount = 0.0;          // PaintDensity (value: the vertex, number: the radius)
    std::vector<double> density = {};  // SetDensity
  };

  void enqueue(const Edit& edit);
  void check_key(std::uint64_t key) const;  // caller holds mutex_
  void work();
  bool apply(const Edit& edit);  // worker thread; false when its sphere is gone
  bool apply_one(const Edit& edit);  // apply() without the history
  void apply_target(int count);  // worker thread: the count target, reached at once when fewer
  bool apply_finish();           // worker thread; false when cancelled (the state as before)
  // Worker thread, during a finish: publishes its phase and fraction (the spheres stay those of
  // the last snapshot); false when the finish is to stop (cancelled, or the session ends).
  bool finish_progress(const char* phase, double fraction);
  bool adopt_fresh_run_if_better();  // worker thread, in apply_finish(); false when cancelled
  double measure();              // worker thread: the error now, relative to the diagonal
  // What undo() brings back: the skeleton, the targets and the density of a moment (moments
  // share a density until it is painted).
  struct Moment {
    SkeletonizerState state;
    Target target;
    double lambda = 0.0;
    std::shared_ptr<const std::vector<double>> density;
  };
  void use_density(std::shared_ptr<const std::vector<double>> density);  // worker thread
  bool paint_density(int vertex, double radius, double amount);  // worker; false: all would be 0
  Moment moment() const;            // worker thread
  void go_back_to(const Moment& m);  // worker thread
  void publish(double steps_per_second);
  void update_topology(const MedialMesh& mesh);  // worker thread

  std::unique_ptr<Skeletonizer> skeletonizer_;
  const int threads_;
  const int most_spheres_;  // max_spheres, or the vertex count if fewer (read by callers)
  bool paused_ = false;  // worker's copy
  int iteration_ = 0;
  std::size_t dropped_ = 0;
  std::deque<Moment> undo_, redo_;  // worker's: the newest last
  std::shared_ptr<const std::vector<double>> density_;  // worker's: the shape's (null: none)
  std::uint64_t density_changes_ = 0;                   // worker's
  FinishOptions finish_options_;
  std::unique_ptr<Evaluator> evaluator_;  // worker's, built by the first finish
  int finishes_ = 0;                      // worker's
  bool finished_ = false;
  bool hand_edited_ = false;  // worker's: a sphere split, removed or frozen, or an undo/redo
  double error_before_finish_ = 0.0, error_after_finish_ = 0.0;
  double measured_error_ = 0.0;
  int measured_at_iteration_ = -1;
  const SurfaceGenus input_genus_;
  // Worker's: the topology of topology_mesh_ (that of an empty mesh to start with: its
  // defaults), kept while the published mesh stays the same.
  MedialMesh topology_mesh_;
  MedialTopology topology_;
  std::vector<std::vector<int>> extra_loops_;

  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::deque<Edit> pending_;
  EditSnapshot published_;
  bool stop_ = false;
  bool finishing_ = false;         // a finish asked for and not done or cancelled
  bool cancel_finish_ = false;     // cancel_finish() asked to stop it
  int cancelled_finishes_ = 0;
  std::thread worker_;
};

EditSession::Impl::Impl(Shape shape, const SkeletonizerOptions& options, int threads,
                        FinishOptions finish, SurfaceGenus input_genus)
    : skeletonizer_(std::make_unique<Skeletonizer>(std::move(shape), options)),
      threads_(threads),
      most_spheres_(std::min(options.max_spheres, skeletonizer_->shape().size())),
      finish_options_(std::move(finish)),
      input_genus_(std::move(input_genus)) {
  if (threads < 0) throw InvalidOption("threads", "must be 0 or more");
  finish_options_.refine.validate();
  skeletonizer_->pass_over_settled(true);  // a session steps on for ever once settled
  if (finish_options_.surface.points.empty()) {
    finish_options_.surface.points = skeletonizer_->shape().points;
    finish_options_.surface.normals = skeletonizer_->shape().normals;
  }
  if (!skeletonizer_->shape().density.empty())
    density_ = std::make_shared<const std::vector<double>>(skeletonizer_->shape().density);
  publish(0.0);
  worker_ = std::thread([this] { work(); });
}

EditSession::Impl::~Impl() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  worker_.join();
}

void EditSession::Impl::check_key(std::uint64_t key) const {
  const auto& keys = published_.keys;
  if (std::find(keys.begin(), keys.end(), key) == keys.end())
    throw InvalidArgument("no sphere with key " + std::to_string(key));
}

void EditSession::Impl::enqueue(const Edit& edit) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (std::uint64_t key : edit.keys) check_key(key);
    if (pending_.size() >= kMaxPendingEdits)
      throw InvalidArgument("too many edits waiting (" + std::to_string(kMaxPendingEdits) + ")");
    pending_.push_back(edit);
    if (edit.kind == Edit::Kind::Finish) {  // said at once: the worker may be mid-step
      finishing_ = true;
      cancel_finish_ = false;
      published_.finishing = true;
      published_.finish_phase = "waiting";
      published_.finish_fraction = 0.0;
      ++published_.version;
    }
  }
  changed_.notify_all();
}

void EditSession::remove(const std::vector<std::uint64_t>& keys) {
  impl_->enqueue({Impl::Edit::Kind::Remove, keys});
}

void EditSession::split_at(int vertex) {
  if (vertex < 0 || vertex >= shape().size())
    throw InvalidArgument("no vertex with index " + std::to_string(vertex));
  impl_->enqueue({Impl::Edit::Kind::Split, {}, vertex});
}

void EditSession::paint_density(int vertex, double radius, double amount) {
  if (vertex < 0 || vertex >= shape().size())
    throw InvalidArgument("no vertex with index " + std::to_string(vertex));
  if (!(radius > 0.0 && radius <= 1.0))
    throw InvalidOption("radius", "must be in (0, 1], a fraction of the diagonal (got " +
                                      std::to_string(radius) + ")");
  if (!(std::abs(amount) <= kMaxDensityStroke))
    throw InvalidOption("amount", "must be between -" + std::to_string(kMaxDensityStroke) +
                                      " and " + std::to_string(kMaxDensityStroke));
  Impl::Edit edit{Impl::Edit::Kind::PaintDensity, {}, vertex, radius};
  edit.amount = amount;
  impl_->enqueue(edit);
}

void EditSession::set_density(std::vector<double> density) {
  if (!density.empty()) {
    try {
      check_density(density, shape().points.size());
    } catch (const InvalidInput& e) {
      throw InvalidArgument(e.what());
    }
  }
  Impl::Edit edit{Impl::Edit::Kind::SetDensity, {}};
  edit.density = std::move(density);
  impl_->enqueue(edit);
}

void EditSession::freeze(const std::vector<std::uint64_t>& keys, bool frozen) {
  impl_->enqueue({Impl::Edit::Kind::Freeze, keys, frozen ? 1 : 0});
}

void EditSession::set_target_spheres(int count) {
  if (count < 1 || count > impl_->most_spheres_)
    throw InvalidOption("count", "must be between 1 and " + std::to_string(impl_->most_spheres_) +
                                     " (got " + std::to_string(count) + ")");
  impl_->enqueue({Impl::Edit::Kind::Target, {}, count});
}

void EditSession::set_lambda(double lambda) {
  SkeletonizerOptions::check_lambda("lambda", lambda);
  impl_->enqueue({Impl::Edit::Kind::Lambda, {}, 0, lambda});
}

void EditSession::change_target_spheres(int by) {
  impl_->enqueue({Impl::Edit::Kind::TargetBy, {}, by});
}

void EditSession::scale_lambda(double factor) {
  if (!(factor > 0.0 && factor <= SkeletonizerOptions::kMaxLambda))
    throw InvalidOption("lambda", "factor must be in (0, 1e6] (got " + std::to_string(factor) + ")");
  impl_->enqueue({Impl::Edit::Kind::LambdaTimes, {}, 0, factor});
}

void EditSession::undo() { impl_->enqueue({Impl::Edit::Kind::Undo, {}}); }

void EditSession::redo() { impl_->enqueue({Impl::Edit::Kind::Redo, {}}); }

void EditSession::pause(bool paused) {
  impl_->enqueue({Impl::Edit::Kind::Pause, {}, paused ? 1 : 0});
}

void EditSession::finish() { impl_->enqueue({Impl::Edit::Kind::Finish, {}}); }

bool EditSession::finishing() const {
  const std::lock_guard<std::mutex> lock(impl_->mutex_);
  return impl_->finishing_;
}

void EditSession::cancel_finish() {
  {
    const std::lock_guard<std::mutex> lock(impl_->mutex_);
    if (!impl_->finishing_) return;
    impl_->cancel_finish_ = true;
  }
  impl_->changed_.notify_all();
}

EditSnapshot EditSession::snapshot() const {
  std::lock_guard<std::mutex> lock(impl_->mutex_);
  return impl_->published_;
}

std::uint64_t EditSession::wait_for_version(std::uint64_t version, int timeout_ms) const {
  std::unique_lock<std::mutex> lock(impl_->mutex_);
  impl_->changed_.wait_for(lock, std::chrono::milliseconds(timeout_ms), [&] {
    return impl_->published_.version > version || impl_->stop_;
  });
  return impl_->published_.version;
}

EditSession::Impl::Moment EditSession::Impl::moment() const {
  const Skeletonizer& s = *skeletonizer_;
  return {s.state(), s.options().target, s.options().lambda, density_};
}

void EditSession::Impl::go_back_to(const Moment& m) {
  Skeletonizer& s = *skeletonizer_;
  s.restore(m.state);
  s.set_target(m.target);
  s.set_lambda(m.lambda);
  if (m.density != density_) use_density(m.density);
}

void EditSession::Impl::use_density(std::shared_ptr<const std::vector<double>> density) {
  skeletonizer_->set_density(density ? *density : std::vector<double>());
  density_ = std::move(density);
  ++density_changes_;
}

bool EditSession::Impl::paint_density(int vertex, double radius, double amount) {
  const Shape& shape = skeletonizer_->shape();
  std::vector<double> painted =
      density_ ? *density_ : std::vector<double>(shape.points.size(), 1.0);
  // A smooth bump: `amount` at the vertex, nothing from `radius` (of the diagonal) on.
  const double reach = radius * shape.diagonal;
  for (int v = 0; v < shape.size(); ++v) {
    const double distance = (shape.points[v] - shape.points[vertex]).norm();
    if (distance >= reach) continue;
    const double falloff = 1.0 - (distance / reach) * (distance / reach);
    painted[v] = std::max(0.0, painted[v] + amount * falloff * falloff);
  }
  if (std::none_of(painted.begin(), painted.end(), [](double d) { return d > 0.0; })) return false;
  use_density(std::make_shared<const std::vector<double>>(std::move(painted)));
  return true;
}

bool EditSession::Impl::apply(const Edit& edit) {
  // Undo and redo move between moments; any other edit (but pause) is a moment of its own.
  if (edit.kind == Edit::Kind::Undo || edit.kind == Edit::Kind::Redo) {
    auto& from = edit.kind == Edit::Kind::Undo ? undo_ : redo_;
    auto& to = edit.kind == Edit::Kind::Undo ? redo_ : undo_;
    if (from.empty()) return false;
    finished_ = false;
    hand_edited_ = true;
    to.push_back(moment());
    go_back_to(from.back());
    from.pop_back();
    return true;
  }
  if (edit.kind == Edit::Kind::Pause) return apply_one(edit);
  Moment before = moment();
  // Nothing to take back (a cancelled finish left everything as it was: not a dropped edit).
  if (!apply_one(edit)) return edit.kind == Edit::Kind::Finish;
  if (edit.kind != Edit::Kind::Finish) finished_ = false;
  // A fresh run knows nothing of these (it runs on the prepared shape as it came).
  hand_edited_ = hand_edited_ || edit.kind == Edit::Kind::Remove ||
                 edit.kind == Edit::Kind::Split || edit.kind == Edit::Kind::Freeze ||
                 edit.kind == Edit::Kind::PaintDensity || edit.kind == Edit::Kind::SetDensity;
  undo_.push_back(std::move(before));
  if (static_cast<int>(undo_.size()) > kUndoSteps) undo_.pop_front();
  redo_.clear();
  return true;
}

bool EditSession::Impl::apply_one(const Edit& edit) {
  Skeletonizer& s = *skeletonizer_;
  const auto count = [&] { return static_cast<int>(s.spheres().size()); };
  switch (edit.kind) {
    case Edit::Kind::Remove: {
      std::vector<int> ids;  // of the spheres still there and not frozen
      for (std::uint64_t key : edit.keys) {
        const int id = s.id_of(key);
        if (id >= 0 && !s.frozen(id)) ids.push_back(id);
      }
      std::sort(ids.begin(), ids.end());
      ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
      if (ids.empty() || static_cast<int>(ids.size()) >= count()) return false;
      for (auto id = ids.rbegin(); id != ids.rend(); ++id) s.remove_sphere(*id);
      // The user chose the count: removed spheres stay removed, growth asked for stays asked.
      const int target = s.options().target.count();
      s.set_target(Target{target > 0 ? std::max(1, target - static_cast<int>(ids.size())) : count()});
      return true;
    }
    case Edit::Kind::Split:
      if (count() >= most_spheres_) return false;
      s.add_sphere_at(edit.value);
      s.set_target(Target{std::max(s.options().target.count(), count())});
      return true;
    case Edit::Kind::Freeze: {
      bool any = false;
      for (std::uint64_t key : edit.keys) {
        const int id = s.id_of(key);
        if (id < 0) continue;
        s.freeze(id, edit.value != 0);
        any = true;
      }
      return any;
    }
    case Edit::Kind::Target:
      apply_target(edit.value);
      return true;
    case Edit::Kind::TargetBy: {
      const int now = s.options().target.count() > 0 ? s.options().target.count() : count();
      const long long wanted = static_cast<long long>(now) + edit.value;
      apply_target(static_cast<int>(std::clamp<long long>(wanted, 1, most_spheres_)));
      return true;
    }
    case Edit::Kind::Lambda:
      s.set_lambda(edit.number);
      return true;
    case Edit::Kind::LambdaTimes:
      s.set_lambda(std::min(s.options().lambda * edit.number, SkeletonizerOptions::kMaxLambda));
      return true;
    case Edit::Kind::Pause:
      paused_ = edit.value != 0;
      return true;
    case Edit::Kind::Finish:
      return apply_finish();
    case Edit::Kind::PaintDensity:
      return paint_density(edit.value, edit.number, edit.amount);
    case Edit::Kind::SetDensity:
      use_density(edit.density.empty() ? nullptr
                                       : std::make_shared<const std::vector<double>>(edit.density));
      return true;
    case Edit::Kind::Undo:
    case Edit::Kind::Redo:
      break;  // apply() takes them
  }
  return true;
}

void EditSession::Impl::apply_target(int target) {
  Skeletonizer& s = *skeletonizer_;
  s.set_target(Target{target});
  // Fewer spheres at once: the smallest unfrozen clusters go (they cover the least).
  while (static_cast<int>(s.spheres().size()) > target) {
    const int count = static_cast<int>(s.spheres().size());
    std::vector<int> sizes(count, 0);
    for (int label : s.labels()) ++sizes[label];
    int smallest = -1;
    for (int id = 0; id < count; ++id)
      if (!s.frozen(id) && (smallest < 0 || sizes[id] < sizes[smallest])) smallest = id;
    if (smallest < 0) break;  // every sphere left is frozen
    s.remove_sphere(smallest);
  }
}

double EditSession::Impl::measure() {
  const Skeletonizer& s = *skeletonizer_;
  if (!evaluator_)  // a tree over the surface: built once, by the first measurement
    evaluator_ = std::make_unique<Evaluator>(finish_options_.surface, finish_options_.measure);
  return (*evaluator_)(s.adjacency_mesh()).hausdorff / s.shape().diagonal;
}

bool EditSession::Impl::finish_progress(const char* phase, double fraction) {
  bool go_on = true;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    go_on = !stop_ && !cancel_finish_;
    published_.finishing = true;
    published_.finish_phase = phase;
    published_.finish_fraction = fraction;
    ++published_.version;
  }
  changed_.notify_all();
  return go_on;
}

bool EditSession::Impl::apply_finish() {
  Skeletonizer& s = *skeletonizer_;
  const SkeletonizerState start = s.state();
  const double measured_before = measured_error_;
  const int measured_at_before = measured_at_iteration_;
  // Ends the finish: done, or cancelled with everything as it was before.
  const auto end = [&](bool done) {
    if (!done) {
      s.restore(start);
      measured_error_ = measured_before;
      measured_at_iteration_ = measured_at_before;
    }
    const std::lock_guard<std::mutex> lock(mutex_);
    finishing_ = cancel_finish_ = false;
    if (!done) ++cancelled_finishes_;
    return done;
  };
  if (!finish_progress("measuring", 0.0)) return end(false);
  error_before_finish_ = measure();
  const FinishReport finished = finish_skeleton(
      s, *evaluator_, finish_options_.refine, /*refitted=*/false, [&](const Progress& p) {
        return finish_progress(
            p.phase == Progress::Phase::FinalRefit ? "final refits" : "refining", p.fraction);
      });
  if (finished.cancelled) return end(false);
  error_after_finish_ = finished.error / s.shape().diagonal;
  // The refinement only keeps moves that help, but the refits before it may not: a finish never
  // leaves the skeleton worse than it found it.
  if (error_after_finish_ > error_before_finish_) {
    s.restore(start);
    error_after_finish_ = error_before_finish_;
  }
  if (finish_options_.fresh_run && !hand_edited_ && !adopt_fresh_run_if_better())
    return end(false);
  ++finishes_;
  finished_ = true;
  paused_ = true;  // steps would undo the final refits
  measured_error_ = error_after_finish_;
  measured_at_iteration_ = iteration_;
  return end(true);
}

bool EditSession::Impl::adopt_fresh_run_if_better() {
  Skeletonizer& s = *skeletonizer_;
  const ProgressCallback until_stopped = [this](const Progress& p) {
    return finish_progress("fresh run", p.phase == Progress::Phase::OtherStarts ? p.fraction : 0.0);
  };
  BestStart fresh;
  try {
    fresh = finish_options_.fresh_run(s.options(), until_stopped);
  } catch (const Cancelled&) {
    return false;
  } catch (const std::exception&) {
    return true;  // it could not run: the live skeleton stays (it is a result)
  }
  if (!(fresh.measured_error < error_after_finish_)) return true;
  try {
    s.restore(fresh.state);
  } catch (const InvalidArgument&) {
    return true;  // not a state of this shape: a callback run on another
  }
  error_after_finish_ = fresh.measured_error;
  return true;
}

void EditSession::Impl::publish(double steps_per_second) {
  const Skeletonizer& s = *skeletonizer_;
  EditSnapshot next;
  next.iteration = iteration_;
  next.steps_per_second = steps_per_second;
  next.error = s.total_error();
  next.paused = paused_;
  next.target_spheres = s.options().target.count();
  next.lambda = s.options().lambda;
  next.keys = s.keys();
  next.spheres = s.spheres();
  for (std::size_t id = 0; id < s.spheres().size(); ++id)
    next.frozen.push_back(s.frozen(static_cast<int>(id)));
  next.labels = s.labels();
  next.mesh = s.medial_mesh();
  next.dropped_edits = dropped_;
  next.undo_steps = static_cast<int>(undo_.size());
  next.redo_steps = static_cast<int>(redo_.size());
  next.finishes = finishes_;
  next.finished = finished_;
  next.error_before_finish = error_before_finish_;
  next.error_after_finish = error_after_finish_;
  next.measured_error = measured_error_;
  next.measured_at_iteration = measured_at_iteration_;
  next.density = density_;
  next.density_changes = density_changes_;
  update_topology(next.mesh);
  next.topology = topology_;
  next.input_genus = input_genus_;
  next.extra_loops = extra_loops_;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    next.version = published_.version + 1;
    next.finishing = finishing_;
    if (finishing_) next.finish_phase = "waiting";
    next.cancelled_finishes = cancelled_finishes_;
    published_ = std::move(next);
  }
  changed_.notify_all();
}

// The elimination over Z/2 (and the search for extra loops) only for a mesh that changed: a
// paused or settled skeleton publishes the same one again and again.
void EditSession::Impl::update_topology(const MedialMesh& mesh) {
  if (same_mesh(mesh, topology_mesh_)) return;
  topology_ = medial_topology(mesh);
  extra_loops_.clear();
  if (input_genus_.known && topology_.loops > input_genus_.handles())
    extra_loops_ = extra_loops(mesh, input_genus_.handles());
  topology_mesh_ = mesh;
}

void EditSession::Impl::work() {
#ifdef _OPENMP
  if (threads_ > 0) omp_set_num_threads(threads_);  // per thread: this one runs every step
#endif
  Skeletonizer& s = *skeletonizer_;
  s.restart_schedule();
  auto last_step = Clock::now();
  auto last_measure = Clock::time_point();
  for (;;) {
    std::deque<Edit> edits;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      // Paused: sleep until an edit or the end comes.
      changed_.wait(lock, [&] { return stop_ || !pending_.empty() || !paused_; });
      if (stop_) return;
      edits.swap(pending_);
    }
    bool edited = false;
    for (const Edit& edit : edits) {
      bool applied = false;
      try {
        applied = apply(edit);
      } catch (const std::exception&) {
        // Checked when queued; what can still fail here leaves the state as it was.
      }
      if (applied)
        edited = true;
      else
        ++dropped_;
    }
    if (edited) s.restart_schedule();
    if (paused_) {
      publish(0.0);
      continue;
    }
    const Turn turn = s.advance();
    finished_ = false;
    if (turn.done && Clock::now() - last_measure >= kMeasureInterval) {
      measured_error_ = measure();
      measured_at_iteration_ = iteration_ + 1;
      last_measure = Clock::now();
    }
    const auto now = Clock::now();
    const double seconds = std::chrono::duration<double>(now - last_step).count();
    last_step = now;
    ++iteration_;
    publish(seconds > 0.0 ? 1.0 / seconds : 0.0);
    if (turn.done) {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait_for(lock, kSettledStepPause, [&] { return stop_ || !pending_.empty(); });
    }
  }
}

EditSession::EditSession(Shape shape, const SkeletonizerOptions& options, int threads,
                         FinishOptions finish, SurfaceGenus input_genus)
    : impl_(std::make_unique<Impl>(std::move(shape), options, threads, std::move(finish),
                                   std::move(input_genus))) {}
EditSession::~EditSession() = default;

const Shape& EditSession::shape() const { return impl_->skeletonizer_->shape(); }

FinishOptions finish_as_skeletonize_does(const PreparedShape& prepared, const Options& options) {
  FinishOptions finish{prepared.surface, options.refine,
                       refinement_eval_options(prepared), {}};
  // Held by the callback, which only the session's worker calls (one finish at a time).
  auto fresh = std::make_shared<PreparedShape>(prepared);
  finish.fresh_run = [fresh, options](const SkeletonizerOptions& now,
                                      const ProgressCallback& progress) {
    fresh->run = now;
    return best_start(*fresh, options, progress);
  };
  return finish;
}

std::vector<float> EditSession::vertex_errors(const MedialMesh& mesh) const {
  const Shape& s = shape();
  const std::vector<double> distances = envelope_distances(mesh, s.points);
  std::vector<float> relative(distances.size());
  for (std::size_t v = 0; v < distances.size(); ++v)
    relative[v] = static_cast<float>(distances[v] / s.diagonal);
  return relative;
}

}  // namespace vmas
