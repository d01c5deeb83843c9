"""The sections as run: Table 1, Table 2 (and the picture of its worst row), Table 3, the real
scans, the scaling and live editing, each walking its models and inputs, running vmas on each
and storing the rows in the results (saved as they come)."""

import json
import math
import os
import subprocess

import numpy as np

import vmas_files

from . import cad, running
from .inputs import (SPARSE_MAX_SPHERES, STREAM_SAMPLES, TRANSFORMS, cap_cut, lid_bound,
                     STREAM_CAD, merged_range_scans, moved_copy, noise_inputs, scaling_cloud,
                     seed_sequence, sparse_cloud)
from .plots import plot_scaling, render
from .running import evaluate, read_mesh, skeletonize
from .tables import KIND_LABEL, REFERENCES, entry_eps, noise_targets, row_eps


def table1(args, paper, results, save, log):
    meshes = os.path.join(args.data, "meshes")
    work = os.path.join(args.out, "meshes")
    os.makedirs(work, exist_ok=True)
    for model in args.models:
        shape = os.path.join(meshes, model + ".off")
        row = {"model": model}
        results["table1"].append(row)
        if model not in paper:
            row["error"] = "model not in paper_tables.tsv"
            continue
        spheres = paper[model]["M"]
        row["M"] = spheres
        try:
            row["vertices"] = len(read_mesh(shape)[0])
        except (OSError, ValueError) as e:
            row["error"] = f"cannot read {shape}: {e}"
            continue
        log(f"[table 1] {model}: skeletonize M={spheres}")
        ours_ply = os.path.join(work, model + ".ply")
        errors_txt = os.path.join(work, model + "_errors.txt")
        medial_errors_txt = os.path.join(work, model + "_medial_errors.txt")
        row["ours"] = skeletonize(args, shape, ours_ply, spheres)
        if not row["ours"].get("error"):
            log(f"[table 1] {model}: eval ours")
            row["ours"]["eval"] = evaluate(args.vmas, shape, ours_ply, args.timeout, errors_txt,
                                           medial_errors_txt)
        for name, _ in REFERENCES:
            ma = os.path.join(args.data, "reference", model, name + ".ma")
            if not os.path.exists(ma):
                row[name] = {"error": "no reference file"}
                continue
            log(f"[table 1] {model}: eval {name}")
            row[name] = evaluate(args.vmas, shape, ma, args.timeout)
        save()
        if args.render and not row["ours"].get("error"):
            png = os.path.join(args.out, model + ".png")
            ours_eval = row["ours"].get("eval", {})
            evaluated = not ours_eval.get("error")
            errors = errors_txt if os.path.exists(errors_txt) and evaluated else "-"
            medial_errors = medial_errors_txt if os.path.exists(medial_errors_txt) and evaluated \
                else "-"
            eps = ours_eval.get("eps_percent")
            title = f"{model}: vmas, M={spheres}" + (f", ε={eps:.3f} %" if eps is not None else "")
            row["render"] = render(args, shape, ours_ply, errors, png,
                                   "--medial-errors", medial_errors, "--title", title)


