"""The Markdown of bench.md, built from the results alone: the cell formats, Table 1 against the
paper and the reference methods, the targets of Table 2 (noise_targets, which also stores them in
the results) and its tables and summaries, Table 3 with its targets, the real scans beside the
previous release, the scaling table."""

import math
import os

from .inputs import (CAP_FRACTION, SPARSE_MAX_SPHERES, SPARSE_POINTS, STREAM_SCALING,
                     TRANSFORMS)


# ---------------------------------------------------------------------------------------------
# Cells


def cell(value, digits=3):
    if value is None:
        return "–"
    if isinstance(value, float):
        return f"{value:.{digits}f}" if math.isfinite(value) else str(value)
    return str(value).replace("|", "\\|").replace("\n", " ")


def eps_cell(entry):
    if entry is None:
        return "–"
    if entry.get("error"):
        return "FAILED: " + cell(entry["error"])[:160]
    return cell(entry.get("eps_percent"))


def markdown_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def geometric_mean(values):
    values = [v for v in values if v and v > 0 and math.isfinite(v)]
    return math.exp(sum(map(math.log, values)) / len(values)) if values else None


# ---------------------------------------------------------------------------------------------
# Table 1


# the reference methods of DATA/reference/<model>/<key>.ma: (key, column)
REFERENCES = (("qmat", "Q-MAT"), ("coverage_axis", "CA"), ("coverage_axis_pp", "CA++"))


def format_table1(results, paper):
    header = ["model", "vertices", "M", "ours ε %", "Q-MAT ε %", "CA ε %", "CA++ ε %",
              "paper VMAS ε %", "ours time s", "wall s", "paper time s", "ratio", "checks"]
    rows, ratios = [], []
    better_paper = better_refs = compared_paper = compared_refs = 0
    for r in results["table1"]:
        p = paper.get(r["model"], {})
        if r.get("error"):
            rows.append([r["model"], cell(r.get("vertices")), cell(r.get("M")),
                         "FAILED: " + cell(r["error"])] + ["–"] * 9)
            continue
        ours = r["ours"]
        ours_eval = ours.get("eval")
        if ours.get("error"):
            ours_cell = "FAILED: " + cell(ours["error"])[:160]
        else:
            ours_cell = eps_cell(ours_eval)
        eps = (ours_eval or {}).get("eps_percent")
        refs = [r.get(name, {}).get("eps_percent") for name, _ in REFERENCES]
        if eps is not None and p.get("eps_VMAS") is not None:
            compared_paper += 1
            better_paper += eps <= p["eps_VMAS"]
        if eps is not None and all(v is not None for v in refs):
            compared_refs += 1
            better_refs += eps < min(refs)
        own_time = ours.get("vmas_total_s")
        ratio = own_time / p["time_VMAS"] if own_time and p.get("time_VMAS") else None
        if ratio:
            ratios.append(ratio)
        checks = ours.get("checks")
        rows.append([r["model"], cell(r.get("vertices")), cell(r.get("M")), ours_cell]
                    + [eps_cell(r.get(name)) for name, _ in REFERENCES]
                    + [cell(p.get("eps_VMAS")), cell(own_time, 2),
                       cell(ours.get("wall_s"), 2) if not ours.get("error") else "–",
                       cell(p.get("time_VMAS"), 2), cell(ratio, 2),
                       "–" if checks is None else ("ok" if not checks else cell("; ".join(checks)))])
    summary = [
        f"- ours ε ≤ paper's VMAS ε on {better_paper} of {compared_paper} models",
        f"- ours ε < min(Q-MAT, CA, CA++) (recomputed by vmas eval) on {better_refs} of "
        f"{compared_refs} models",
    ]
    g = geometric_mean(ratios)
    summary.append("- geometric mean of the time ratio ours / paper: "
                   + (f"{g:.2f} over {len(ratios)} models" if g else "–"))
    failed_checks = [r["model"] for r in results["table1"]
                     if r.get("ours", {}).get("checks")]
    summary.append("- validity checks (exactly M spheres, radii positive and finite, valid "
                   "indices, one connected component): "
                   + ("all passed" if not failed_checks else "failed on " + ", ".join(failed_checks)))
    return markdown_table(header, rows) + "\n\n" + "\n".join(summary)


# ---------------------------------------------------------------------------------------------
# Table 2: noise robustness


