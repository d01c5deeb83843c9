"""The benchmark's inputs: the paper's table (DATA/paper_tables.tsv: each model's sphere count M
and the paper's figures) and the files the bench generates, each from its own seed sequence
[--seed, CRC-32 of the model, stream, ...] so that it depends on its row alone: Table 2's noisy
clouds and meshes and the outlier cloud, Table 3's sparse, cut and moved copies, the scaling
clouds."""

import os
import zlib

import numpy as np

import vmas_files


def read_paper_table(path):
    rows = {}
    with open(path, encoding="utf-8") as f:
        lines = [l.rstrip("\n") for l in f if l.strip() and not l.startswith("#")]
    header = lines[0].split("\t")
    for line in lines[1:]:
        values = dict(zip(header, line.split("\t")))
        row = {}
        for k, v in values.items():
            try:
                row[k] = int(v) if k in ("vertices", "M") else float(v)
            except ValueError:
                row[k] = v
        rows[values["model"]] = row
    return rows


# ---------------------------------------------------------------------------------------------
# Seeds


# streams of the seed sequence [--seed, model, stream, 1000 σ]: each row's data depends on
# (seed, model, kind, σ) alone, whatever else is run
STREAM_SAMPLES, STREAM_CLOUD_NOISE, STREAM_MESH_NOISE, STREAM_OUTLIERS = 0, 1, 2, 3
STREAM_SPARSE, STREAM_TRANSFORMS = 4, 5  # Table 3 (transforms: σ slot = transform index)
STREAM_SCALING = 4  # seed of a scaling cloud: [--seed, CRC-32 of the model, 4, 0, N]
STREAM_CAD = 6  # a coarse part's clouds: σ slot = the cloud's index


def seed_sequence(seed, model, stream, sigma=0.0):
    """Seed of numpy's generator for one (model, stream, σ): [seed, CRC-32 of the model name,
    stream, 1000 σ]."""
    return [seed, zlib.crc32(model.encode()), stream, int(round(sigma * 1000))]


# ---------------------------------------------------------------------------------------------
# Table 2: noisy clouds and meshes, outliers


OUTLIER_FRACTION = 0.01


def sigma_name(sigma):
    return f"{sigma:g}".replace(".", "p")


def noise_inputs(args, model, shape, points, faces, work):
    """Writes the inputs of one model; yields (kind, σ, path, point count, seed sequence).
    The clean mesh (kind mesh, σ = 0) is the model's own file."""
    diagonal = vmas_files.bbox_diagonal(points)
    samples, normals = vmas_files.sample_surface(
        points, faces, args.cloud_points, seed_sequence(args.seed, model, STREAM_SAMPLES))
    for sigma in args.noise:  # the clean mesh first: it gives ε(clean)
        if sigma == 0:
            yield "mesh", 0.0, shape, len(points), None
        else:
            off = os.path.join(work, f"{model}_mesh_s{sigma_name(sigma)}.off")
            seed = seed_sequence(args.seed, model, STREAM_MESH_NOISE, sigma)
            noise = np.random.default_rng(seed).normal(scale=sigma / 100 * diagonal,
                                                       size=points.shape)
            vmas_files.write_off(off, points + noise, faces)
            yield "mesh", sigma, off, len(points), seed
    for sigma in args.noise:
        # the same noise for both cloud kinds: they differ by the normals alone
        seed = seed_sequence(args.seed, model, STREAM_CLOUD_NOISE, sigma)
        cloud = samples if sigma == 0 else samples + np.random.default_rng(seed).normal(
            scale=sigma / 100 * diagonal, size=samples.shape)
        for kind, with_normals in (("cloud", None), ("normals", normals)):
            xyz = os.path.join(work, f"{model}_{kind}_s{sigma_name(sigma)}.xyz")
            vmas_files.write_xyz(xyz, cloud, with_normals)
            yield kind, sigma, xyz, len(cloud), seed
    seed = seed_sequence(args.seed, model, STREAM_OUTLIERS)
    rng = np.random.default_rng(seed)
    cloud = samples.copy()
    replaced = rng.choice(len(cloud), size=int(round(OUTLIER_FRACTION * len(cloud))),
                          replace=False)
    lo, hi = points.min(axis=0), points.max(axis=0)
    cloud[replaced] = rng.uniform(lo, hi, size=(len(replaced), 3))
    xyz = os.path.join(work, f"{model}_outliers.xyz")
    vmas_files.write_xyz(xyz, cloud)
    yield "outliers", 0.0, xyz, len(cloud), seed


