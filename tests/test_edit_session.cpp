// The live-editing engine (vmas/edit_session.hpp): a worker thread optimises while the test
// thread edits, as a browser front end would.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <string>
#include <thread>

#include "optimise/topology.hpp"
#include "test_shapes.hpp"
#include "vmas/edit_session.hpp"
#include "vmas/error.hpp"
#include "vmas/vmas.hpp"

namespace vmas {
namespace {

std::unique_ptr<EditSession> capsule_session(int spheres, FinishOptions finish = {}) {
  const test::Sample s = test::sample_capsule(0.2, 1.0, 4000, 47);
  SurfaceInput cloud;
  cloud.points = s.points;
  cloud.normals = s.normals;
  SkeletonizerOptions options;
  options.target.spheres = spheres;
  return std::make_unique<EditSession>(build_shape(cloud, ShapeOptions{}), options, 0,
                                       std::move(finish));
}

// The first snapshot that satisfies `done`, waiting at most 20 s (then the last one).
EditSnapshot wait_until(const EditSession& session,
                        const std::function<bool(const EditSnapshot&)>& done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  EditSnapshot snapshot = session.snapshot();
  while (!done(snapshot) && std::chrono::steady_clock::now() < deadline) {
    session.wait_for_version(snapshot.version, 100);
    snapshot = session.snapshot();
  }
  return snapshot;
}

EditSnapshot settled(const EditSession& session, std::size_t spheres) {
  return wait_until(session, [&](const EditSnapshot& s) { return s.spheres.size() == spheres; });
}

TEST(EditSession, GrowsToItsTargetWhileRunningAndLabelsEveryVertex) {
  const auto session = capsule_session(8);
  const EditSnapshot s = settled(*session, 8);
  ASSERT_EQ(s.spheres.size(), 8u);
  EXPECT_EQ(s.keys.size(), 8u);
  EXPECT_EQ(s.frozen.size(), 8u);
  EXPECT_EQ(s.mesh.spheres.size(), 8u);
  EXPECT_EQ(s.labels.size(), static_cast<std::size_t>(session->shape().size()));
  for (int label : s.labels) {
    ASSERT_GE(label, 0);
    ASSERT_LT(label, 8);
  }
  EXPECT_GT(s.iteration, 0);
  // Settled, it measures its error every few seconds.
  const EditSnapshot measured =
      wait_until(*session, [](const EditSnapshot& s) { return s.measured_at_iteration >= 0; });
  ASSERT_GE(measured.measured_at_iteration, 0);
  EXPECT_GT(measured.measured_error, 0.0);
  EXPECT_LT(measured.measured_error, 0.2);
}

TEST(EditSession, RemovedSphereStaysRemovedAndASplitAddsOne) {
  const auto session = capsule_session(8);
  const EditSnapshot before = settled(*session, 8);
  const std::uint64_t gone = before.keys[3];
  session->remove(gone);
  const EditSnapshot after = settled(*session, 7);
  ASSERT_EQ(after.spheres.size(), 7u);
  EXPECT_EQ(std::count(after.keys.begin(), after.keys.end(), gone), 0);
  EXPECT_EQ(after.target_spheres, 7);
  // Later steps do not split it back.
  const EditSnapshot later = wait_until(
      *session, [&](const EditSnapshot& s) { return s.iteration >= after.iteration + 15; });
  EXPECT_EQ(later.spheres.size(), 7u);

  session->split_at(123);
  const EditSnapshot split = settled(*session, 8);
  ASSERT_EQ(split.spheres.size(), 8u);
  EXPECT_EQ(std::count_if(split.keys.begin(), split.keys.end(),
                          [&](std::uint64_t k) {
                            return std::find(later.keys.begin(), later.keys.end(), k) ==
                                   later.keys.end();
                          }),
            1);
}

TEST(EditSession, FrozenSphereDoesNotMove) {
  const auto session = capsule_session(6);
  const EditSnapshot start = settled(*session, 6);
  const std::uint64_t key = start.keys[2];
  session->freeze(key, true);
  const EditSnapshot frozen = wait_until(*session, [&](const EditSnapshot& s) {
    const auto at = std::find(s.keys.begin(), s.keys.end(), key) - s.keys.begin();
    return s.frozen[at];
  });
  const auto at = std::find(frozen.keys.begin(), frozen.keys.end(), key) - frozen.keys.begin();
  ASSERT_TRUE(frozen.frozen[at]);
  // A split elsewhere makes the others move; the frozen one keeps its place exactly.
  session->split_at(7);
  const EditSnapshot later = wait_until(
      *session, [&](const EditSnapshot& s) { return s.iteration >= frozen.iteration + 10; });
  const auto now = std::find(later.keys.begin(), later.keys.end(), key) - later.keys.begin();
  ASSERT_LT(now, static_cast<long>(later.keys.size()));
  EXPECT_EQ(later.spheres[now].center, frozen.spheres[at].center);
  EXPECT_EQ(later.spheres[now].radius, frozen.spheres[at].radius);
}

TEST(EditSession, BadEditsAreRejectedAndPausingStopsTheSteps) {
  const auto session = capsule_session(5);
  const EditSnapshot start = settled(*session, 5);
  EXPECT_THROW(session->remove(start.keys.back() + 1000), InvalidArgument);
  EXPECT_THROW(session->freeze(start.keys.back() + 1000, true), InvalidArgument);
  EXPECT_THROW(session->split_at(-1), InvalidArgument);
  EXPECT_THROW(session->split_at(session->shape().size()), InvalidArgument);
  EXPECT_THROW(session->set_target_spheres(0), InvalidOption);
  EXPECT_THROW(session->set_lambda(-1.0), InvalidOption);

  session->pause(true);
  const EditSnapshot paused = wait_until(*session, [](const EditSnapshot& s) { return s.paused; });
  ASSERT_TRUE(paused.paused);
  session->wait_for_version(paused.version, 300);
  EXPECT_EQ(session->snapshot().iteration, paused.iteration);
  // A flood of edits (a front end gone wild) while the worker is busy finishing (hundreds of
  // milliseconds): the queue takes kMaxPendingEdits and refuses the rest, nothing else.
  session->finish();
  std::size_t refused = 0;
  std::string refusal;
  for (int i = 0; i < 5000; ++i) {
    try {
      session->set_lambda(0.2);
    } catch (const InvalidArgument& e) {
      ++refused;
      refusal = e.what();
    }
  }
  EXPECT_GE(refused, 5000u - 2 * EditSession::kMaxPendingEdits);
  EXPECT_LT(refused, 5000u);
  EXPECT_NE(refusal.find("too many edits waiting"), std::string::npos) << refusal;
  // Once the worker has caught up, edits are taken again.
  bool resumed_ok = false;
  for (int attempt = 0; attempt < 100 && !resumed_ok; ++attempt) {
    try {
      session->pause(false);
      resumed_ok = true;
    } catch (const InvalidArgument&) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }
  ASSERT_TRUE(resumed_ok);
  const EditSnapshot resumed = wait_until(
      *session, [&](const EditSnapshot& s) { return s.iteration > paused.iteration + 2; });
  EXPECT_FALSE(resumed.paused);
  EXPECT_EQ(resumed.spheres.size(), 5u);
}

TEST(EditSession, ATargetBelowTheCountRemovesSpheresAtOnce) {
  const auto session = capsule_session(9);
  settled(*session, 9);
  session->set_target_spheres(4);
  const EditSnapshot s = settled(*session, 4);
  EXPECT_EQ(s.spheres.size(), 4u);
  EXPECT_EQ(s.target_spheres, 4);
}

// Undo takes edits back one by one (spheres, freezes, count, λ of that moment), redo makes them
// again; a new edit ends the redo.
TEST(EditSession, UndoTakesEditsBackAndRedoMakesThemAgain) {
  const auto session = capsule_session(6);
  const EditSnapshot start = settled(*session, 6);
  ASSERT_EQ(start.undo_steps, 0);
  session->pause(true);
  const EditSnapshot paused =
      wait_until(*session, [](const EditSnapshot& s) { return s.paused; });
  session->freeze(paused.keys[0], true);
  session->remove(paused.keys[3]);
  session->scale_lambda(2.0);
  const EditSnapshot edited =
      wait_until(*session, [](const EditSnapshot& s) { return s.undo_steps == 3; });
  ASSERT_EQ(edited.spheres.size(), 5u);
  EXPECT_TRUE(edited.frozen[0]);
  EXPECT_DOUBLE_EQ(edited.lambda, 2 * paused.lambda);

  for (int i = 0; i < 3; ++i) session->undo();
  const EditSnapshot undone =
      wait_until(*session, [](const EditSnapshot& s) { return s.redo_steps == 3; });
  EXPECT_EQ(undone.undo_steps, 0);
  EXPECT_EQ(undone.keys, paused.keys);
  EXPECT_EQ(undone.spheres.size(), paused.spheres.size());
  for (std::size_t i = 0; i < paused.spheres.size(); ++i)
    EXPECT_EQ(undone.spheres[i].center, paused.spheres[i].center);
  EXPECT_FALSE(undone.frozen[0]);
  EXPECT_EQ(undone.target_spheres, 6);
  EXPECT_DOUBLE_EQ(undone.lambda, paused.lambda);

  session->redo();
  const EditSnapshot redone =
      wait_until(*session, [](const EditSnapshot& s) { return s.redo_steps == 2; });
  EXPECT_TRUE(redone.frozen[0]);
  EXPECT_EQ(redone.spheres.size(), 6u);
  session->set_target_spheres(4);  // a new edit: nothing left to redo
  const EditSnapshot fresh =
      wait_until(*session, [](const EditSnapshot& s) { return s.spheres.size() == 4; });
  EXPECT_EQ(fresh.redo_steps, 0);
  EXPECT_EQ(fresh.undo_steps, 2);
  session->redo();  // nothing to make again: dropped, the state stays
  const EditSnapshot same = wait_until(
      *session, [&](const EditSnapshot& s) { return s.dropped_edits > fresh.dropped_edits; });
  EXPECT_EQ(same.spheres.size(), 4u);
}

// An action on a selection is one edit: several spheres removed or frozen, one undo step; a
// frozen sphere is not removed; a removal keeps the growth asked for before it.
TEST(EditSession, SeveralSpheresInOneEditOneUndoStepFrozenOnesStay) {
  const auto session = capsule_session(8);
  settled(*session, 8);
  session->pause(true);
  const EditSnapshot paused =
      wait_until(*session, [](const EditSnapshot& s) { return s.paused; });
  const std::vector<std::uint64_t> box = {paused.keys[1], paused.keys[2], paused.keys[5]};
  session->freeze(box, true);
  const EditSnapshot frozen =
      wait_until(*session, [](const EditSnapshot& s) { return s.undo_steps == 1; });
  EXPECT_TRUE(frozen.frozen[1] && frozen.frozen[2] && frozen.frozen[5]);
  EXPECT_EQ(std::count(frozen.frozen.begin(), frozen.frozen.end(), true), 3);
  session->freeze(std::vector<std::uint64_t>{paused.keys[5]}, false);
  // Four asked, one of them frozen: three go, in one edit.
  session->remove({paused.keys[0], paused.keys[2], paused.keys[3], paused.keys[4]});
  const EditSnapshot removed =
      wait_until(*session, [](const EditSnapshot& s) { return s.undo_steps == 3; });
  ASSERT_EQ(removed.spheres.size(), 5u);
  EXPECT_NE(std::find(removed.keys.begin(), removed.keys.end(), paused.keys[2]),
            removed.keys.end());
  EXPECT_EQ(removed.target_spheres, 5);
  session->undo();
  const EditSnapshot back =
      wait_until(*session, [](const EditSnapshot& s) { return s.undo_steps == 2; });
  EXPECT_EQ(back.keys, paused.keys);
  // Growth asked for (+2) and then a removal: the target is 8 + 2 - 1.
  session->change_target_spheres(2);
  session->remove(paused.keys[0]);
  const EditSnapshot grown =
      wait_until(*session, [](const EditSnapshot& s) { return s.undo_steps == 4; });
  EXPECT_EQ(grown.target_spheres, 9);
  // Only frozen spheres asked: nothing to do, dropped.
  session->remove(std::vector<std::uint64_t>{paused.keys[1]});
  const EditSnapshot same = wait_until(
      *session, [&](const EditSnapshot& s) { return s.dropped_edits > grown.dropped_edits; });
  EXPECT_EQ(same.spheres.size(), grown.spheres.size());
}

// A finish says where it is, and a cancel brings back the state before it
// (here its fresh run waits for the cancel, so that the test knows the finish is under way).
TEST(EditSession, AFinishShowsItsPhaseAndCanBeCancelled) {
  FinishOptions finish;
  finish.fresh_run = [](const SkeletonizerOptions&, const ProgressCallback& progress) -> BestStart {
    while (progress(Progress{})) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    throw Cancelled();
  };
  const auto session = capsule_session(6, std::move(finish));
  settled(*session, 6);
  session->pause(true);
  const EditSnapshot paused =
      wait_until(*session, [](const EditSnapshot& s) { return s.paused; });
  session->finish();
  EXPECT_TRUE(session->finishing());
  const EditSnapshot running = wait_until(
      *session, [](const EditSnapshot& s) { return s.finish_phase == "fresh run"; });
  EXPECT_TRUE(running.finishing);
  EXPECT_EQ(running.finish_phase, "fresh run");
  session->cancel_finish();
  const EditSnapshot cancelled =
      wait_until(*session, [](const EditSnapshot& s) { return s.cancelled_finishes == 1; });
  ASSERT_EQ(cancelled.cancelled_finishes, 1);
  EXPECT_FALSE(cancelled.finishing);
  EXPECT_FALSE(session->finishing());
  EXPECT_FALSE(cancelled.finished);
  EXPECT_EQ(cancelled.finishes, 0);
  EXPECT_TRUE(cancelled.paused);
  EXPECT_EQ(cancelled.undo_steps, paused.undo_steps);
  EXPECT_EQ(cancelled.dropped_edits, paused.dropped_edits);
  ASSERT_EQ(cancelled.spheres.size(), paused.spheres.size());
  for (std::size_t i = 0; i < paused.spheres.size(); ++i)
    EXPECT_EQ(cancelled.spheres[i].center, paused.spheres[i].center);
  session->split_at(0);
  const EditSnapshot split =
      wait_until(*session, [](const EditSnapshot& s) { return s.spheres.size() == 7; });
  EXPECT_EQ(split.spheres.size(), 7u);
  session->cancel_finish();  // nothing under way: nothing happens
}

TEST(EditSession, FinishRefitsAndRefinesKeepsFrozenSpheresAndPauses) {
  const auto session = capsule_session(8);
  const EditSnapshot start = settled(*session, 8);
  const std::uint64_t kept = start.keys[1];
  const auto index_of = [&](const EditSnapshot& s) {
    return std::find(s.keys.begin(), s.keys.end(), kept) - s.keys.begin();
  };
  session->pause(true);
  session->freeze(kept, true);
  const EditSnapshot frozen = wait_until(
      *session, [&](const EditSnapshot& s) { return s.paused && s.frozen[index_of(s)]; });
  ASSERT_TRUE(frozen.frozen[index_of(frozen)]);
  session->finish();
  const EditSnapshot done =
      wait_until(*session, [](const EditSnapshot& s) { return s.finishes == 1; });
  ASSERT_EQ(done.finishes, 1);
  EXPECT_TRUE(done.finished);
  EXPECT_TRUE(done.paused);  // steps would undo the final refits
  ASSERT_EQ(done.spheres.size(), 8u);
  EXPECT_GT(done.error_after_finish, 0.0);
  EXPECT_LE(done.error_after_finish, done.error_before_finish);
  // The frozen sphere did not move; the others did (final refits with a small λ).
  EXPECT_EQ(done.spheres[index_of(done)].center, frozen.spheres[index_of(frozen)].center);
  EXPECT_EQ(done.spheres[index_of(done)].radius, frozen.spheres[index_of(frozen)].radius);
  int moved = 0;
  for (std::size_t i = 0; i < done.spheres.size(); ++i)
    moved += done.spheres[i].center != frozen.spheres[i].center;
  EXPECT_GT(moved, 0);
  // Paused, the finished spheres stay as they are.
  session->wait_for_version(done.version, 300);
  EXPECT_EQ(session->snapshot().iteration, done.iteration);
  EXPECT_TRUE(session->snapshot().finished);
  // An edit of its own: undo brings the spheres of before back.
  session->undo();
  const EditSnapshot undone =
      wait_until(*session, [](const EditSnapshot& s) { return s.redo_steps == 1; });
  EXPECT_FALSE(undone.finished);
  EXPECT_EQ(undone.keys, frozen.keys);
  for (std::size_t i = 0; i < frozen.spheres.size(); ++i)
    EXPECT_EQ(undone.spheres[i].center, frozen.spheres[i].center);
}

// Finishing a session no hand has touched also runs vmas skeletonize's starts (with the count
// of that moment) and keeps the better; once a sphere was edited by hand, it does not.
TEST(EditSession, FinishingAnUntouchedSessionIsAtLeastAsGoodAsAFreshRun) {
  const test::Sample s = test::sample_capsule(0.2, 1.0, 4000, 47);
  SurfaceInput cloud;
  cloud.points = s.points;
  cloud.normals = s.normals;
  Options options;
  options.run.target.spheres = 8;
  options.threads = 1;
  const PreparedShape prepared = prepare_shape(cloud, options);
  FinishOptions finish = finish_as_skeletonize_does(prepared, options);
  int calls = 0, fresh_count = 0;
  double fresh_error = -1.0;
  const auto fresh_run = finish.fresh_run;
  finish.fresh_run = [&](const SkeletonizerOptions& now, const ProgressCallback& progress) {
    ++calls;
    fresh_count = now.target.count();
    const BestStart fresh = fresh_run(now, progress);
    fresh_error = fresh.measured_error;
    return fresh;
  };
  EditSession session(prepared.shape, prepared.run, 1, finish);
  settled(session, 8);
  session.change_target_spheres(1);  // the count may change: the fresh run has the new one
  settled(session, 9);
  session.finish();
  const EditSnapshot done = wait_until(session, [](const EditSnapshot& s) { return s.finishes == 1; });
  ASSERT_EQ(done.finishes, 1);
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(fresh_count, 9);
  ASSERT_EQ(done.spheres.size(), 9u);
  EXPECT_GT(fresh_error, 0.0);
  EXPECT_LE(done.error_after_finish, fresh_error);
  EXPECT_LE(done.error_after_finish, done.error_before_finish);

  session.remove(done.keys[0]);
  settled(session, 8);
  session.finish();
  const EditSnapshot again = wait_until(session, [](const EditSnapshot& s) { return s.finishes == 2; });
  ASSERT_EQ(again.finishes, 2);
  EXPECT_EQ(calls, 1);  // edited by hand: the user's spheres are finished, not replaced
}

}  // namespace
}  // namespace vmas

