"""CAD-like test meshes (issue 46, item 5): closed, coarsely tessellated parts of 500-5 000
vertices as a CAD exporter writes them — vertices only where the outline bends, long thin
triangles across flat faces and along straight walls, sharp edges. Made here, not found, so
that nothing was tuned on them: a gear with a bore, a flanged pipe, a stepped shaft, a thin
square tube and a slotted plate."""

import math

import numpy as np


def _ring_quads(rings, closed):
    """Faces joining consecutive rings (each an index array of the same length, itself a closed
    loop); the last ring joins the first when `closed`."""
    faces = []
    count = len(rings) if closed else len(rings) - 1
    for k in range(count):
        a, b = rings[k], rings[(k + 1) % len(rings)]
        n = len(a)
        for i in range(n):
            j = (i + 1) % n
            faces.append((a[i], a[j], b[j]))
            faces.append((a[i], b[j], b[i]))
    return faces


def _outward(points, faces):
    """The faces turned so that the signed volume is positive (normals outward)."""
    faces = np.asarray(faces, dtype=np.int64)
    p = points[faces]
    volume = np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum()
    return faces[:, ::-1].copy() if volume < 0 else faces


def _loft(loops, closed):
    """A mesh through `loops` (each an (n, 3) array, all of the same n): a torus-like surface
    when `closed` (the last loop joins the first)."""
    points = np.concatenate(loops)
    n = len(loops[0])
    rings = [np.arange(k * n, (k + 1) * n) for k in range(len(loops))]
    return points, _outward(points, _ring_quads(rings, closed))


def _extruded_annulus(outer, inner, height):
    """A plate of `height` between the closed outlines `outer` and `inner` ((n, 2), sampled at
    matching parameters): its flat faces are strips of long triangles from rim to rim."""
    def at(outline, z):
        return np.column_stack([outline, np.full(len(outline), z)])
    return _loft([at(outer, 0.0), at(outer, height), at(inner, height), at(inner, 0.0)], True)


def gear(teeth=30, per_tooth=12, outer=1.0, root=0.86, bore=0.32, height=0.28):
    """A spur gear with a round bore (genus 1): 4 x teeth x per_tooth vertices."""
    n = teeth * per_tooth
    angle = np.arange(n) * 2 * math.pi / n
    phase = (np.arange(n) % per_tooth) / per_tooth  # position within a tooth, 0..1
    # Trapezoidal teeth: root, flank up, tip, flank down.
    radius = np.interp(phase, [0.0, 0.2, 0.35, 0.65, 0.8, 1.0], [root, root, outer, outer, root, root])
    rim = np.column_stack([radius * np.cos(angle), radius * np.sin(angle)])
    hole = np.column_stack([bore * np.cos(angle), bore * np.sin(angle)])
    return _extruded_annulus(rim, hole, height)


def _revolved(profile, segments):
    """Loops of the closed (r, z) `profile` revolved about z in `segments` steps."""
    angle = np.arange(segments) * 2 * math.pi / segments
    return [np.column_stack([r * np.cos(angle), r * np.sin(angle), np.full(segments, z)])
            for r, z in profile]


def flanged_pipe(segments=96):
    """A pipe with a flange at each end (genus 1): a closed profile revolved."""
    profile = [(0.30, 0.0), (0.62, 0.0), (0.62, 0.10), (0.38, 0.10), (0.38, 1.40),
               (0.62, 1.40), (0.62, 1.50), (0.30, 1.50), (0.30, 1.10), (0.30, 0.40)]
    return _loft(_revolved(profile, segments), True)


def stepped_shaft(segments=96):
    """A solid shaft of three diameters with a collar (genus 0), its end faces fans around a
    centre vertex."""
    profile = [(0.20, 0.0), (0.20, 0.9), (0.34, 0.9), (0.34, 1.0), (0.28, 1.0), (0.28, 1.9),
               (0.14, 1.9), (0.14, 2.6)]
    points, faces = _loft(_revolved(profile, segments), False)
    last = len(points) - segments
    points = np.vstack([points, [[0.0, 0.0, profile[0][1]], [0.0, 0.0, profile[-1][1]]]])
    bottom, top = len(points) - 2, len(points) - 1
    caps = []
    for i in range(segments):
        j = (i + 1) % segments
        caps.append((bottom, j, i))
        caps.append((top, last + i, last + j))
    return points, _outward(points, np.vstack([faces, caps]))


def _square_outline(half, per_side):
    """A square of half-width `half` sampled `per_side` times a side, counter-clockwise."""
    t = np.arange(per_side) / per_side
    sides = [np.column_stack([-half + 2 * half * t, np.full(per_side, -half)]),
             np.column_stack([np.full(per_side, half), -half + 2 * half * t]),
             np.column_stack([half - 2 * half * t, np.full(per_side, half)]),
             np.column_stack([np.full(per_side, -half), half - 2 * half * t])]
    return np.concatenate(sides)


def square_tube(per_side=60, wall=0.06, length=2.0):
    """A thin-walled square tube (genus 1): long triangles down its walls."""
    outer = _square_outline(0.5, per_side)
    inner = _square_outline(0.5 - wall, per_side)
    return _extruded_annulus(outer, inner, length)


def slotted_plate(per_end=96, width=0.5, length=2.0, slot=0.16, height=0.12):
    """A flat bar with rounded ends and a slot along its middle (genus 1): the outline and the
    slot's outline, both stadiums, sampled at matching angles."""
    def stadium(half_width, half_length):
        half = per_end
        upper = np.linspace(-math.pi / 2, math.pi / 2, half, endpoint=False)
        lower = upper + math.pi
        right = np.column_stack([half_length + half_width * np.cos(upper),
                                 half_width * np.sin(upper)])
        left = np.column_stack([-half_length + half_width * np.cos(lower),
                                half_width * np.sin(lower)])
        return np.concatenate([right, left])
    return _extruded_annulus(stadium(width / 2, length / 2 - width / 2),
                             stadium(slot / 2, length / 2 - width / 2), height)


PARTS = {"gear": gear, "flanged_pipe": flanged_pipe, "stepped_shaft": stepped_shaft,
         "square_tube": square_tube, "slotted_plate": slotted_plate}