KINDS = (  # (key, label); the outlier row is one extra row per model
    ("cloud", "cloud, no normals"),
    ("normals", "cloud, exact normals"),
    ("mesh", "noisy mesh"),
)
OUTLIERS = ("outliers", "cloud, no normals, 1 % outliers")
KIND_LABEL = dict(KINDS + (OUTLIERS,))
OUTLIER_SLACK = 0.3  # outlier row: ε at most this many points above the σ = 0 cloud's
DENOISE_SLACK = 0.3  # noisy rows: ε at most this many points above `--denoise off`'s
TIME_FACTOR = 2.0  # time at most this many times the clean run of the same kind
NOISE_TOLERANCE = 0.25  # noisy rows: vmas' noise estimate within this fraction of σ (issue 18)


def entry_eps(entry, key="eval"):
    """ε of one run (skeletonize() entry with its `key` evaluation), None if it has none."""
    if not entry or entry.get("error"):
        return None
    value = (entry.get(key) or {}).get("eps_percent")
    return value if value is not None and math.isfinite(value) else None


def row_eps(row):
    return entry_eps(row.get("ours"))


def _eps_in_model_diagonal(entry, untransformed):
    """ε of a run on a moved copy (an entry with the transform's "scale") in % of the untransformed
    model's diagonal: the same length whatever the rotation. (A rotation changes the bounding box,
    so ε in % of the moved copy's own diagonal changes even for a skeleton that moved exactly
    with it: pinion's untransformed skeleton, rotated, reads 1.99 / 1.84 / 1.74 / 1.68 %.)"""
    eps = entry_eps(entry)
    if eps is None or "scale" not in entry:
        return eps
    try:
        own = entry["eval"]["json"]["diagonal"]
        model = untransformed["eval"]["json"]["diagonal"]
    except (KeyError, TypeError):
        return None
    return eps * own / (entry["scale"] * model)


def _time(row):
    ours = row.get("ours") or {}
    return None if ours.get("error") else ours.get("vmas_total_s", ours.get("wall_s"))


def _failure(row):
    """Why a row has no usable result (crash, timeout, no ε, invalid output), or None."""
    if row.get("error"):
        return row["error"]
    ours = row.get("ours") or {}
    if ours.get("error"):
        return ours["error"]
    if (ours.get("eval") or {}).get("error"):
        return "eval: " + ours["eval"]["error"]
    if row_eps(row) is None:
        return "ε not finite"
    invalid = [c for c in ours.get("checks") or [] if not c.endswith(" components")]
    return "invalid output: " + "; ".join(invalid) if invalid else None


def noise_ratio(row):
    """vmas' noise estimate over the true σ, both as lengths, for a noisy row that ran (else
    None). Not the percentages: vmas gives its estimate in % of the diagonal of the noisy data
    as it prepared them (up to 35 % longer than the clean mesh's at σ = 3 %), while σ is in %
    of the clean mesh's diagonal, which `vmas eval` against the clean mesh reports."""
    if row["kind"] == "outliers" or not row["sigma_percent"] or _failure(row):
        return None
    summary = row["ours"]["summary"]
    estimate = summary["noise"]["deviation_percent"] * summary["diagonal"]
    return estimate / (row["sigma_percent"] * row["ours"]["eval"]["json"]["diagonal"])


