"""Small readers and writers for the files the vmas scripts handle (numpy only).

Shapes in any other format are read by `vmas convert` (the library's own readers) into OFF,
medial meshes by `vmas convert --medial` into .ma; scripts/render does so.
Shared by scripts/bench and scripts/render:
  read_off(path)            -> (points (n,3), faces (f,3) int)   OFF / NOFF, comments, polygons fanned
  read_medial_ply(path)     -> MedialMesh (spheres (n,4) x y z r, edges (e,2), faces (f,3))
  read_ma(path)             -> MedialMesh from a Q-MAT / Coverage Axis .ma file
  read_medial(path)         -> either of the two by extension
  read_errors(path)         -> per-vertex error values written by `vmas eval --errors`
  write_xyz(path, points, normals=None)
  write_off(path, points, faces)
  sample_surface(points, faces, count, seed) -> (points, normals), area-weighted
  medial_components(medial) -> number of connected components of the sphere graph
  validate_medial(medial, expected_spheres) -> list of problems (empty when valid)
"""

import re
import struct
from dataclasses import dataclass

import numpy as np


@dataclass
class MedialMesh:
    spheres: np.ndarray  # (n, 4): x y z radius
    edges: np.ndarray  # (e, 2) int
    faces: np.ndarray  # (f, 3) int


# ---------------------------------------------------------------------------------------------
# OFF (read) and OFF / XYZ (written)


def _tokens_without_comments(text):
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            yield line


def read_off(path):
    with open(path, "r", encoding="utf-8", errors="replace") as f:
        lines = list(_tokens_without_comments(f.read()))
    header = lines[0].split()
    keyword = header[0].upper()
    if not keyword.endswith("OFF"):
        raise ValueError(f"{path}: not an OFF file (header {header[0]!r})")
    rest = header[1:]
    index = 1
    if len(rest) < 3:
        rest = lines[1].split()
        index = 2
    nv, nf = int(rest[0]), int(rest[1])
    points = np.array([[float(x) for x in lines[index + i].split()[:3]] for i in range(nv)],
                      dtype=np.float64).reshape(-1, 3)
    faces = []
    for line in lines[index + nv:index + nv + nf]:
        values = [int(x) for x in line.split()]
        count, ids = values[0], values[1:1 + values[0]]
        for k in range(1, count - 1):  # fan polygons into triangles
            faces.append((ids[0], ids[k], ids[k + 1]))
    return points, np.array(faces, dtype=np.int64).reshape(-1, 3)


def write_xyz(path, points, normals=None):
    data = points if normals is None else np.hstack([points, normals])
    np.savetxt(path, data, fmt="%.9g")


def write_off(path, points, faces):
    with open(path, "w", encoding="utf-8") as f:
        f.write(f"OFF\n{len(points)} {len(faces)} 0\n")
        np.savetxt(f, points, fmt="%.9g")
        np.savetxt(f, np.column_stack([np.full(len(faces), 3), faces]), fmt="%d")


# ---------------------------------------------------------------------------------------------
# PLY (ASCII and binary, any element order; lists supported)

_PLY_TYPES = {
    "char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h",
    "ushort": "H", "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I",
    "float": "f", "float32": "f", "double": "d", "float64": "d",
}