# ---------------------------------------------------------------------------------------------
# Table 3: sparse, cut and moved copies


SPARSE_POINTS = 5000  # the "5 000 points" kind
SPARSE_MAX_SPHERES = 60  # ... run at min(M, this)
CAP_FRACTION = 0.1  # cap cut off: the points in the last 10 % of the longest side are removed
TRANSFORMS = 3  # similarity transforms per model and input kind


def random_rotation(rng):
    q = rng.normal(size=4)
    a, b, c, d = q / np.linalg.norm(q)
    return np.array([[a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)],
                     [2 * (b * c + a * d), a * a - b * b + c * c - d * d, 2 * (c * d - a * b)],
                     [2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d]])


def sparse_cloud(args, model, points, faces, path):
    """The "5 000 points" input: SPARSE_POINTS area-weighted random surface points without
    normals, written to `path`."""
    sparse, _ = vmas_files.sample_surface(points, faces, SPARSE_POINTS,
                                          seed_sequence(args.seed, model, STREAM_SPARSE))
    vmas_files.write_xyz(path, sparse)


def cap_cut(args, model, points, faces, path):
    """The "cap cut off" input, written to `path`: the Table 2 cloud's samples (σ = 0), the end
    of the longest side cut off. Returns (the points kept, the axis of the cut, the cut
    plane's coordinate on it)."""
    samples, _ = vmas_files.sample_surface(points, faces, args.cloud_points,
                                           seed_sequence(args.seed, model, STREAM_SAMPLES))
    low, high = points.min(axis=0), points.max(axis=0)
    axis = int(np.argmax(high - low))
    cut = low[axis] + (1.0 - CAP_FRACTION) * (high[axis] - low[axis])
    kept = samples[samples[:, axis] <= cut]
    vmas_files.write_xyz(path, kept)
    return kept, axis, cut


LID_SPACING = 0.0025  # lid bound: grid spacing on the cut plane, fraction of the diagonal
LID_GRID = 40000  # ... coarser if the grid would have more points than this