def noise_targets(results):
    """Adds row["targets"] = {name: {"ok": True/False/None (does not apply), "text": ...}},
    row["bound_percent"] and row["noise_ratio"] (noise_ratio()) to every row of Table 2 (see
    BENCHMARKS.md, "Table 2 targets")."""
    rows = [r for r in results["table2"] if r.get("kind") in KIND_LABEL]
    clean = {(r["model"], r["kind"]): r for r in rows if r["sigma_percent"] == 0
             and r["kind"] != "outliers"}
    for r in rows:
        reference_kind = "cloud" if r["kind"] == "outliers" else r["kind"]
        reference = clean.get((r["model"], reference_kind))
        is_reference = reference is r
        eps_clean = row_eps(clean.get((r["model"], "mesh"), {}))
        failure = _failure(r)
        targets = {"run": {"ok": failure is None, "text": failure or "ok"}}
        eps, ref_eps = row_eps(r), row_eps(reference or {})
        if r["kind"] == "outliers":
            bound = ref_eps + OUTLIER_SLACK if ref_eps is not None else None
        else:
            bound = eps_clean + 2 * r["sigma_percent"] if eps_clean is not None else None
        r["eps_clean_percent"], r["bound_percent"] = eps_clean, bound
        r["noise_ratio"] = noise_ratio(r)
        if r["kind"] == "mesh" and r["sigma_percent"] == 0:
            targets["epsilon"] = {"ok": None, "text": "reference ε(clean)"}
        elif failure:
            targets["epsilon"] = {"ok": False, "text": "no ε"}
        elif bound is None:
            targets["epsilon"] = {"ok": None, "text": "no reference ε"}
        else:
            ok = eps <= bound + 1e-9
            targets["epsilon"] = {"ok": ok, "text": f"ε {eps:.2f} {'≤' if ok else '>'} "
                                                    f"{bound:.2f}"}
        components = (r.get("ours") or {}).get("components")
        ref_components = None if reference is None or _failure(reference) else \
            reference["ours"].get("components")
        time_s, ref_time = _time(r), None if reference is None else _time(reference)
        if is_reference:
            targets["components"] = {"ok": None, "text": "reference"}
            targets["time"] = {"ok": None, "text": "reference"}
        else:
            if ref_components != 1:
                targets["components"] = {"ok": None, "text": "clean run not connected"
                                         if ref_components else "no clean run"}
            elif failure or components is None:
                targets["components"] = {"ok": False, "text": "no result"}
            else:
                targets["components"] = {"ok": components == 1,
                                         "text": f"{components} component"
                                                 + ("s" if components != 1 else "")}
            if ref_time is None:
                targets["time"] = {"ok": None, "text": "no clean run"}
            elif failure or time_s is None:
                targets["time"] = {"ok": False, "text": "no result"}
            else:
                ok = time_s <= TIME_FACTOR * ref_time
                targets["time"] = {"ok": ok, "text": f"time {time_s:.2f} {'≤' if ok else '>'} "
                                                     f"{TIME_FACTOR:g}×{ref_time:.2f} s"}
        r["targets"] = targets


TARGET_LETTERS = (("run", "!"), ("epsilon", "ε"), ("components", "c"), ("time", "t"))


def target_mark(row):
    """✓, 'ref' (clean mesh), or ✗ followed by the letters of the targets missed."""
    targets = row.get("targets", {})
    missed = "".join(letter for name, letter in TARGET_LETTERS
                     if targets.get(name, {}).get("ok") is False)
    if missed:
        return "✗" + ("!" if "!" in missed else missed)
    if row["kind"] == "mesh" and row["sigma_percent"] == 0:
        return "ref"
    return "✓"


def target_text(row):
    targets = row.get("targets", {})
    if not targets.get("run", {}).get("ok", True):
        return "✗ failed: " + cell(targets["run"]["text"])[:160]
    missed = [t["text"] for name, _ in TARGET_LETTERS
              if (t := targets.get(name, {})).get("ok") is False]
    if missed:
        return "✗ " + "; ".join(missed)
    return "ref" if row["kind"] == "mesh" and row["sigma_percent"] == 0 else "✓"


def noise_cell(row):
    if row is None:
        return "–"
    if _failure(row) and row_eps(row) is None:
        return "FAILED"
    off = entry_eps(row.get("denoise_off"))
    return f"{cell(row_eps(row), 2)} {target_mark(row)}" + (f" (off {off:.2f})" if off is not None
                                                           else "")


def estimated_noise(row):
    return (row.get("ours") or {}).get("noise_percent")


def format_table2(results, args):
    rows = [r for r in results["table2"] if r.get("kind") in KIND_LABEL]
    by_key = {(r["model"], r["kind"], r["sigma_percent"]): r for r in rows}
    models = list(dict.fromkeys(r["model"] for r in results["table2"]))
    parts = []
    for kind, label in KINDS:
        header = ["model", "M", "ε clean %"] + [f"σ={s:g} %" for s in args.noise]
        if kind == "cloud":
            header.append("1 % outliers")
        lines = []
        for model in models:
            mesh0 = by_key.get((model, "mesh", 0.0))
            line = [model, cell((mesh0 or {}).get("M")),
                    cell(row_eps(mesh0), 2) if mesh0 else "–"]
            line += [noise_cell(by_key.get((model, kind, s))) for s in args.noise]
            if kind == "cloud":
                line.append(noise_cell(by_key.get((model, "outliers", 0.0))))
            lines.append(line)
        parts += [f"**{label}** — ε % against the clean mesh", "", markdown_table(header, lines),
                  ""]
    parts.append("✓: every target met; ✗ then the targets missed: ε (ε > bound), c (more than "
                 "one component while the clean run of that input kind has one), t (time > "
                 f"{TIME_FACTOR:g}× the clean run of that input kind); ✗! failed run or invalid "
                 "output; ref: the clean mesh, which gives ε clean. Bound: ε clean + 2σ "
                 f"(outliers: the σ=0 cloud's ε + {OUTLIER_SLACK:g}). (off x): ε of the same "
                 "input with `--denoise off`.")
    parts += ["", noise_summary(rows)]
    for r in results["table2"]:
        if r.get("kind") not in KIND_LABEL:
            parts.append(f"- {r['model']} not run: {cell(r.get('error'))}")
    worst = results.get("noise_worst")
    if worst and isinstance(worst.get("render"), str):
        parts.append(f"- picture of the worst ε row: `{os.path.basename(worst['render'])}` "
                     "(noisy input | medial mesh | error on the clean mesh)")
    parts += ["", "### Table 2 details", "", noise_details(rows)]
    return "\n".join(parts)


