"""The density section (issue 51): on a Table 1 model with density 4 on its top, a real scan
with density 4 on its top and a CAD part with the curvature rule, the share of spheres in the
dense region with and without the field, the coverage ε (surface -> medial maximum) in the dense
region and elsewhere, and the time."""

import os

import numpy as np

import vmas_files

from . import cad, running
from .running import evaluate, read_mesh, skeletonize

DENSE = 4.0
# (file name, case, shape, the paper's count or another, the share of points on top made dense;
# None: the curvature rule, dense where it gives at least DENSE_CURVED)
CASES = (("armadillo", "armadillo, top 12 % (head, hands)", "meshes/armadillo.off", 83, 0.12),
         ("bunny", "merged bunny (scan) top", "scans/bunny_merged_45k.xyz", 100, 0.15),
         ("shaft", "stepped shaft (CAD), curvature", None, 60, None))
DENSE_CURVED = 2.5


def _share(labels, dense, spheres):
    """The spheres' mean share of dense points among those they hold: the share of spheres in the
    dense region, a sphere on its border counting in part (a thin dense band, such as a part's
    edges, is no sphere's majority)."""
    labels = np.asarray(labels)
    shares = [dense[labels == s].mean() for s in range(spheres) if np.any(labels == s)]
    return float(np.mean(shares))


def density_section(args, results, save, log):
    work = os.path.join(args.out, "density")
    os.makedirs(work, exist_ok=True)
    for slug, name, relative, spheres, top in CASES:
        if relative:
            shape = os.path.join(args.data, relative)
            points = read_mesh(shape)[0]
            up = int(np.argmax(np.ptp(points, axis=0)))
            cut = np.quantile(points[:, up], 1.0 - top)
            dense = points[:, up] >= cut
            density_file = os.path.join(work, slug + ".density.txt")
            np.savetxt(density_file, np.where(dense, DENSE, 1.0), fmt="%g")
            field = ("--density", density_file)
        else:
            part_points, faces = cad.PARTS["stepped_shaft"]()
            shape = os.path.join(work, "stepped_shaft.off")
            vmas_files.write_off(shape, part_points, faces)
            dense = running.vmas.density_by_rule(part_points, "curvature") >= DENSE_CURVED
            field = ("--density", "curvature")
        row = {"case": name, "spheres": spheres, "dense_points": float(dense.mean())}
        for tag, extra in (("uniform", ()), ("density", field)):
            log(f"[density] {name}: {tag}")
            ply = os.path.join(work, f"{slug}.{tag}.ply")
            labels_path = ply + ".labels"
            entry = skeletonize(args, shape, ply, spheres, extra=(*extra, "--labels", labels_path))
            if entry.get("error"):
                row[tag] = entry
                continue
            errors_path = ply + ".errors"
            entry["eval"] = evaluate(args.vmas, shape, ply, args.timeout, errors_path=errors_path)
            labels = np.loadtxt(labels_path, dtype=int)
            errors = np.loadtxt(errors_path)
            diagonal = vmas_files.bbox_diagonal(read_mesh(shape)[0])
            entry["share"] = _share(labels, dense, spheres)
            entry["cover_dense"] = 100.0 * float(errors[dense].max()) / diagonal
            entry["cover_rest"] = 100.0 * float(errors[~dense].max()) / diagonal
            row[tag] = entry
        results["density"].append(row)
        save()


def format_density(results):
    lines = ["| case | spheres | dense points | share of spheres there: uniform → density (×) | "
             "ε % | coverage % dense / elsewhere: uniform → density | time s: uniform → density |",
             "|---|---|---|---|---|---|---|"]
    for row in results["density"]:
        u, d = row.get("uniform", {}), row.get("density", {})
        if "share" not in u or "share" not in d:
            lines.append(f"| {row['case']} | {row['spheres']} | failed | | | | |")
            continue
        times = [e["wall_s"] for e in (u, d)]
        lines.append(
            f"| {row['case']} | {row['spheres']} | {100 * row['dense_points']:.0f} % | "
            f"{u['share']:.2f} → {d['share']:.2f} ({d['share'] / max(u['share'], 1e-9):.2f} ×) | "
            f"{u['eval'].get('eps_percent', float('nan')):.2f} → "
            f"{d['eval'].get('eps_percent', float('nan')):.2f} | "
            f"{u['cover_dense']:.2f} / {u['cover_rest']:.2f} → {d['cover_dense']:.2f} / "
            f"{d['cover_rest']:.2f} | {times[0]:.2f} → {times[1]:.2f} |")
    return "\n".join(lines)
