"""`import vmas`: arrays in every dtype and order, bad arrays, meshes and clouds, options, files,
the same bytes as the CLI, Ctrl-C, and no leak. Run by ctest (PYTHONPATH=build/python)."""

import os
import resource
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import vmas

VMAS_CLI = os.environ.get("VMAS_CLI", "")
CORPUS = os.path.join(os.path.dirname(__file__), "..", "corpus")


def sphere_points(n, seed=1):
    p = np.random.default_rng(seed).normal(size=(n, 3))
    return p / np.linalg.norm(p, axis=1)[:, None]


def capsule_points(n, seed=2):
    """Points on a capsule of radius 0.2 along x from -0.5 to 0.5, and their outward normals."""
    rng = np.random.default_rng(seed)
    points, normals = [], []
    while len(points) < n:
        q = rng.uniform([-0.7, -0.2, -0.2], [0.7, 0.2, 0.2])
        axis = np.array([np.clip(q[0], -0.5, 0.5), 0.0, 0.0])
        d = q - axis
        if np.linalg.norm(d) < 1e-9:
            continue
        normal = d / np.linalg.norm(d)
        points.append(axis + 0.2 * normal)
        normals.append(normal)
    return np.array(points), np.array(normals)


def test_every_real_dtype_and_order_gives_the_same_skeleton():
    points, normals = capsule_points(3000)
    reference = vmas.skeletonize(points, normals, spheres=6, threads=1)
    for variant in (points.astype(np.float32), np.asfortranarray(points), points[::1].copy(order="F"),
                    np.ascontiguousarray(points)):
        if variant.dtype == np.float32:
            continue  # float32 rounds the coordinates: checked below for the sphere count only
        result = vmas.skeletonize(variant, normals, spheres=6, threads=1)
        np.testing.assert_array_equal(result.centers, reference.centers)
    single = vmas.skeletonize(points.astype(np.float32), normals.astype(np.float32), spheres=6)
    assert single.centers.shape == (6, 3)
    assert np.abs(single.centers[:, 1:]).max() < 0.05  # on the capsule's axis
    as_ints = vmas.skeletonize((points * 1000).astype(np.int64), spheres=4)
    assert as_ints.centers.shape == (4, 3)


def test_result_arrays_and_dicts():
    points, normals = capsule_points(2000)
    result = vmas.skeletonize(points, normals, spheres=5)
    assert result.centers.shape == (5, 3) and result.centers.dtype == np.float64
    assert result.radii.shape == (5,) and np.all(result.radii > 0.1) and np.all(result.radii < 0.3)
    assert result.edges.ndim == 2 and result.edges.shape[1] == 2
    assert result.faces.ndim == 2 and result.faces.shape[1] == 3
    assert result.labels.shape == (2000,) and set(np.unique(result.labels)) <= set(range(5))
    assert result.summary["spheres"] == 5
    assert result.seconds["total"] > 0
    d = result.to_dict()
    assert set(d) >= {"centers", "radii", "edges", "faces", "labels", "warnings", "summary"}
    assert all(isinstance(w, tuple) and len(w) == 2 for w in result.warnings)


def test_nan_points_are_dropped_and_labelled_minus_one():
    points = sphere_points(1500)
    points[[3, 700, 1499]] = np.nan
    result = vmas.skeletonize(points, spheres=2)
    assert list(result.labels[[3, 700, 1499]]) == [-1, -1, -1]
    assert (result.labels >= 0).sum() == 1497


@pytest.mark.parametrize("bad", [np.zeros((10, 2)), np.zeros((0, 3)), np.zeros(30),
                                 np.zeros((4, 3, 1)), [[0, 0, 0], [1, 1]], "points",
                                 np.array([["a", "b", "c"]])])
def test_bad_arrays_are_value_errors(bad):
    with pytest.raises(ValueError):
        vmas.skeletonize(bad, spheres=2)