def noise_summary(rows):
    header = ["input", "rows", "ran (valid output)", "ε ≤ bound", "one component",
              "time ≤ 2× clean", "all targets"]
    lines = []

    def count(selection, name):
        checked = [r for r in selection if r["targets"][name]["ok"] is not None]
        return f"{sum(r['targets'][name]['ok'] for r in checked)}/{len(checked)}" \
            if checked else "–"

    groups = [(label, [r for r in rows if r["kind"] == kind])
              for kind, label in KINDS + (OUTLIERS,)] + [("all", rows)]
    for label, selection in groups:
        if not selection:
            continue
        checked = [r for r in selection if any(t["ok"] is not None
                                               for n, t in r["targets"].items() if n != "run")]
        met = sum(all(t["ok"] is not False for t in r["targets"].values()) for r in checked)
        lines.append([label, str(len(selection))] + [count(selection, n) for n in
                                                      ("run", "epsilon", "components", "time")]
                     + [f"{met}/{len(checked)}" if checked else "–"])
    summary = [markdown_table(header, lines), ""]
    excess = sorted(((row_eps(r) - r["bound_percent"], r) for r in rows
                     if row_eps(r) is not None and r.get("bound_percent") is not None
                     and r["targets"]["epsilon"]["ok"] is not None), key=lambda x: -x[0])
    worst = [(d, r) for d, r in excess if d > 0][:5]

    def name(r):
        return f"{r['model']} ({KIND_LABEL[r['kind']]}" + \
            (")" if r["kind"] == "outliers" else f", σ={r['sigma_percent']:g} %)")

    if worst:
        summary.append("- worst ε rows (ε − bound): " + "; ".join(
            f"{name(r)}: {row_eps(r):.2f} > {r['bound_percent']:.2f} (+{d:.2f})" for d, r in worst))
    elif excess:
        d, r = excess[0]
        summary.append(f"- every ε within its bound; closest: {name(r)}: {row_eps(r):.2f} ≤ "
                       f"{r['bound_percent']:.2f} ({d:+.2f})")
    slow = sorted(((r, _time(r) / _time_reference(rows, r)) for r in rows
                   if r["targets"]["time"]["ok"] is False and _time(r) is not None),
                  key=lambda x: -x[1])[:5]
    if slow:
        summary.append("- slowest against their clean run: " + "; ".join(
            f"{name(r)}: {_time(r):.2f} s ({ratio:.1f}×)" for r, ratio in slow))
    split = [r for r in rows if r["targets"]["components"]["ok"] is False and
             (r.get("ours") or {}).get("components")]
    if split:
        summary.append("- not connected: " + "; ".join(
            f"{name(r)}: {r['ours']['components']} components" for r in split))
    compared = [(r, row_eps(r), entry_eps(r["denoise_off"])) for r in rows if r.get("denoise_off")]
    compared = [(r, e, off) for r, e, off in compared if e is not None and off is not None]
    if compared:
        worse = sorted(((e - off, r, e, off) for r, e, off in compared
                        if e > off + DENOISE_SLACK + 1e-9), key=lambda x: -x[0])
        summary.append(
            f"- default ≤ `--denoise off` + {DENOISE_SLACK:g} (never worse than doing nothing): "
            f"{len(compared) - len(worse)}/{len(compared)} noisy rows"
            + ("; misses: " + "; ".join(f"{name(r)}: {e:.2f} > {off:.2f} + {DENOISE_SLACK:g}"
                                        for _, r, e, off in worse[:8]) if worse else ""))
    rated = [r for r in rows if r["noise_ratio"] is not None]
    if rated:
        misses = sorted((r for r in rated if abs(r["noise_ratio"] - 1) > NOISE_TOLERANCE + 1e-9),
                        key=lambda r: -abs(r["noise_ratio"] - 1))

        def met(kinds):
            selection = [r for r in rated if r["kind"] in kinds]
            return f"{len(selection) - sum(r['kind'] in kinds for r in misses)}/{len(selection)}"

        summary.append(
            f"- noise estimate within ±{100 * NOISE_TOLERANCE:g} % of σ (absolute, against the "
            f"clean mesh's diagonal): {met(('cloud', 'normals', 'mesh'))} noisy rows (clouds "
            f"{met(('cloud', 'normals'))}, meshes {met(('mesh',))})"
            + ("; misses: " + "; ".join(f"{name(r)}: ratio {r['noise_ratio']:.2f}"
                                        for r in misses[:8]) + ("; …" if len(misses) > 8 else "")
               if misses else ""))
    failed = [r for r in rows if not r["targets"]["run"]["ok"]]
    if failed:
        summary.append("- failed: " + "; ".join(f"{name(r)}: {cell(r['targets']['run']['text'])}"
                                                for r in failed))
    return "\n".join(summary)