def table2(args, paper, results, save, log):
    meshes = os.path.join(args.data, "meshes")
    work = os.path.join(args.out, "noise")
    os.makedirs(work, exist_ok=True)
    table1_runs = {r["model"]: r["ours"] for r in results["table1"]
                   if r.get("ours") and not r["ours"].get("error")
                   and not r["ours"].get("eval", {}).get("error")}
    for model in args.cloud_models:
        shape = os.path.join(meshes, model + ".off")
        if model not in paper:
            results["table2"].append({"model": model, "kind": "–", "sigma_percent": None,
                                      "error": "model not in paper_tables.tsv"})
            continue
        spheres = paper[model]["M"]
        try:
            points, faces = read_mesh(shape)
        except (OSError, ValueError) as e:
            results["table2"].append({"model": model, "kind": "–", "sigma_percent": None,
                                      "error": f"cannot read {shape}: {e}"})
            continue
        for kind, sigma, path, count, seed in noise_inputs(args, model, shape, points, faces,
                                                           work):
            row = {"model": model, "kind": kind, "sigma_percent": sigma, "input": path,
                   "points": count, "M": spheres, "seed_sequence": seed,
                   "samples_seed_sequence": None if kind == "mesh" else
                   seed_sequence(args.seed, model, STREAM_SAMPLES)}
            results["table2"].append(row)
            what = f"[table 2] {model}, {KIND_LABEL[kind]}, σ={sigma:g} %"
            if kind == "mesh" and sigma == 0 and model in table1_runs:
                log(f"{what}: the clean mesh, run of Table 1 reused")
                row["ours"], row["reused"] = table1_runs[model], "table1"
                continue
            ply = os.path.splitext(path)[0] + ".ply" if path != shape else \
                os.path.join(work, f"{model}_mesh_s0.ply")
            log(f"{what}: skeletonize M={spheres}")
            row["ours"] = skeletonize(args, path, ply, spheres)
            if not row["ours"].get("error"):
                log(f"{what}: eval against the clean mesh")
                row["ours"]["eval"] = evaluate(args.vmas, shape, ply, args.timeout)
            row["ours"]["medial"] = ply
            if sigma > 0 or kind == "outliers":
                # "never worse than doing nothing": the same input taken as it is
                log(f"{what}: skeletonize --denoise off")
                off_ply = os.path.splitext(ply)[0] + "_off.ply"
                row["denoise_off"] = skeletonize(args, path, off_ply, spheres,
                                                 extra=("--denoise", "off"))
                if not row["denoise_off"].get("error"):
                    row["denoise_off"]["eval"] = evaluate(args.vmas, shape, off_ply,
                                                          args.timeout)
            save()
        noise_targets(results)
        save()


def render_worst(args, results, log):
    """OUT/noise_worst.png: the row of Table 2 with the largest ε − bound."""
    rows = [r for r in results["table2"] if row_eps(r) is not None and r.get("bound_percent")
            is not None and r.get("targets", {}).get("epsilon", {}).get("ok") is not None]
    if not rows:
        return
    worst = max(rows, key=lambda r: row_eps(r) - r["bound_percent"])
    shape = os.path.join(args.data, "meshes", worst["model"] + ".off")
    medial = worst["ours"]["medial"]
    errors = os.path.join(args.out, "noise", "worst_errors.txt")
    medial_errors = os.path.join(args.out, "noise", "worst_medial_errors.txt")
    log(f"[table 2] picture of the worst row: {worst['model']}, {KIND_LABEL[worst['kind']]}, "
        f"σ={worst['sigma_percent']:g} %")
    evaluation = evaluate(args.vmas, shape, medial, args.timeout, errors, medial_errors)
    png = os.path.join(args.out, "noise_worst.png")
    ev = worst["ours"]["eval"]
    title = (f"{worst['model']}, {KIND_LABEL[worst['kind']]}, σ={worst['sigma_percent']:g} %: "
             f"ε={row_eps(worst):.2f} % (bound {worst['bound_percent']:.2f} %; surface → medial "
             f"{ev.get('surface_to_medial_max_percent', math.nan):.2f}, medial → surface "
             f"{ev.get('medial_to_surface_max_percent', math.nan):.2f})")
    evaluated = not evaluation.get("error")
    results["noise_worst"] = {"model": worst["model"], "kind": worst["kind"],
                              "sigma_percent": worst["sigma_percent"], "eval": evaluation,
                              "render": render(args, shape, medial, errors if evaluated else "-",
                                               png, "--title", title, "--input", worst["input"],
                                               "--medial-errors",
                                               medial_errors if evaluated else "-")}


def run_and_measure(args, log, what, inputs, truth, ply, spheres, data=None):
    """skeletonize `inputs` (--json) at `spheres`, eval against `truth` (and `data`, the input
    itself, when given); the entry of skeletonize() with "eval" (and "eval_data")."""
    log(f"[table 3] {what}: skeletonize M={spheres}")
    entry = skeletonize(args, inputs, ply, spheres)
    if not entry.get("error"):
        entry["eval"] = evaluate(args.vmas, truth, ply, args.timeout)
        if data:
            entry["eval_data"] = evaluate(args.vmas, data, ply, args.timeout)
    return entry