def test_normals_and_faces_must_fit():
    points = sphere_points(100)
    with pytest.raises(ValueError, match="one row per point"):
        vmas.skeletonize(points, points[:50], spheres=2)
    with pytest.raises(ValueError):
        vmas.skeletonize(points, faces=np.array([[0, 1, 2.5]]), spheres=2)
    with pytest.raises(ValueError):
        vmas.skeletonize(points, faces=np.array([[0, 1, 500]]), spheres=2)


def test_options_are_the_clis_with_its_messages():
    points = sphere_points(800)
    with pytest.raises(vmas.InvalidOption, match="lambda"):
        vmas.skeletonize(points, spheres=3, lambda_=-1)
    with pytest.raises(ValueError, match="lambda"):
        vmas.skeletonize(points, spheres=3, **{"lambda": -1})
    with pytest.raises(ValueError, match="error cannot go with spheres"):
        vmas.skeletonize(points, spheres=3, error=0.01)
    with pytest.raises(ValueError, match="denoise"):
        vmas.skeletonize(points, spheres=3, denoise="much")
    with pytest.raises(vmas.InvalidInput):
        vmas.skeletonize(points[:5], spheres=40)
    fine = vmas.skeletonize(points, spheres=3, lambda_=0.1, denoise="off", final_rounds=0,
                            no_projection=False, estimate_normals=True)
    assert fine.centers.shape == (3, 3)


def test_a_mesh_stays_a_mesh_and_files_round_trip(tmp_path):
    surface = vmas.read(os.path.join(CORPUS, "seed_icosphere.off"))
    assert surface.points.shape == (42, 3) and surface.faces.shape == (80, 3)
    from_surface = vmas.skeletonize(surface, spheres=4)
    from_arrays = vmas.skeletonize(surface.points, faces=surface.faces, spheres=4)
    np.testing.assert_array_equal(from_surface.centers, from_arrays.centers)
    assert from_surface.summary["enclosure"] == pytest.approx(1.0, abs=0.05)
    path = str(tmp_path / "s.ply")
    vmas.write(path, from_surface)
    back = vmas.read_medial(path)
    np.testing.assert_allclose(back.centers, from_surface.centers, rtol=1e-6)
    figures = vmas.evaluate(surface, from_surface)
    assert 0 < figures["hausdorff_percent"] < 20
    with pytest.raises(OSError, match="no such file"):
        vmas.read(str(tmp_path / "missing.ply"))
    with pytest.raises(OSError):
        vmas.write(str(tmp_path / "no" / "folder.ply"), from_surface)


@pytest.mark.skipif(not VMAS_CLI, reason="VMAS_CLI (the vmas binary) not given")
def test_the_same_bytes_as_the_cli(tmp_path):
    for name, options in (("seed_icosphere.off", ["--spheres", "5"]),
                          ("seed_sphere_normals.xyz", ["--spheres", "3", "--lambda", "0.1"])):
        source = os.path.join(CORPUS, name)
        cli = str(tmp_path / "cli.ply")
        subprocess.run([VMAS_CLI, "skeletonize", source, "-o", cli, "-q"] + options, check=True)
        keywords = {options[i][2:].replace("-", "_"): float(options[i + 1])
                    for i in range(0, len(options), 2)}
        keywords["spheres"] = int(keywords["spheres"])
        mine = str(tmp_path / "py.ply")
        vmas.write(mine, vmas.skeletonize(vmas.read(source), **keywords))
        assert open(cli, "rb").read() == open(mine, "rb").read(), name


def test_progress_is_called_and_can_cancel():
    points = sphere_points(3000)
    phases = []
    vmas.skeletonize(points, spheres=8, progress=lambda phase, f: phases.append((phase, f)))
    assert {p for p, _ in phases} >= {"preparing", "optimising", "settling", "final_refit",
                                      "refining", "other_starts"}
    assert all(0.0 <= f <= 1.0 for _, f in phases)
    # Each phase comes once, in the documented order, its fraction rising to 1, never back.
    order = [p for k, (p, _) in enumerate(phases) if k == 0 or phases[k - 1][0] != p]
    documented = ["preparing", "optimising", "settling", "final_refit", "refining",
                  "other_starts", "smoothing_check"]
    assert order == sorted(set(order), key=documented.index)
    for phase in order:
        fractions = [f for p, f in phases if p == phase]
        assert fractions == sorted(fractions) and fractions[-1] == 1.0, phase
    assert phases[0] == ("preparing", 0.0)
    with pytest.raises(vmas.Cancelled):
        vmas.skeletonize(points, spheres=8, progress=lambda phase, f: phase == "preparing")

    def fails(phase, fraction):
        raise RuntimeError("from the callback")
    with pytest.raises(RuntimeError, match="from the callback"):
        vmas.skeletonize(points, spheres=8, progress=fails)