namespace vmas {
namespace {

TEST(EditSession, PaintedDensityDrawsSpheresAndUndoTakesItBack) {
  const auto session = capsule_session(12);
  const EditSnapshot before = settled(*session, 12);
  ASSERT_FALSE(before.density);
  const auto near_top = [](const EditSnapshot& s) {
    return std::count_if(s.spheres.begin(), s.spheres.end(),
                         [](const Sphere& sphere) { return sphere.center.z() > 0.75; });
  };
  // The vertex nearest the top cap.
  const Shape& shape = session->shape();
  int top = 0;
  for (int v = 0; v < shape.size(); ++v)
    if (shape.points[v].z() > shape.points[top].z()) top = v;
  session->paint_density(top, 0.3, 7.0);
  const EditSnapshot painted =
      wait_until(*session, [&](const EditSnapshot& s) { return s.density_changes > 0; });
  ASSERT_TRUE(painted.density);
  ASSERT_EQ(painted.density->size(), static_cast<std::size_t>(shape.size()));
  EXPECT_DOUBLE_EQ((*painted.density)[top], 8.0);  // 1 + 7 at the brush's centre
  EXPECT_EQ(*std::min_element(painted.density->begin(), painted.density->end()), 1.0);
  // The optimisation keeps the count and moves spheres where the density is high: the
  // removal of a few spheres makes them come back there.
  session->set_target_spheres(8);
  settled(*session, 8);
  session->set_target_spheres(12);
  const EditSnapshot regrown = wait_until(*session, [&](const EditSnapshot& s) {
    return s.spheres.size() == 12 && near_top(s) > near_top(before);
  });
  EXPECT_GT(near_top(regrown), near_top(before));
  // Three undos: the counts, then the painting.
  session->undo();
  session->undo();
  session->undo();
  const EditSnapshot undone = wait_until(
      *session, [&](const EditSnapshot& s) { return s.density_changes > painted.density_changes; });
  EXPECT_FALSE(undone.density);
  EXPECT_THROW(session->paint_density(-1, 0.3, 1.0), InvalidArgument);
  EXPECT_THROW(session->paint_density(top, 0.0, 1.0), InvalidOption);
  EXPECT_THROW(session->paint_density(top, 0.3, 1e9), InvalidOption);
  EXPECT_THROW(session->set_density(std::vector<double>(3, 1.0)), InvalidArgument);
  EXPECT_THROW(session->set_density(std::vector<double>(shape.size(), 0.0)), InvalidArgument);
}

// A snapshot's topology is medial_topology of its mesh, with the genus given; the loops beyond
// that genus are those extra_loops finds (a torus's loop is one when the genus is said to be 0).
TEST(EditSession, SnapshotsCarryTheirMeshsTopologyTheGenusAndTheExtraLoops) {
  Options options;
  options.run.target.spheres = 20;
  options.threads = 1;
  const PreparedShape prepared = prepare_shape(test::torus(1.0, 0.3, 48, 24), options);
  ASSERT_EQ(prepared.result.input_genus.genus, std::vector<int>{1});
  const auto has_its_loop = [](const EditSnapshot& s) {
    return s.spheres.size() == 20 && s.topology.components == 1 && s.topology.loops == 1;
  };
  const auto expect_its_meshs = [](const EditSnapshot& s) {
    const MedialTopology t = medial_topology(s.mesh);
    EXPECT_EQ(s.topology.components, t.components);
    EXPECT_EQ(s.topology.loops, t.loops);
    EXPECT_EQ(s.topology.cavities, t.cavities);
    EXPECT_EQ(s.topology.closing_triangles, t.closing_triangles);
  };
  {
    EditSession session(prepared.shape, prepared.run, 1, {}, prepared.result.input_genus);
    const EditSnapshot s = wait_until(session, has_its_loop);
    ASSERT_TRUE(has_its_loop(s));
    expect_its_meshs(s);
    EXPECT_TRUE(s.input_genus.known);
    EXPECT_EQ(s.input_genus.genus, std::vector<int>{1});
    EXPECT_TRUE(s.extra_loops.empty());
    EXPECT_EQ(s.topology.cavities, 0);  // left out (open_cavities)
    EXPECT_TRUE(s.topology.closing_triangles.empty());
    // Paused: a removal gives a mesh of its own, and λ keeps the mesh (and its topology).
    session.pause(true);
    session.remove(s.keys[0]);
    const EditSnapshot fewer =
        wait_until(session, [](const EditSnapshot& s) { return s.spheres.size() == 19; });
    ASSERT_EQ(fewer.spheres.size(), 19u);
    expect_its_meshs(fewer);
    session.set_lambda(0.5);
    const EditSnapshot same =
        wait_until(session, [](const EditSnapshot& s) { return s.lambda == 0.5; });
    ASSERT_EQ(same.lambda, 0.5);
    EXPECT_EQ(same.mesh.faces, fewer.mesh.faces);
    expect_its_meshs(same);
  }
  SurfaceGenus sphere;  // as if the torus were a sphere: its loop is one too many
  sphere.known = true;
  sphere.genus = {0};
  EditSession session(prepared.shape, prepared.run, 1, {}, sphere);
  const EditSnapshot s = wait_until(session, has_its_loop);
  ASSERT_TRUE(has_its_loop(s));
  expect_its_meshs(s);
  ASSERT_EQ(s.extra_loops.size(), 1u);
  EXPECT_EQ(s.extra_loops, extra_loops(s.mesh, 0));
  EXPECT_GE(s.extra_loops[0].size(), 3u);
  // A cloud's genus is unknown: no loop is extra.
  const auto cloud = capsule_session(6);
  const EditSnapshot c = settled(*cloud, 6);
  EXPECT_FALSE(c.input_genus.known);
  EXPECT_TRUE(c.extra_loops.empty());
  expect_its_meshs(c);
}

}  // namespace
}  // namespace vmas