def _time_reference(rows, row):
    kind = "cloud" if row["kind"] == "outliers" else row["kind"]
    for r in rows:
        if r["model"] == row["model"] and r["kind"] == kind and r["sigma_percent"] == 0:
            return _time(r)
    return None


def noise_details(rows):
    header = ["model", "input", "σ %", "ε %", "bound %", "S→M max %", "M→S max %", "time s",
              "wall s", "comp.", "noise est. %", "target"]
    lines = []
    models = list(dict.fromkeys(r["model"] for r in rows))
    kinds = [k for k, _ in KINDS + (OUTLIERS,)]
    for r in sorted(rows, key=lambda r: (models.index(r["model"]), kinds.index(r["kind"]),
                                         r["sigma_percent"])):
        ours = r.get("ours") or {}
        evaluation = ours.get("eval") or {}
        lines.append([r["model"], KIND_LABEL[r["kind"]],
                      "0" if r["kind"] == "outliers" else f"{r['sigma_percent']:g}",
                      cell(row_eps(r), 3), cell(r.get("bound_percent"), 2),
                      cell(evaluation.get("surface_to_medial_max_percent"), 3),
                      cell(evaluation.get("medial_to_surface_max_percent"), 3),
                      cell(ours.get("vmas_total_s"), 2),
                      cell(ours.get("wall_s"), 2), cell(ours.get("components")),
                      "–" if estimated_noise(r) is None else f"{estimated_noise(r):.2g}",
                      target_text(r)])
    return markdown_table(header, lines)


# ---------------------------------------------------------------------------------------------
# Table 3: sparse, open and moved inputs


SPARSE_FACTOR = 1.5  # vertex cloud and 5 000 points: ε at most this × the mesh's at that count
CAP_MAX_EPS = 5.0  # cap cut off: ε against the data at most this
CAP_MAX_COVER = 2.5  # ... every kept point at most this far from the reconstruction (issue 46)
CAP_MAX_REACH = 2.0  # ... which goes at most this far past the cut
OPEN_ENCLOSURE = 0.8  # enclosure figures below this read open
SPREAD_MAX = 0.3  # moved copies: their ε (and the untransformed run's) within this many points


def _enclosure(entry):
    summary = (entry or {}).get("summary") or {}
    holes = summary.get("holes") or {}
    return summary.get("enclosure"), holes.get("count"), holes.get("widest_percent")