def interrupted_output(setup, call, after):
    """What a child Python prints when Ctrl-C reaches `call` (code, after `setup`) `after`
    seconds into it: 'interrupted' if it raised KeyboardInterrupt, 'finished' otherwise; and the
    seconds from the signal to its end."""
    script = ("import numpy as np, sys, time, vmas\n" + setup + "print('go', flush=True)\n"
              "try:\n"
              f"    {call}\n"
              "    print('finished', flush=True)\n"
              "except KeyboardInterrupt:\n"
              "    print('interrupted', flush=True)\n")
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True,
                             env=dict(os.environ))
    assert child.stdout.readline().strip() == "go"
    time.sleep(after)
    sent = time.monotonic()
    child.send_signal(signal.SIGINT)
    out, _ = child.communicate(timeout=60)
    return out.strip(), time.monotonic() - sent


def test_ctrl_c_raises_keyboard_interrupt():
    out, _ = interrupted_output("p = np.random.default_rng(0).normal(size=(200000, 3))\n",
                                "vmas.skeletonize(p, spheres=3000, denoise='off')",
                                3.0)  # well into the run (3000 spheres take far longer)
    assert out == "interrupted", out


def test_ctrl_c_stops_a_skeletonizer_while_it_prepares():
    # A million points without normals: preparation alone takes seconds (thinning, outliers,
    # normals), and Ctrl-C must not wait for its end.
    out, waited = interrupted_output(
        "p = np.random.default_rng(0).normal(size=(1000000, 3))\n"
        "p /= np.linalg.norm(p, axis=1)[:, None]\n"
        "p += np.random.default_rng(1).normal(scale=0.01, size=p.shape)\n",
        "vmas.Skeletonizer(p, spheres=50)", 0.5)
    assert out == "interrupted", out
    print(f"Ctrl-C while preparing answered in {waited:.2f} s")


def test_no_leak_over_many_calls():
    points = sphere_points(200)

    def rss_kb():
        return int(open("/proc/self/statm").read().split()[1]) * resource.getpagesize() // 1024
    options = dict(spheres=2, threads=1, denoise="off", refine_moves=0)  # quick calls
    for _ in range(100):
        vmas.skeletonize(points, **options).to_dict()
    before = rss_kb()
    for _ in range(1000):
        vmas.skeletonize(points, **options).to_dict()
    assert rss_kb() < before * 1.10 + 1024


def test_the_editing_loop_of_the_paper():
    points, normals = capsule_points(3000)
    skeletonizer = vmas.Skeletonizer(points, normals, spheres=5, threads=1)
    assert skeletonizer.spheres == 1
    summary = skeletonizer.run()
    assert summary["spheres"] == 5 and not summary["cancelled"]
    keys = list(skeletonizer.keys)
    added = skeletonizer.add_sphere(17)
    assert skeletonizer.spheres == 6 and added == 5
    skeletonizer.freeze(0)
    kept = skeletonizer.medial_mesh().centers[0].copy()
    for _ in range(5):
        skeletonizer.step()
    np.testing.assert_array_equal(skeletonizer.medial_mesh().centers[0], kept)
    skeletonizer.remove_sphere(1)
    assert keys[1] not in list(skeletonizer.keys) and keys[2] == skeletonizer.keys[1]
    assert skeletonizer.split() >= 0
    turn = skeletonizer.advance()
    assert set(turn) == {"error", "converged", "split", "done"}
    mesh = skeletonizer.medial_mesh()
    assert mesh.centers.shape[0] == skeletonizer.spheres
    assert skeletonizer.vertex_labels.shape == (skeletonizer.points.shape[0],)
    assert skeletonizer.labels.shape == (len(points),)  # by input row
    with pytest.raises(vmas.InvalidArgument):
        skeletonizer.remove_sphere(99)
    with pytest.raises(vmas.InvalidArgument):
        skeletonizer.add_sphere(-1)