def table3(args, paper, results, save, log):
    meshes = os.path.join(args.data, "meshes")
    work = os.path.join(args.out, "robustness")
    os.makedirs(work, exist_ok=True)
    clean_meshes = {r["model"]: r["ours"] for r in results["table2"]
                    if r.get("kind") == "mesh" and r.get("sigma_percent") == 0
                    and entry_eps(r.get("ours")) is not None}
    for model in args.cloud_models:
        if model not in paper:
            continue
        shape = os.path.join(meshes, model + ".off")
        points, faces = read_mesh(shape)
        spheres, sparse_spheres = paper[model]["M"], min(paper[model]["M"], SPARSE_MAX_SPHERES)
        row = {"model": model, "M": spheres, "sparse_M": sparse_spheres}
        results["table3"].append(row)
        base = os.path.join(work, model)
        # the clean mesh at M: Table 2's run (itself Table 1's when that ran)
        row["mesh"] = clean_meshes.get(model) or run_and_measure(
            args, log, f"{model}, mesh", shape, shape, base + "_mesh.ply", spheres)
        row["mesh_sparse_M"] = row["mesh"] if sparse_spheres == spheres else run_and_measure(
            args, log, f"{model}, mesh at {sparse_spheres}", shape, shape,
            base + f"_mesh_{sparse_spheres}.ply", sparse_spheres)
        vertices = base + "_vertices.xyz"
        vmas_files.write_xyz(vertices, points)
        row["vertex_cloud"] = run_and_measure(args, log, f"{model}, vertex cloud", vertices,
                                              shape, base + "_vertices.ply", spheres)
        sparse_xyz = base + "_5000.xyz"
        sparse_cloud(args, model, points, faces, sparse_xyz)
        row["sparse"] = run_and_measure(args, log, f"{model}, 5 000 points", sparse_xyz, shape,
                                        base + "_5000.ply", sparse_spheres)
        cap_xyz = base + "_cap.xyz"
        kept, axis, cut = cap_cut(args, model, points, faces, cap_xyz)
        cap = run_and_measure(args, log, f"{model}, cap cut off", cap_xyz, shape,
                              base + "_cap.ply", spheres, data=cap_xyz)
        cap["lid_bound_percent"] = lid_bound(points, faces, kept, axis, cut)
        if not cap.get("error"):
            try:
                medial = running.vmas.read_medial(base + "_cap.ply")
                diagonal = vmas_files.bbox_diagonal(kept)
                cap["reach_percent"] = float(
                    100.0 * ((medial.centers[:, axis] + medial.radii).max() - kept[:, axis].max())
                    / diagonal)
            except (OSError, ValueError) as e:
                cap["reach_error"] = str(e)
        row["cap"] = cap
        row["transforms"] = {"mesh": [], "vertex_cloud": []}
        for t in range(TRANSFORMS):
            moved_off, moved_xyz, scale = moved_copy(args, model, points, faces, t, base)
            row["transforms"]["mesh"].append(dict(run_and_measure(
                args, log, f"{model}, moved mesh {t}", moved_off, moved_off,
                base + f"_moved{t}_mesh.ply", spheres), scale=scale))
            row["transforms"]["vertex_cloud"].append(dict(run_and_measure(
                args, log, f"{model}, moved vertex cloud {t}", moved_xyz, moved_off,
                base + f"_moved{t}_vertices.ply", spheres), scale=scale))
        save()


# The real scans: files of DATA/scans read as clouds, the range scans of DATA/scans/bunny_range
# merged by their poses, at the default sphere count; the reconstruction of the bunny scans.
SCAN_EXTENSIONS = (".xyz", ".ply", ".pcd", ".off", ".obj")
SCAN_SPHERES = 100
RANGE_SCANS = os.path.join("bunny_range", "bun.conf")
SCAN_RECONSTRUCTIONS = {"bunny_merged_45k.xyz": os.path.join("bunny_range", "bun_zipper.ply"),
                        "bunny_range_merged.xyz": os.path.join("bunny_range", "bun_zipper.ply")}