def lid_bound(points, faces, kept, axis, cut):
    """The "lid bound" of the cap cut off, in % of the cut cloud's diagonal (as `vmas eval`
    normalises ε against the data): the largest distance from a point of the clean mesh's
    cross-section by the cut plane to the nearest kept point. A solid that fills the opening
    holds such a point x, and the ray from x away from the data leaves the solid at a boundary
    point at least as far from every kept point (all lie on the other side of the plane), so no
    reconstruction that closes the opening has an ε against the data below it. Measured exactly
    at the points of a grid (LID_SPACING) inside the cross-section, so it stays a lower bound,
    at most about a grid spacing below the exact max; None if no grid point is inside."""
    u, v = [a for a in range(3) if a != axis]
    # the cross-section: a segment per triangle whose vertices lie on both sides of the plane
    corners = points[faces]
    below = corners[:, :, axis] < cut
    ends, crossed = [], []
    for i, j in ((0, 1), (1, 2), (2, 0)):
        a, b = corners[:, i], corners[:, j]
        crossed.append(below[:, i] != below[:, j])
        t = (cut - a[:, axis]) / np.where(crossed[-1], b[:, axis] - a[:, axis], 1.0)
        ends.append(a[:, [u, v]] + t[:, None] * (b[:, [u, v]] - a[:, [u, v]]))
    segments = np.stack(ends, axis=1)[np.stack(crossed, axis=1)].reshape(-1, 2, 2)
    if len(segments) == 0:
        return None
    # grid points inside by the even–odd rule, a row of the grid at a time
    diagonal = vmas_files.bbox_diagonal(kept)
    low, high = segments.min(axis=(0, 1)), segments.max(axis=(0, 1))
    spacing = max(LID_SPACING * diagonal, np.sqrt(np.prod(high - low) / LID_GRID))
    columns = np.arange(low[0] + spacing / 2, high[0], spacing)
    rows = np.arange(low[1] + spacing / 2, high[1], spacing)
    (u0, v0), (u1, v1) = segments[:, 0].T, segments[:, 1].T
    odd = []
    for row in rows:
        spans = (v0 <= row) != (v1 <= row)
        crossings = np.sort(u0[spans] + (row - v0[spans]) * (u1[spans] - u0[spans])
                            / (v1[spans] - v0[spans]))
        odd.append(np.searchsorted(crossings, columns) % 2 == 1)
    grid_u, grid_v = np.meshgrid(columns, rows)
    inside = np.column_stack([grid_u[odd], grid_v[odd]])
    if len(inside) == 0:
        return None

    def farthest(cloud):
        """Max over the inside points of the distance to the nearest point of `cloud`."""
        nearest = [np.min((chunk[:, :1] - cloud[:, u]) ** 2 + (chunk[:, 1:] - cloud[:, v]) ** 2
                          + (cloud[:, axis] - cut) ** 2, axis=1)
                   for chunk in np.array_split(inside, 1 + len(inside) * len(cloud) // 10**7)]
        return float(np.sqrt(np.concatenate(nearest).max()))

    # an upper bound from the kept points near the plane; every point farther from the plane
    # than it is farther from each inside point than that point's nearest, so the second pass
    # over the points within it of the plane is exact
    near = kept[kept[:, axis] >= cut - 0.01 * diagonal]
    bound = farthest(near) if len(near) else np.inf
    return 100.0 * farthest(kept[kept[:, axis] >= cut - bound]) / diagonal


def moved_copy(args, model, points, faces, t, base):
    """Moved copy `t` of a mesh: a random rotation, a scale e^U(−1,1) and a translation U(−2,2)
    per axis; writes the mesh BASE_moved<t>.off and its vertex cloud BASE_moved<t>.xyz. Returns
    (the mesh's path, the cloud's path, the scale)."""
    rng = np.random.default_rng(seed_sequence(args.seed, model, STREAM_TRANSFORMS, t))
    rotation, scale = random_rotation(rng), float(np.exp(rng.uniform(-1.0, 1.0)))
    moved = points @ rotation.T * scale + rng.uniform(-2.0, 2.0, size=3)
    off, xyz = base + f"_moved{t}.off", base + f"_moved{t}.xyz"
    vmas_files.write_off(off, moved, faces)
    vmas_files.write_xyz(xyz, moved)
    return off, xyz, scale


# ---------------------------------------------------------------------------------------------
# Scaling


def scaling_cloud(args, model, points, faces, count, work):
    """OUT/scaling/<model>_<count>.ply: `count` area-weighted random surface points without
    normals, binary little-endian PLY (float x y z). A file with the same header (count, model,
    seed) and size is kept. Returns (path, seed sequence, True if it was kept)."""
    seed = seed_sequence(args.seed, model, STREAM_SCALING) + [count]
    path = os.path.join(work, f"{model}_{count}.ply")
    header = ("ply\nformat binary_little_endian 1.0\n"
              f"comment scripts/bench: {count} area-weighted random points of {model}.off, "
              f"seed sequence {seed}\n"
              f"element vertex {count}\nproperty float x\nproperty float y\nproperty float z\n"
              "end_header\n").encode()
    try:
        with open(path, "rb") as f:
            if f.read(len(header)) == header and \
                    os.path.getsize(path) == len(header) + 12 * count:
                return path, seed, True
    except OSError:
        pass
    samples, _ = vmas_files.sample_surface(points, faces, count, seed)
    with open(path + ".tmp", "wb") as f:
        f.write(header)
        samples.astype("<f4").tofile(f)
    os.replace(path + ".tmp", path)
    return path, seed, False


# ---------------------------------------------------------------------------------------------
# Real scans


def _quaternion_matrix(x, y, z, w):
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def merged_range_scans(conf, read_points, path):
    """The range scans a Stanford .conf lists (`bmesh FILE tx ty tz qx qy qz qw`: a point p of
    the scan goes to R(q)ᵀp + t), merged into one cloud written to `path` (x y z), as a
    registration pipeline hands it on; kept when already there. `read_points(file)`: its points
    as stored. Returns `path`."""
    if os.path.isfile(path):
        return path
    folder, merged = os.path.dirname(conf), []
    with open(conf, encoding="utf-8") as f:
        for line in f:
            words = line.split()
            if len(words) != 9 or words[0] != "bmesh":
                continue
            t, q = np.array(words[2:5], float), [float(v) for v in words[5:9]]
            merged.append(np.asarray(read_points(os.path.join(folder, words[1]))) @
                          _quaternion_matrix(*q) + t)
    vmas_files.write_xyz(path + ".tmp", np.vstack(merged))
    os.replace(path + ".tmp", path)
    return path