def test_run_then_finish_is_what_skeletonize_gives_with_one_start():
    points, normals = capsule_points(3000)
    result = vmas.skeletonize(points, normals, spheres=8, starts=1, threads=1)
    skeletonizer = vmas.Skeletonizer(points, normals, spheres=8, starts=1, threads=1)
    skeletonizer.run()
    finished = skeletonizer.finish()
    assert set(finished) == {"moves_tried", "moves_kept", "measured_error_percent", "cancelled"}
    assert finished["moves_tried"] >= 1 and not finished["cancelled"]
    np.testing.assert_array_equal(skeletonizer.medial_mesh().centers, result.medial_mesh.centers)
    np.testing.assert_array_equal(skeletonizer.medial_mesh().radii, result.medial_mesh.radii)
    assert finished["measured_error_percent"] == pytest.approx(
        result.summary["measured_error_percent"], abs=1e-3)
    # A second finish refines again but does not refit the refitted skeleton twice.
    again = skeletonizer.finish()
    assert again["measured_error_percent"] <= finished["measured_error_percent"] + 1e-9


def test_open3d_arrays_go_in_directly():
    o3d = pytest.importorskip("open3d", reason="Debian's python3-open3d (scripts/build installs it)")
    points, normals = capsule_points(2000)
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
    cloud.normals = o3d.utility.Vector3dVector(normals)
    from_open3d = vmas.skeletonize(np.asarray(cloud.points), np.asarray(cloud.normals), spheres=5)
    from_numpy = vmas.skeletonize(points, normals, spheres=5)
    np.testing.assert_array_equal(from_open3d.centers, from_numpy.centers)
    ball = o3d.geometry.TriangleMesh.create_sphere(radius=2.0, resolution=20)
    result = vmas.skeletonize(np.asarray(ball.vertices), faces=np.asarray(ball.triangles),
                              spheres=1)
    assert np.linalg.norm(result.centers[0]) < 0.05 and abs(result.radii[0] - 2.0) < 0.05


def test_keywords_are_checked_as_python_checks_arguments():
    """One test per kind of option: unknown, flag, integer, number, denoise."""
    points = sphere_points(800)
    with pytest.raises(TypeError, match=r"skeletonize\(\) got an unexpected keyword argument "
                                        r"'lamda' \(did you mean 'lambda_'\?\)"):
        vmas.skeletonize(points, spheres=3, lamda=0.1)
    with pytest.raises(TypeError, match="unexpected keyword argument 'bogus'"):
        vmas.skeletonize(points, spheres=3, bogus=1)
    with pytest.raises(TypeError, match=r"Skeletonizer\(\) got an unexpected keyword argument"):
        vmas.Skeletonizer(points, spheres=3, bogus=1)
    # Flags: Python's and NumPy's booleans, nothing else.
    for wrong in (0, 1, "false", "true", 1.0):
        with pytest.raises(TypeError, match="no_projection must be True or False"):
            vmas.skeletonize(points, spheres=3, no_projection=wrong)
    off = vmas.skeletonize(points, spheres=3, no_projection=np.False_, threads=1)
    default = vmas.skeletonize(points, spheres=3, threads=1)
    np.testing.assert_array_equal(off.centers, default.centers)
    # Integers: no bool, no float.
    for wrong in (True, 3.0, "3"):
        with pytest.raises(TypeError, match="spheres must be an integer"):
            vmas.skeletonize(points, spheres=wrong)
    with pytest.raises(TypeError, match="threads must be an integer"):
        vmas.skeletonize(points, spheres=3, threads=True)
    assert vmas.skeletonize(points, spheres=np.int64(3)).centers.shape == (3, 3)
    # Numbers: int, float, NumPy; no bool, no text.
    for wrong in (True, "0.1"):
        with pytest.raises(TypeError, match="lambda_ must be a number"):
            vmas.skeletonize(points, spheres=3, lambda_=wrong)
    a = vmas.skeletonize(points, spheres=3, lambda_=np.float32(0.25), threads=1)
    b = vmas.skeletonize(points, spheres=3, lambda_=0.25, threads=1)
    np.testing.assert_array_equal(a.centers, b.centers)
    # denoise: False is off, True the default.
    noisy = sphere_points(3000) + np.random.default_rng(4).normal(scale=0.05, size=(3000, 3))
    as_they_are = vmas.skeletonize(noisy, spheres=3, denoise=False).summary["noise"]
    assert not as_they_are["measured"] and not as_they_are["smoothed"]
    assert vmas.skeletonize(noisy, spheres=3, denoise=True).summary["noise"]["smoothed"]
    with pytest.raises(TypeError, match="denoise must be"):
        vmas.skeletonize(noisy, spheres=3, denoise=[0.01])


