"""What scripts/bench and scripts/render share (numpy only): finding vmas' Python module, and the
writers and small numeric helpers of the benchmark's inputs. Files are read by vmas itself
(vmas.read, vmas.read_medial), never here.
  import_vmas(binary, program) -> the module `vmas` built with the vmas binary `binary`
  write_xyz(path, points, normals=None)
  write_off(path, points, faces)
  bbox_diagonal(points)
  sample_surface(points, faces, count, seed) -> (points, normals), area-weighted
"""

import os
import sys

import numpy as np

REPOSITORY = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def import_vmas(binary, program):
    """The Python module `vmas` built with the vmas binary `binary`, imported from the folder
    python/ beside it (build/vmas: build/python), or from this repository's build/python when
    there is none (a copy of the binary, a wrapper script). Exits with a one-line message when
    it cannot be imported."""
    folder = os.path.join(os.path.dirname(os.path.abspath(binary)), "python")
    if not os.path.isdir(folder):
        folder = os.path.join(REPOSITORY, "build", "python")
    sys.path.insert(0, folder)
    try:
        import vmas
    except ImportError as error:
        sys.exit(f"{program}: cannot import the vmas Python module from {folder} "
                 f"({' '.join(str(error).split())}); build the project (scripts/build)")
    return vmas


# ---------------------------------------------------------------------------------------------
# Writers of the benchmark's inputs


def write_xyz(path, points, normals=None):
    data = points if normals is None else np.hstack([points, normals])
    np.savetxt(path, data, fmt="%.9g")


def write_off(path, points, faces):
    with open(path, "w", encoding="utf-8") as f:
        f.write(f"OFF\n{len(points)} {len(faces)} 0\n")
        np.savetxt(f, points, fmt="%.9g")
        np.savetxt(f, np.column_stack([np.full(len(faces), 3), faces]), fmt="%d")


# ---------------------------------------------------------------------------------------------
# Geometry helpers


def bbox_diagonal(points):
    return float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))


def sample_surface(points, faces, count, seed=1):
    """Area-weighted uniform random points on a triangle mesh, with the faces' unit normals.
    seed: anything numpy.random.default_rng accepts (an int, a list of ints, a Generator)."""
    rng = np.random.default_rng(seed)
    a, b, c = points[faces[:, 0]], points[faces[:, 1]], points[faces[:, 2]]
    cross = np.cross(b - a, c - a)
    area = 0.5 * np.linalg.norm(cross, axis=1)
    chosen = rng.choice(len(faces), size=count, p=area / area.sum())
    u, v = rng.random(count), rng.random(count)
    flip = u + v > 1.0
    u[flip], v[flip] = 1.0 - u[flip], 1.0 - v[flip]
    samples = a[chosen] + u[:, None] * (b[chosen] - a[chosen]) + v[:, None] * (c[chosen] - a[chosen])
    normals = cross[chosen] / np.linalg.norm(cross[chosen], axis=1)[:, None]
    return samples, normals