def format_table3(results):
    header = ["model", "M", "ε mesh", "vertex cloud", "M'", "ε mesh at M'", "5 000 points",
              "cap cut off: open?", "ε vs data", "lid bound", "data covered within",
              "reach past cut", "ε vs clean mesh",
              "moved meshes: ε spread", "moved vertex clouds: ε spread"]
    lines, tally, misses = [], {}, {}

    def judge(name, ok, text):
        checked, met = tally.get(name, (0, 0))
        tally[name] = (checked + (ok is not None), met + bool(ok))
        if ok is False:
            misses.setdefault(name, []).append(text)
        return ("✓ " if ok else "✗ " if ok is False else "") if ok is not None else ""

    for row in results["table3"]:
        model = row["model"]
        mesh, mesh_sparse = entry_eps(row["mesh"]), entry_eps(row["mesh_sparse_M"])
        line = [model, str(row["M"]), cell(mesh, 2)]
        for key, reference, label in (("vertex_cloud", mesh, "vertex cloud"),
                                      ("sparse", mesh_sparse, "5 000 points")):
            eps, entry = entry_eps(row[key]), row[key]
            components = entry.get("components")
            ok = None if eps is None or reference is None else \
                eps <= SPARSE_FACTOR * reference + 1e-9 and components == 1
            mark = judge(label, ok, f"{model} {cell(eps, 2)} vs {SPARSE_FACTOR:g}×"
                                    f"{cell(reference, 2)}, {components} component(s)")
            line.append(f"{mark}{cell(eps, 2)}" + (f" ({components} c)" if components not in
                                                   (None, 1) else ""))
            if key == "vertex_cloud":
                line += [str(row["sparse_M"]), cell(mesh_sparse, 2)]
        cap = row["cap"]
        enclosure, holes, widest = _enclosure(cap)
        is_open = None if enclosure is None else (bool(holes) or enclosure < OPEN_ENCLOSURE)
        line.append(judge("cap reported open", is_open, f"{model} (winding {enclosure})")
                    + (f"{holes} hole(s), {cell(widest, 1)} %" if holes else
                       f"w {cell(enclosure, 2)}" if enclosure is not None else "–"))
        data_eps, lid = entry_eps(cap, "eval_data"), cap.get("lid_bound_percent")
        line.append(judge("cap ε vs data", None if data_eps is None else
                          data_eps <= CAP_MAX_EPS,
                          f"{model} {cell(data_eps, 2)} (lid bound {cell(lid, 2)})")
                    + cell(data_eps, 2))
        cover = ((cap.get("eval_data") or {}) if not cap.get("error") else {}).get(
            "surface_to_medial_max_percent")
        reach = cap.get("reach_percent")
        line += [cell(lid, 2),
                 judge("cap data covered", None if cover is None else cover <= CAP_MAX_COVER,
                       f"{model} {cell(cover, 2)}") + cell(cover, 2),
                 judge("cap reach past cut", None if reach is None else reach <= CAP_MAX_REACH,
                       f"{model} {cell(reach, 2)}") + cell(reach, 2),
                 cell(entry_eps(cap), 2)]
        for kind in ("mesh", "vertex_cloud"):
            runs = [row[kind]] + row["transforms"][kind]
            own = [entry_eps(r) for r in runs]
            model_units = [_eps_in_model_diagonal(r, row[kind]) for r in runs]
            pieces = {r.get("components") for r in runs}
            if None in own or None in model_units:
                line.append("–")
                continue
            spread = max(model_units) - min(model_units)
            own_spread = max(own) - min(own)
            ok = spread <= SPREAD_MAX + 1e-9 and len(pieces) == 1
            line.append(judge({"mesh": "moved meshes", "vertex_cloud": "moved vertex clouds"}[kind], ok,
                              f"{model} {spread:.2f} ({'/'.join(f'{v:.2f}' for v in model_units)})")
                        + f"{spread:.2f} (own {own_spread:.2f})")
        lines.append(line)
    parts = [markdown_table(header, lines), "",
             f"Vertex cloud: the mesh's vertices without normals at M; 5 000 points: "
             f"{SPARSE_POINTS} random surface samples at M' = min(M, {SPARSE_MAX_SPHERES}); "
             f"target for both: ε ≤ {SPARSE_FACTOR:g} × the mesh's ε at that count, one "
             f"component. Cap cut off: the Table 2 cloud (σ = 0) without the points in the last "
             f"{100 * CAP_FRACTION:g} % of the longest side; targets: reported open (holes found "
             f"or winding number < {OPEN_ENCLOSURE:g}), ε against the data ≤ {CAP_MAX_EPS:g} %; "
             "lid bound: the largest distance from a point of the clean mesh's cross-section by "
             "the cut plane to the nearest kept point, in % of the cut cloud's diagonal like ε "
             "against the data, which no reconstruction whose solid fills the opening can go "
             "below; data covered within: the farthest a kept point lies from the reconstruction "
             f"(target ≤ {CAP_MAX_COVER:g} %); reach: how far the spheres go past the cut (% of the "
             f"diagonal; target ≤ {CAP_MAX_REACH:g} %). Moved: the "
             f"mesh and its vertex cloud under {TRANSFORMS} random similarity transforms "
             "(rotation, scale e^U(−1,1), translation U(−2,2)); target: the spread of ε over "
             f"them and the untransformed run ≤ {SPREAD_MAX:g} points and the same number of "
             "components, ε in % of the untransformed model's diagonal (own: the spread in % of "
             "each copy's own bounding-box diagonal, which a rotation changes).", ""]
    for name, (checked, met) in tally.items():
        parts.append(f"- {name}: {met}/{checked}" + (
            "; misses: " + "; ".join(misses[name]) if misses.get(name) else ""))
    return "\n".join(parts)


# ---------------------------------------------------------------------------------------------
# Scaling


def scaling_run(row):
    """The vmas run of a scaling row, or None if there is none or it failed."""
    ours = row.get("ours")
    return ours if ours and not ours.get("error") else None