def run_in_threads(*work):
    """Runs each callable in a thread of its own, all at once; the exceptions they raised."""
    import threading
    failures = []

    def guarded(function):
        def run():
            try:
                function()
            except Exception as e:  # noqa: BLE001 - any failure is the test's
                failures.append(e)
        return run
    threads = [threading.Thread(target=guarded(function)) for function in work]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    return failures


def test_a_skeletonizer_used_from_two_threads_takes_turns():
    """Edits from one thread while another runs the optimisation: no crash, a consistent
    state (the paper's workflow from a notebook)."""
    points, normals = capsule_points(4000)
    skeletonizer = vmas.Skeletonizer(points, normals, spheres=30, threads=1)
    stop = time.monotonic() + 30.0  # the stress: 30 s

    def optimise():
        while time.monotonic() < stop:
            skeletonizer.step()

    def edit():
        rng = np.random.default_rng(3)
        while time.monotonic() < stop:
            skeletonizer.add_sphere(int(rng.integers(len(skeletonizer.points))))
            if skeletonizer.spheres > 2:
                skeletonizer.remove_sphere(int(rng.integers(skeletonizer.spheres)))
            mesh = skeletonizer.medial_mesh()
            assert mesh.centers.shape[0] == len(skeletonizer.keys)

    failures = run_in_threads(optimise, edit)
    assert not failures, failures


def test_a_skeletonizer_speaks_the_inputs_frame_and_rows():
    points, normals = capsule_points(3000)
    moved = points * 10.0 + np.array([100.0, -50.0, 3.0])
    dropped = moved.copy()
    dropped[7] = np.nan
    skeletonizer = vmas.Skeletonizer(dropped, normals, spheres=4, threads=1)
    skeletonizer.run()
    # The prepared vertices are the input's points, where the input put them.
    kept = np.delete(moved, 7, axis=0)
    assert skeletonizer.points.shape == kept.shape
    np.testing.assert_allclose(np.sort(skeletonizer.points, axis=0), np.sort(kept, axis=0),
                               atol=1e-9)
    labels = skeletonizer.labels
    assert labels.shape == (len(points),) and labels[7] == -1 and (np.delete(labels, 7) >= 0).all()