def read_ply(path):
    """Returns {element name: {property name: list/array of values}} (lists as lists of tuples)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise ValueError(f"{path}: not a PLY file")
    newline = data.find(b"\n", end)
    header = data[:end].decode("ascii", errors="replace").splitlines()
    body = data[newline + 1:]
    fmt = None
    elements = []  # [name, count, [(prop name, type, list count type or None)]]
    for line in header:
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "format":
            fmt = parts[1]
        elif parts[0] == "element":
            elements.append([parts[1], int(parts[2]), []])
        elif parts[0] == "property":
            if parts[1] == "list":
                elements[-1][2].append((parts[4], _PLY_TYPES[parts[3]], _PLY_TYPES[parts[2]]))
            else:
                elements[-1][2].append((parts[2], _PLY_TYPES[parts[1]], None))
    result = {}
    if fmt == "ascii":
        tokens = body.decode("ascii", errors="replace").split()
        pos = 0
        for name, count, props in elements:
            columns = {p[0]: [] for p in props}
            for _ in range(count):
                for pname, ptype, ltype in props:
                    if ltype is None:
                        columns[pname].append(float(tokens[pos]))
                        pos += 1
                    else:
                        n = int(tokens[pos])
                        columns[pname].append(tuple(int(t) for t in tokens[pos + 1:pos + 1 + n]))
                        pos += 1 + n
            result[name] = columns
        return result
    if fmt not in ("binary_little_endian", "binary_big_endian"):
        raise ValueError(f"{path}: unsupported PLY format {fmt!r}")
    order = "<" if fmt == "binary_little_endian" else ">"
    pos = 0
    for name, count, props in elements:
        if all(p[2] is None for p in props):  # fixed-size records: one numpy read
            dtype = np.dtype([(p[0], order + p[1]) for p in props])
            array = np.frombuffer(body, dtype=dtype, count=count, offset=pos)
            pos += dtype.itemsize * count
            result[name] = {p[0]: array[p[0]] for p in props}
            continue
        columns = {p[0]: [] for p in props}
        for _ in range(count):
            for pname, ptype, ltype in props:
                if ltype is None:
                    (value,) = struct.unpack_from(order + ptype, body, pos)
                    pos += struct.calcsize(ptype)
                    columns[pname].append(value)
                else:
                    (n,) = struct.unpack_from(order + ltype, body, pos)
                    pos += struct.calcsize(ltype)
                    values = struct.unpack_from(order + ptype * n, body, pos)
                    pos += struct.calcsize(ptype) * n
                    columns[pname].append(values)
        result[name] = columns
    return result


def _first_key(columns, names):
    for name in names:
        if name in columns:
            return columns[name]
    return None


def read_medial_ply(path):
    ply = read_ply(path)
    vertex = ply.get("vertex", {})
    radius = _first_key(vertex, ("radius", "r"))
    if radius is None:
        raise ValueError(f"{path}: vertex element has no radius property")
    spheres = np.column_stack([np.asarray(vertex[k], dtype=np.float64)
                               for k in ("x", "y", "z")] + [np.asarray(radius, np.float64)])
    edges = np.zeros((0, 2), dtype=np.int64)
    if "edge" in ply:
        e = ply["edge"]
        a, b = _first_key(e, ("vertex1", "v1")), _first_key(e, ("vertex2", "v2"))
        if a is not None and b is not None:
            edges = np.column_stack([np.asarray(a, np.int64), np.asarray(b, np.int64)])
    faces = np.zeros((0, 3), dtype=np.int64)
    if "face" in ply:
        lists = _first_key(ply["face"], ("vertex_indices", "vertex_index"))
        if lists is not None:
            tris = []
            for ids in lists:
                for k in range(1, len(ids) - 1):
                    tris.append((ids[0], ids[k], ids[k + 1]))
            faces = np.array(tris, dtype=np.int64).reshape(-1, 3)
    return MedialMesh(spheres.reshape(-1, 4), edges.reshape(-1, 2), faces)


def read_ma(path):
    with open(path, "r", encoding="utf-8", errors="replace") as f:
        lines = list(_tokens_without_comments(f.read()))
    nv, ne, nf = (int(x) for x in lines[0].split()[:3])
    spheres, edges, faces = [], [], []
    for line in lines[1:]:
        parts = line.split()
        if parts[0] == "v":
            spheres.append([float(x) for x in parts[1:5]])
        elif parts[0] == "e":
            edges.append([int(x) for x in parts[1:3]])
        elif parts[0] == "f":
            faces.append([int(x) for x in parts[1:4]])
    if len(spheres) != nv:
        raise ValueError(f"{path}: header says {nv} spheres, found {len(spheres)}")
    del ne, nf
    return MedialMesh(np.array(spheres, np.float64).reshape(-1, 4),
                      np.array(edges, np.int64).reshape(-1, 2),
                      np.array(faces, np.int64).reshape(-1, 3))


def read_medial(path):
    return read_ma(path) if str(path).lower().endswith(".ma") else read_medial_ply(path)


def read_errors(path):
    """Per-vertex errors of `vmas eval --errors`: one number per line (last column is used if a
    line has several); '#' comments and non-numeric header lines are skipped."""
    values = []
    with open(path, "r", encoding="utf-8", errors="replace") as f:
        for line in f:
            line = line.split("#", 1)[0].strip()
            if not line:
                continue
            try:
                values.append(float(re.split(r"[\s,;]+", line)[-1]))
            except ValueError:
                continue
    return np.array(values, dtype=np.float64)


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


def medial_components(medial):
    """Connected components of the graph whose nodes are the spheres and whose links are the
    edges and the faces' sides (union-find)."""
    n = len(medial.spheres)
    parent = list(range(n))

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    links = [tuple(e) for e in medial.edges.tolist()]
    for f in medial.faces.tolist():
        links += [(f[0], f[1]), (f[1], f[2]), (f[0], f[2])]
    for i, j in links:
        if 0 <= i < n and 0 <= j < n:
            ri, rj = find(i), find(j)
            if ri != rj:
                parent[ri] = rj
    return len({find(i) for i in range(n)})


def validate_medial(medial, expected_spheres=None):
    """Validity conditions of a medial mesh; returns a list of short problem strings."""
    problems = []
    n = len(medial.spheres)
    if expected_spheres is not None and n != expected_spheres:
        problems.append(f"{n} spheres (expected {expected_spheres})")
    if n == 0:
        return problems + ["empty"]
    r = medial.spheres[:, 3]
    centres = medial.spheres[:, :3]
    bad_radius = int(np.count_nonzero(~np.isfinite(r) | (r <= 0)))
    if bad_radius:
        problems.append(f"{bad_radius} radii not positive and finite")
    if not np.all(np.isfinite(centres)):
        problems.append("non-finite centres")
    for name, ids in (("edge", medial.edges), ("face", medial.faces)):
        if ids.size and (ids.min() < 0 or ids.max() >= n):
            problems.append(f"{name} index out of range")
        if ids.size:
            repeated = int(np.count_nonzero(np.any(ids[:, :1] == ids[:, 1:], axis=1)))
            if ids.shape[1] == 3:
                repeated += int(np.count_nonzero(ids[:, 1] == ids[:, 2]))
            if repeated:
                problems.append(f"{repeated} {name}s with a repeated index")
    if not problems or all("index" not in p for p in problems):
        components = medial_components(medial)
        if components != 1:
            problems.append(f"{components} components")
    return problems