def thinning_cell(ours):
    thinning = (ours or {}).get("thinning") or {}
    if thinning.get("points") is None:
        return "–"
    if thinning.get("applied"):
        return f"{thinning['points']} (thinned, voxel {thinning.get('voxel_percent', 0):.3g} %)"
    return f"{thinning['points']} (all)"


# ---------------------------------------------------------------------------------------------
# Real scans


def _scan_cells(entry):
    """ε against its kept points, how far from it they lie at most (coverage), its openings and
    the reach past them, ε against the reconstruction, seconds, peak MB, points dropped, stray
    clusters: of one binary's run (entry of sections.run_scan)."""
    if entry is None:
        return ["–"] * 9
    if entry.get("error"):
        return ["FAILED: " + cell(entry["error"])[:80]] + ["–"] * 8
    summary = entry.get("summary") or {}
    strays = summary.get("stray_clusters") or {}
    rss = entry.get("peak_rss_kb")
    kept = entry.get("eval") or {}
    return [eps_cell(entry.get("eval")), cell(kept.get("surface_to_medial_max_percent"), 2),
            cell(kept.get("openings")), cell(kept.get("reach_percent"), 2),
            eps_cell(entry.get("eval_reconstruction"))
            if entry.get("eval_reconstruction") else "–", cell(entry.get("wall_s"), 2),
            cell(rss / 1024.0, 0) if rss else "–", cell(entry.get("dropped_points")),
            cell(strays.get("count")) if strays else "–"]


def format_scans(results):
    rows = results.get("scans") or []
    with_base = any("base" in row for row in rows)
    header = ["scan", "ε % against its kept points", "kept points within %", "openings",
              "reach past them %", "ε % against the reconstruction",
              "time s", "peak MB", "points dropped", "stray clusters"]
    lines = []
    for row in rows:
        ours = _scan_cells(row.get("ours"))
        if with_base:
            base = _scan_cells(row.get("base"))
            ours = [f"{a} (base {b})" for a, b in zip(ours, base)]
        lines.append([cell(row["scan"])] + ours)
    note = ("\nAt 100 spheres. ε against the points the run kept (labels ≥ 0: outliers and stray "
            "clusters dropped, counted beside) and against the reconstruction where the scan has "
            "one (the Stanford bunny's `bun_zipper.ply`); kept points within: the farthest a kept "
            "point lies from the reconstruction (issue 46's coverage, target ≤ 2.5 %); openings "
            "and the reach past them as `vmas eval` measures them (target ≤ 2 %); (base x): the "
            "same with `--base-vmas` (measured by --vmas).")
    return markdown_table(header, lines) + "\n" + note if rows else "no scans found"


def _coarse_cells(entry):
    """ε, seconds, centres outside, radii off, vertices the run sampled: of one mesh run."""
    if entry is None:
        return ["–"] * 5
    if entry.get("error"):
        return ["FAILED: " + cell(entry["error"])[:80]] + ["–"] * 4
    summary = entry.get("summary") or {}
    invalid = summary.get("invalid_spheres") or {}
    sampling = summary.get("mesh_sampling") or {}
    return [eps_cell(entry.get("eval")), cell(entry.get("wall_s"), 2),
            cell(invalid.get("outside")), cell(invalid.get("radius_off")),
            cell(sampling.get("vertices")) if sampling.get("applied") else "–"]


def format_coarse(results):
    rows = results.get("coarse") or []
    with_base = any("base" in row for row in rows)
    header = ["part", "vertices", "ε % as a mesh", "time s", "centres outside", "radii off",
              "vertices sampled", "ε % of 10 000 points (each cloud)", "mesh ≤ best cloud"]
    lines, met = [], 0
    for row in rows:
        ours = _coarse_cells(row.get("ours"))
        if with_base:
            ours = [f"{a} (base {b})" for a, b in zip(ours, _coarse_cells(row.get("base")))]
        clouds = [entry_eps(c) for c in row["clouds"]]
        mesh = entry_eps(row.get("ours"))
        known = [c for c in clouds if c is not None]
        within = mesh is not None and known and mesh <= min(known)
        met += bool(within)
        lines.append([cell(row["part"]), cell(row["vertices"])] + ours +
                     [" / ".join(cell(c) for c in clouds), "yes" if within else "no"])
    note = (f"\nAt 60 spheres; ε against the mesh. The clouds: 10 000 area-weighted random points "
            f"of the faces with their normals (three seeds). Target (issue 46, item 5): the mesh "
            f"at most the clouds' ε; met on {met} of {len(rows)} (against the best of the three)."
            + (" (base x): the previous release (`--base-vmas`)." if with_base else ""))
    return markdown_table(header, lines) + "\n" + note if rows else "no parts"


