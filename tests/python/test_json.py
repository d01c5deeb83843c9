"""Every command's --json output against docs/json.schema.json, and docs/json.md describing every
field the schema names. Run by ctest (VMAS_CLI: the vmas binary)."""

import json
import os
import re
import subprocess

import jsonschema
import numpy as np
import pytest

VMAS_CLI = os.environ.get("VMAS_CLI", "")
DOCS = os.path.join(os.path.dirname(__file__), "..", "..", "docs")
with open(os.path.join(DOCS, "json.schema.json")) as f:
    SCHEMA = json.load(f)

pytestmark = pytest.mark.skipif(not VMAS_CLI, reason="VMAS_CLI (the vmas binary) is not set")


def icosphere_off(path):
    """An octahedron subdivided three times, pushed onto the unit sphere."""
    vertices = [np.array(v, float) for v in
                [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]]
    faces = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
    for _ in range(3):
        middle, split = {}, []

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                vertices.append((vertices[a] + vertices[b]) / 2)
                middle[key] = len(vertices) - 1
            return middle[key]
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            split += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
        faces = split
    with open(path, "w") as f:
        f.write(f"OFF\n{len(vertices)} {len(faces)} 0\n")
        for v in vertices:
            f.write("%.9f %.9f %.9f\n" % tuple(v / np.linalg.norm(v)))
        for face in faces:
            f.write("3 %d %d %d\n" % face)


def lines_of(args, expected_code):
    done = subprocess.run([VMAS_CLI] + args, capture_output=True, text=True, timeout=300)
    assert done.returncode == expected_code, done.stderr
    objects = [json.loads(line) for line in done.stdout.splitlines() if line.strip()]
    assert objects, f"no JSON from vmas {' '.join(args)}"
    return objects


def valid(objects, kind):
    for o in objects:
        jsonschema.validate(o, SCHEMA)  # the whole schema: one of its kinds
        jsonschema.validate(o, {"$ref": f"#/definitions/{kind}", **{"definitions": SCHEMA["definitions"]}})


def test_every_command_prints_what_the_schema_says(tmp_path):
    ball = str(tmp_path / "ball.off")
    icosphere_off(ball)
    cloud = str(tmp_path / "ellipsoid.xyz")
    on_sphere = np.random.default_rng(3).normal(size=(2000, 3))
    on_sphere /= np.linalg.norm(on_sphere, axis=1)[:, None]
    np.savetxt(cloud, on_sphere * [1.0, 0.6, 0.4], fmt="%.6f")  # an ellipsoid, without normals
    out = str(tmp_path / "ball.ply")
    valid(lines_of(["skeletonize", ball, "-n", "8", "-o", out, "--json"], 0), "skeletonize")
    valid(lines_of(["skeletonize", ball, "-n", "8", "-o", out, "--json", "--eval"], 0),
          "skeletonize")
    batch = lines_of(["skeletonize", ball, cloud, "-n", "8", "--output-dir",
                      str(tmp_path / "out"), "--json"], 0)
    assert len(batch) == 2
    valid(batch, "skeletonize")
    # A batch with one missing input: a failure line for it, the other as usual.
    mixed = lines_of(["skeletonize", ball, str(tmp_path / "missing.xyz"), "-n", "8",
                      "--output-dir", str(tmp_path / "out2"), "--json"], 1)
    valid([mixed[0]], "skeletonize")
    valid([mixed[1]], "failure")
    # A summary file's lines, and an input --resume skips.
    summary = str(tmp_path / "out2" / "summary.jsonl")
    again = ["skeletonize", ball, str(tmp_path / "missing.xyz"), "-n", "8", "--output-dir",
             str(tmp_path / "out2"), "--json", "--summary", summary, "--resume"]
    lines_of(again, 1)
    with open(summary) as f:
        kept = [json.loads(line) for line in f]
    valid([kept[0]], "skeletonize")
    valid([kept[1]], "failure")
    resumed = lines_of(again, 1)
    valid([resumed[0]], "skipped")
    valid([resumed[1]], "failure")
    # What a launcher asks before and after its runs (--pending): the input still to run, and why.
    pending = lines_of(again + ["--pending", str(tmp_path / "todo")], 0)
    assert [p["input"] for p in pending] == [str(tmp_path / "missing.xyz")]
    valid(pending, "pending")
    valid(lines_of(["skeletonize", ball, "-n", "0", "-o", out, "--json"], 2), "failure")
    valid(lines_of(["eval", ball, out, "--json"], 0), "eval")
    valid(lines_of(["eval", str(tmp_path / "missing.off"), out, "--json"], 1), "failure")


def test_the_docs_describe_every_field_of_the_schema():
    with open(os.path.join(DOCS, "json.md")) as f:
        docs = f.read()
    named = set()

    def walk(node):
        if isinstance(node, dict):
            for name, value in node.get("properties", {}).items():
                named.add(name)
                walk(value)
            for key in ("definitions",):
                for value in node.get(key, {}).values():
                    walk(value)
    walk(SCHEMA)
    missing = sorted(n for n in named if not re.search(r"`%s`" % re.escape(n), docs))
    assert not missing, f"docs/json.md does not describe {missing}"