def test_results_pickle_paths_and_errors_as_python_expects(tmp_path):
    import pathlib
    import pickle
    points, normals = capsule_points(2000)
    result = vmas.skeletonize(points, normals, spheres=5, threads=1)
    again = pickle.loads(pickle.dumps(result))
    for name in ("centers", "radii", "edges", "faces", "labels"):
        np.testing.assert_array_equal(getattr(again, name), getattr(result, name))
    assert again.warnings == result.warnings and again.summary == result.summary
    # Paths: str or os.PathLike.
    path = pathlib.Path(tmp_path) / "skeleton.ply"
    vmas.write(path, result)
    np.testing.assert_allclose(vmas.read_medial(path).radii, result.radii, rtol=1e-6)  # float PLY
    # vmas.Error is the base of every vmas exception, each also the built-in.
    for name, builtin in (("InvalidInput", ValueError), ("InvalidOption", ValueError),
                          ("InvalidArgument", ValueError), ("IoError", OSError),
                          ("Cancelled", Exception)):
        kind = getattr(vmas, name)
        assert issubclass(kind, vmas.Error) and issubclass(kind, builtin)
    with pytest.raises(vmas.Error):
        vmas.read(pathlib.Path(tmp_path) / "missing.ply")
    # write() refuses what read_medial() would refuse; nothing is left behind.
    bad = {"centers": result.centers.copy(), "radii": result.radii.copy(),
           "edges": result.edges, "faces": result.faces}
    bad["centers"][0, 0] = np.nan
    broken = type("Broken", (), bad)()
    with pytest.raises(vmas.InvalidInput, match="sphere 0"):
        vmas.write(tmp_path / "bad.ply", broken)
    bad["centers"][0, 0] = 0.0
    bad["radii"][1] = -1.0
    with pytest.raises(vmas.InvalidInput, match="sphere 1"):
        vmas.write(tmp_path / "bad.ply", type("Broken", (), bad)())
    assert not (tmp_path / "bad.ply").exists()


def test_inf_rows_are_dropped_like_nan_and_faces_are_checked():
    points = sphere_points(800)
    for missing in (np.nan, np.inf, -np.inf):
        holed = points.copy()
        holed[5] = missing
        result = vmas.skeletonize(holed, spheres=3)
        assert result.labels[5] == -1 and (np.delete(result.labels, 5) >= 0).all()
    with pytest.raises(ValueError, match="out of range"):
        vmas.skeletonize(points[:3], faces=np.array([[0, 1, 3]]), spheres=1)


def test_an_edit_session_optimises_while_python_edits():
    """The paper's workflow from a notebook: the optimisation runs in the background while two
    threads edit and read it; then it finishes as vmas.skeletonize does."""
    points, normals = capsule_points(4000)
    with vmas.EditSession(points, normals, spheres=20, threads=1) as session:
        assert session.wait(0, timeout=10.0) > 0
        stop = time.monotonic() + 10.0

        def edit():
            rng = np.random.default_rng(5)
            while time.monotonic() < stop:
                session.split_at(int(rng.integers(3000)))
                keys = session.snapshot()["keys"]
                if len(keys) > 3:
                    try:
                        session.remove(int(keys[rng.integers(len(keys))]))
                    except vmas.InvalidArgument:
                        pass  # gone meanwhile, or too many edits waiting
                time.sleep(0.01)

        def read():
            while time.monotonic() < stop:
                snap = session.snapshot()
                assert snap["medial_mesh"].centers.shape[0] == len(snap["keys"])
                assert snap["labels"].shape == (len(points),)

        failures = run_in_threads(edit, read)
        assert not failures, failures
        session.finish()
        deadline = time.monotonic() + 120.0
        while not session.snapshot()["finished"] and time.monotonic() < deadline:
            session.wait(session.snapshot()["version"], timeout=1.0)
        finished = session.snapshot()
        assert finished["finished"] and finished["paused"]
        assert (finished["labels"] >= 0).all()
    with pytest.raises(vmas.InvalidArgument, match="closed"):
        session.snapshot()