def format_scaling(results, args):
    header = ["points", "spheres", "points in the run (thinning)", "wall s", "peak MB",
              "iterations", "ε %"]
    lines = []
    for r in results["scaling"]:
        ours = r.get("ours") or {}
        rss = ours.get("peak_rss_kb")
        line = [cell(r["points"]), cell(r["spheres"]), thinning_cell(scaling_run(r)),
                cell(ours.get("wall_s"), 2), cell(rss / 1024 if rss else None, 1),
                cell(ours.get("iterations")), eps_cell(ours.get("eval"))]
        if r.get("error") or ours.get("error"):
            line[2] = "FAILED: " + cell(r.get("error") or ours["error"])[:160]
        lines.append(line)
    parts = [f"N area-weighted random points of `{args.scaling_model}.off` (seed sequence "
             f"[{args.seed}, CRC-32 of the model, {STREAM_SCALING}, 0, N]), binary PLY without "
             "normals, skeletonized by `vmas skeletonize --spheres M --json` with its default "
             "options (clouds above `--max-points` are thinned); wall s and peak MB "
             "(ru_maxrss / 1024) of the vmas process alone; ε against the clean mesh.", "",
             markdown_table(header, lines), ""]
    plot = results.get("scaling_plot")
    parts.append(f"- plot: `{os.path.basename(plot)}` (wall time against points, log-log)"
                 if isinstance(plot, str) else f"- no plot: {cell((plot or {}).get('error'))}")
    ran = [r for r in results["scaling"] if scaling_run(r)]
    invalid = [f"{r['points']} points, M={r['spheres']}: {'; '.join(r['ours']['checks'])}"
               for r in ran if r["ours"].get("checks")]
    parts.append("- validity checks (exactly M spheres, radii positive and finite, valid "
                 "indices, one connected component): "
                 + ("failed on " + "; ".join(invalid) if invalid else
                    f"passed on all {len(ran)} runs that finished" if ran else "no run finished"))
    return "\n".join(parts)


# The live-editing figures of build/vmas_step_benchmark (tests/benchmarks/step_benchmark.cpp),
# by the benchmark's run name: what each row is.
EDITING_BENCHMARKS = {
    "BM_Step/1": "one step, vessel (49 698 vertices), 200 spheres, 1 thread",
    "BM_Step/2": "one step, vessel, 200 spheres, 2 threads",
    "BM_EditThenStep/1": "remove + split + the step after, vessel, 200 spheres, 1 thread",
    "BM_StepAfterEdit/1": "the step after a remove + split alone, vessel, 200 spheres, 1 thread",
    "BM_StepOnAThinnedScan/2": "one step, 1 M-point armadillo cloud (thinned), 200 spheres, "
                               "2 threads",
    "BM_EditSessionOnAThinnedScan/2/iterations:1/real_time":
        "editor engine (no page), 1 M-point cloud, growing to 200 spheres, then a split and a "
        "removal every 100 ms for 3 s, 2 threads",
}


def format_editing(results):
    """The live-editing figures: the step latency (issue 45's target: at most 4 ms on one thread at
    ~50 000 vertices) and the editor engine's updates per second at 1 M points (at least 10)."""
    row = results.get("editing") or {}
    if row.get("error"):
        return f"not measured: {cell(row['error'])}"
    lines = []
    for b in row.get("benchmarks", []):
        name = b.get("run_name", b.get("name"))
        label = EDITING_BENCHMARKS.get(name, name)
        if "updates_per_s_growing" in b:
            figure = (f"{b['updates_per_s_growing']:.1f} updates/s growing "
                      f"({b.get('growing_s', 0):.1f} s to 200 spheres), "
                      f"{b.get('updates_per_s_editing', 0):.1f} updates/s edited")
            met = min(b["updates_per_s_growing"], b.get("updates_per_s_editing", 0)) >= 10
        else:
            ms = b.get("real_time")
            figure = f"{ms:.2f} ms" if ms is not None else "—"
            met = ms <= 4.0 if name == "BM_Step/1" and ms is not None else None
        lines.append([label, figure, "" if met is None else ("met" if met else "missed")])
    return ("Medians of three repetitions of `vmas_step_benchmark` (Google Benchmark; targets: one "
            "step ≤ 4 ms on one thread at ~50 000 vertices, ≥ 10 updates/s at 1 M points).\n\n"
            + markdown_table(["what", "figure", "target"], lines))