def scan_inputs(args, work):
    """(name, path, reconstruction or None) of every real scan."""
    folder = os.path.join(args.data, "scans")
    if not os.path.isdir(folder):
        return []
    names = sorted(f for f in os.listdir(folder)
                   if f.lower().endswith(SCAN_EXTENSIONS) and os.path.isfile(os.path.join(folder, f)))
    scans = [(name, os.path.join(folder, name)) for name in names]
    if os.path.isfile(os.path.join(folder, RANGE_SCANS)):
        merged = os.path.join(work, "bunny_range_merged.xyz")
        scans.append((os.path.basename(merged), merged_range_scans(
            os.path.join(folder, RANGE_SCANS), lambda f: running.vmas.read(f).points, merged)))
    return [(name, path, os.path.join(folder, SCAN_RECONSTRUCTIONS[name])
             if name in SCAN_RECONSTRUCTIONS else None) for name, path in scans]


def run_scan(args, binary, tag, path, points, work, reconstruction, log):
    """One binary's run on a scan (`points`: as stored): its summary, time and peak memory, and
    its ε against the points it kept (labels ≥ 0: the data as vmas used it; the points it dropped
    are counted) and against the reconstruction when there is one."""
    name = os.path.basename(path)
    ply = os.path.join(work, f"{name}.{tag}.ply")
    labels = os.path.join(work, f"{name}.{tag}.labels")
    log(f"[scans] {name}: {tag} skeletonize")
    entry = skeletonize(args, path, ply, SCAN_SPHERES, memory=True, extra=("--labels", labels),
                        binary=binary)
    if entry.get("error"):
        return entry
    kept = np.loadtxt(labels, dtype=np.int64, ndmin=1) >= 0
    entry["dropped_points"] = int(np.count_nonzero(~kept))
    kept_xyz = os.path.join(work, f"{name}.{tag}.kept.xyz")
    vmas_files.write_xyz(kept_xyz, points[kept])
    entry["eval"] = evaluate(args.vmas, kept_xyz, ply, args.timeout)
    if reconstruction:
        entry["eval_reconstruction"] = evaluate(args.vmas, reconstruction, ply, args.timeout)
    os.remove(kept_xyz)
    return entry


def scans(args, results, save, log):
    """Every real scan with --vmas and, given --base-vmas, with the previous release's binary."""
    work = os.path.join(args.out, "scans")
    os.makedirs(work, exist_ok=True)
    for name, path, reconstruction in scan_inputs(args, work):
        row = {"scan": name, "input": path, "reconstruction": reconstruction}
        results["scans"].append(row)
        points = np.asarray(running.vmas.read(path).points)
        for tag, binary in (("ours", args.vmas), ("base", args.base_vmas)):
            if binary:
                row[tag] = run_scan(args, binary, tag, path, points, work, reconstruction, log)
        save()


# Coarse meshes (issue 46, item 5): CAD-like parts made in code (vmasbench.cad), each run as a
# mesh and as clouds of CAD_CLOUD_POINTS random points of its faces with their normals.
CAD_SPHERES = 60
CAD_CLOUD_POINTS = 10000
CAD_CLOUDS = 3


def coarse_meshes(args, results, save, log):
    """Every part of vmasbench.cad as a mesh (with --vmas and, given --base-vmas, the previous
    release) and as CAD_CLOUDS clouds (--vmas), ε against the mesh."""
    work = os.path.join(args.out, "coarse")
    os.makedirs(work, exist_ok=True)
    for name, make in cad.PARTS.items():
        points, faces = make()
        mesh = os.path.join(work, name + ".off")
        vmas_files.write_off(mesh, points, faces)
        row = {"part": name, "vertices": len(points), "clouds": []}
        results["coarse"].append(row)
        runs = [(tag, binary, mesh) for tag, binary in (("ours", args.vmas), ("base", args.base_vmas))
                if binary]
        for k in range(CAD_CLOUDS):
            samples, normals = vmas_files.sample_surface(
                points, faces, CAD_CLOUD_POINTS, seed_sequence(args.seed, name, STREAM_CAD, k))
            cloud = os.path.join(work, f"{name}.cloud{k}.xyz")
            vmas_files.write_xyz(cloud, samples, normals)
            runs.append((f"cloud{k}", args.vmas, cloud))
        for tag, binary, shape in runs:
            log(f"[coarse] {name}: {tag}")
            ply = os.path.join(work, f"{name}.{tag}.ply")
            entry = skeletonize(args, shape, ply, CAD_SPHERES, binary=binary)
            if not entry.get("error"):
                entry["eval"] = evaluate(args.vmas, mesh, ply, args.timeout)
            if tag.startswith("cloud"):
                row["clouds"].append(entry)
            else:
                row[tag] = entry
        save()