def test_the_noise_curve_example_runs_and_plots(tmp_path):
    """scripts/examples/noise_curve.py, as the README shows it, on a mesh made here (CI has no
    shared models): eight runs, each ε printed, the plot written."""
    rows, columns = 16, 32
    theta = np.linspace(0, np.pi, rows + 1)[1:-1]
    phi = np.linspace(0, 2 * np.pi, columns, endpoint=False)
    ring = np.stack([np.outer(np.sin(theta), np.cos(phi)),
                     0.5 * np.outer(np.sin(theta), np.sin(phi)),
                     np.outer(np.cos(theta), np.ones(columns))], axis=-1).reshape(-1, 3)
    vertices = np.vstack([ring, [[0, 0, 1], [0, 0, -1]]])
    top, bottom = len(ring), len(ring) + 1
    faces = []
    for r in range(rows - 2):
        for c in range(columns):
            a, b = r * columns + c, r * columns + (c + 1) % columns
            faces += [[a, a + columns, b], [b, a + columns, b + columns]]
    for c in range(columns):
        faces.append([top, c, (c + 1) % columns])
        last = (rows - 2) * columns
        faces.append([bottom, last + (c + 1) % columns, last + c])
    mesh = tmp_path / "ellipsoid.off"
    with open(mesh, "w") as f:
        f.write(f"OFF\n{len(vertices)} {len(faces)} 0\n")
        f.writelines(f"{x} {y} {z}\n" for x, y, z in vertices)
        f.writelines(f"3 {a} {b} {c}\n" for a, b, c in faces)
    script = os.path.join(os.path.dirname(__file__), "..", "..", "scripts", "examples",
                          "noise_curve.py")
    plot = tmp_path / "curve.png"
    run = subprocess.run([sys.executable, script, str(mesh), str(plot), "8"], env=dict(os.environ),
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    lines = [line for line in run.stdout.splitlines() if "epsilon" in line]
    assert len(lines) == 8
    assert all(0.0 < float(line.split("epsilon ")[1].split(" %")[0]) < 50.0 for line in lines)
    assert plot.stat().st_size > 10000 and open(plot, "rb").read(8) == b"\x89PNG\r\n\x1a\n"


def test_a_density_puts_spheres_where_it_is_high_and_bad_ones_are_refused(tmp_path):
    rng = np.random.default_rng(5)
    points = rng.normal(size=(4000, 3)) * [3.0, 1.0, 0.8]
    points /= np.linalg.norm(points / [3.0, 1.0, 0.8], axis=1)[:, None]
    dense = points[:, 0] > 1.5
    density = np.where(dense, 4.0, 1.0)

    def dense_spheres(result):
        labels = np.asarray(result.labels)
        return sum(1 for s in range(len(result.radii)) if dense[labels == s].mean() > 0.5)

    plain = vmas.skeletonize(points, spheres=30, threads=1)
    uniform = vmas.skeletonize(points, spheres=30, threads=1, density=np.ones(len(points)))
    assert np.array_equal(plain.centers, uniform.centers)
    weighted = vmas.skeletonize(points, spheres=30, threads=1, density=density)
    assert dense_spheres(weighted) >= 1.5 * dense_spheres(plain)
    # The same from a file, a field of the input and a rule.
    path = tmp_path / "density.txt"
    path.write_text("".join(f"{d}\n" for d in density))
    from_file = vmas.skeletonize(points, spheres=30, threads=1, density=path)
    assert np.array_equal(from_file.centers, weighted.centers)
    xyz = tmp_path / "cloud.xyz"
    xyz.write_text("".join(f"{x!r} {y!r} {z!r} {d}\n" for (x, y, z), d in zip(points, density)))
    surface = vmas.read(xyz, density_field="density")
    assert np.array_equal(surface.density, density)
    rule = vmas.density_by_rule(points, "distance-to:3,0,0,1.5")
    assert rule.shape == (len(points),) and set(np.unique(rule)) == {1.0, 4.0}
    with pytest.raises(vmas.InvalidInput, match="the density has 3 values for 4000 points"):
        vmas.skeletonize(points, spheres=30, density=[1.0, 2.0, 3.0])
    with pytest.raises(vmas.InvalidInput, match="point 2 is negative"):
        vmas.skeletonize(points, spheres=30, density=np.r_[1.0, 1.0, -1.0, np.ones(3997)])
    with pytest.raises(vmas.InvalidInput, match="not a number"):
        vmas.skeletonize(points, spheres=30, density=np.r_[np.nan, np.ones(3999)])
    with pytest.raises(vmas.InvalidInput, match="every density value is 0"):
        vmas.skeletonize(points, spheres=30, density=np.zeros(4000))
    with pytest.raises(vmas.IoError, match="curvy: no such file .nor a density rule"):
        vmas.skeletonize(points, spheres=30, density="curvy")
    with pytest.raises(vmas.InvalidOption, match="distance-to:X,Y,Z,R"):
        vmas.skeletonize(points, spheres=30, density="distance-to:1,2")
    with pytest.raises(TypeError, match="density_field"):
        vmas.skeletonize(points, spheres=30, density_field="d")


def test_an_edit_session_paints_sets_and_reports_the_density_by_input_row():
    points, normals = capsule_points(3000)
    points = np.vstack([points, points[:1]])  # a duplicate row: dropped, reported as 1
    normals = np.vstack([normals, normals[:1]])
    with vmas.EditSession(points, normals, spheres=8, threads=1) as session:
        assert session.snapshot()["density"] is None

        def until(done):
            deadline = time.monotonic() + 20.0
            while not done(snap := session.snapshot()) and time.monotonic() < deadline:
                session.wait(snap["version"], timeout=1.0)
            return session.snapshot()

        session.paint_density(0, 0.2, 3.0)
        painted = until(lambda s: s["density"] is not None)["density"]
        assert painted.shape == (len(points),)
        assert painted[0] == 4.0 and painted[-1] == 1.0 and painted.min() == 1.0
        wanted = np.where(points[:, 0] > 0.3, 4.0, 1.0)
        session.set_density(wanted)
        shown = until(lambda s: s["density"] is not None and
                      np.array_equal(s["density"][:-1], wanted[:-1]))["density"]
        assert np.array_equal(shown[:-1], wanted[:-1]) and shown[-1] == 1.0
        session.undo()
        assert np.array_equal(until(lambda s: s["density"] is not None and
                                    s["density"][0] == 4.0)["density"], painted)
        session.set_density(None)
        assert until(lambda s: s["density"] is None)["density"] is None
        with pytest.raises(vmas.InvalidInput, match="the density has 2 values for 3001 points"):
            session.set_density([1.0, 2.0])
        with pytest.raises(vmas.InvalidOption, match="radius"):
            session.paint_density(0, 0.0, 1.0)


def torus_mesh(rings=48, sides=24, major=1.0, minor=0.35):
    """A closed triangle mesh of a torus (genus 1): its vertices and faces."""
    u, v = np.meshgrid(np.arange(rings) * 2 * np.pi / rings, np.arange(sides) * 2 * np.pi / sides,
                       indexing="ij")
    ring = major + minor * np.cos(v)
    vertices = np.stack([ring * np.cos(u), ring * np.sin(u), minor * np.sin(v)], -1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(rings), np.arange(sides), indexing="ij")
    a, b = i * sides + j, ((i + 1) % rings) * sides + j
    c, d = ((i + 1) % rings) * sides + (j + 1) % sides, i * sides + (j + 1) % sides
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                            np.stack([a, c, d], -1).reshape(-1, 3)])
    return vertices, faces


def test_an_edit_session_reports_the_topology_against_the_meshs_genus():
    vertices, faces = torus_mesh()
    with vmas.EditSession(vertices, faces=faces, spheres=16, threads=1) as session:
        session.finish()
        deadline = time.monotonic() + 120.0
        while not (snap := session.snapshot())["finished"] and time.monotonic() < deadline:
            session.wait(snap["version"], timeout=1.0)
        topology = session.snapshot()["topology"]
    assert snap["finished"]
    assert topology["input_genus"] == [1] and topology["input_genus_unknown"] == ""
    # finish() brings the loops to the genus and removes the triangles closing cavities
    assert (topology["b0"], topology["b1"], topology["b2"]) == (1, 1, 0)
    assert topology["extra_loops"] == [] and topology["cavity_triangles"] == []
    with vmas.EditSession(sphere_points(2000), spheres=8, threads=1) as session:
        session.wait(0, timeout=10.0)
        cloud = session.snapshot()["topology"]
    assert cloud["input_genus"] is None and cloud["input_genus_unknown"] == "a point cloud (no faces)"