def scaling(args, results, save, log):
    """For every --scaling-points N and --scaling-spheres M: skeletonizes the cloud of N points
    with M spheres (JSON summary, peak RSS) and measures ε against the clean mesh; then plots
    OUT/scaling.png."""
    model = args.scaling_model
    shape = os.path.join(args.data, "meshes", model + ".off")
    work = os.path.join(args.out, "scaling")
    os.makedirs(work, exist_ok=True)
    try:
        points, faces = read_mesh(shape)
    except (OSError, ValueError) as e:
        points = faces = None
        error = f"cannot read {shape}: {e}"
    for count in args.scaling_points:
        if points is not None:
            log(f"[scaling] {model}, {count} points: cloud")
            try:
                cloud, seed, kept = scaling_cloud(args, model, points, faces, count, work)
                error = None
                log(f"[scaling] {model}, {count} points: cloud "
                    f"{'kept (same header)' if kept else 'written'}: {cloud}")
            except OSError as e:
                error = f"cannot write the cloud: {e}"
        for spheres in args.scaling_spheres:
            row = {"model": model, "points": count, "spheres": spheres}
            results["scaling"].append(row)
            if error:
                row["error"] = error
                continue
            row.update(input=cloud, seed_sequence=seed)
            what = f"[scaling] {model}, {count} points, M={spheres}"
            log(f"{what}: skeletonize")
            ply = os.path.join(work, f"{model}_{count}_{spheres}.ply")
            row["ours"] = skeletonize(args, cloud, ply, spheres, memory=True)
            if not row["ours"].get("error"):
                log(f"{what}: eval against the clean mesh")
                row["ours"]["eval"] = evaluate(args.vmas, shape, ply, args.timeout)
            save()
    png = os.path.join(args.out, "scaling.png")
    results["scaling_plot"] = plot_scaling(results["scaling"], model, args, png)
    log(f"[scaling] plot: {png}" if results["scaling_plot"] == png else
        f"[scaling] no plot: {results['scaling_plot']['error']}")


EDITING_FILTER = ("^BM_Step/|^BM_EditThenStep/1$|^BM_StepAfterEdit/1$|^BM_StepOnAThinnedScan/2$"
                  "|^BM_EditSessionOnAThinnedScan/")


def live_editing(args, results, save, log):
    """Runs vmas_step_benchmark (beside --vmas; built with the tests) for the step latency and
    the editor engine's updates per second (medians of three repetitions), and keeps its
    figures."""
    binary = os.path.join(os.path.dirname(os.path.abspath(args.vmas)), "vmas_step_benchmark")
    row = {"binary": binary}
    results["editing"] = row
    if not os.path.exists(binary):
        row["error"] = f"{binary} not found (it is built with the tests)"
        save()
        return
    log(f"[editing] {binary}")
    env = dict(os.environ, VMAS_SHARED_DATA=args.data)
    report = None
    try:
        done = subprocess.run([binary, "--benchmark_format=json", "--benchmark_repetitions=3",
                               "--benchmark_report_aggregates_only=true",
                               f"--benchmark_filter={EDITING_FILTER}"],
                              capture_output=True, text=True, timeout=max(args.timeout, 900),
                              env=env, check=False)
        if done.returncode == 0:
            report = json.loads(done.stdout)
        else:
            row["error"] = f"exit {done.returncode}: {done.stderr.strip()[-300:]}"
    except (OSError, subprocess.TimeoutExpired, json.JSONDecodeError) as e:
        row["error"] = str(e)
    if report:
        row["benchmarks"] = [b for b in report.get("benchmarks", [])
                             if b.get("aggregate_name") == "median"]
    save()
