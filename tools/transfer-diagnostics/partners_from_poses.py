#!/usr/bin/env python3
"""Which source triangle each target triangle's deformation in a set of results came from.

An analysis tool, not part of the tests (numpy and scipy). Given a source
reference with poses and target results of the same poses (Sumner's camel
poses, or meshmorph's own output as a control), each target triangle's
deformation gradients over all poses are compared with those of the source
triangles that the saved correspondence's deformed source puts near it. The
source triangles whose gradients agree best (a soft minimum of the summed
squared differences, within RADIUS of the diagonal) show where the results'
own correspondence put the source: the offset from meshmorph's partners to
them, in fractions of the target's bounding-box diagonal, is printed per region
and at the markers. Only triangles whose best candidate agrees at least 1.5
times better than meshmorph's partners count (elsewhere, in parts that move
rigidly, every nearby candidate agrees as well and the offset means nothing).

With --write FILE, a marker file is written in which the source vertex of each
marker in the neck region (horse -> camel) is replaced by the vertex nearest to
where the results' correspondence puts it: a diagnostic of how much the marker
placement weighs, never a choice of markers.

usage: partners_from_poses.py CORR DEFORMED MARKERS [--results PATTERN]
           [--radius R] [--write FILE] [--data DIR]

CORR and DEFORMED come from `meshmorph correspond --no-align -o CORR
--deformed-source DEFORMED`; PATTERN (default: Sumner's camel poses) is a
path with %02d for the pose number 1..10.
"""
import argparse
import os

import numpy as np
from scipy.spatial import cKDTree

from diagnose import frames, read_obj, read_pairs


def gradients(rest, poses, f):
    inv = np.linalg.inv(frames(rest, f)[0])
    return np.stack([frames(p, f)[0] @ inv for p in poses], 1).reshape(len(f), -1)


def read_markers(path):
    rows = [l.replace(",", " ").split() for l in open(path).read().split("\n")]
    rows = [r for r in rows if len(r) == 2]
    return np.array([[int(a), int(b)] for a, b in rows])


# Regions of the camel reference (y up, z along the body towards the head).
def regions(c):
    y, z = c[:, 1], c[:, 2]
    return [
        ("legs", y < 0.3),
        ("body", (y >= 0.3) & (z < 0.15)),
        ("neck base", (y >= 0.3) & (z >= 0.15) & (y < 0.55)),
        ("neck", (z >= 0.15) & (y >= 0.55) & (y < 0.75)),
        ("head", (z >= 0.15) & (y >= 0.75)),
    ]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("corr")
    ap.add_argument("deformed")
    ap.add_argument("markers")
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--data", default=os.path.join(here, "../../../shared/data/dt/horse-camel"))
    ap.add_argument("--results", default=None)
    ap.add_argument("--radius", type=float, default=0.03)
    ap.add_argument("--write", default=None)
    a = ap.parse_args()
    d = a.data
    results = a.results or os.path.join(d, "camel-poses/camel-%02d.obj")
    hv, hf = read_obj(os.path.join(d, "horse-poses/horse-reference.obj"))
    cv, cf = read_obj(os.path.join(d, "camel-poses/camel-reference.obj"))
    source = gradients(hv, [read_obj(os.path.join(d, "horse-poses/horse-%02d.obj" % i))[0]
                            for i in range(1, 11)], hf)
    target = gradients(cv, [read_obj(results % i)[0] for i in range(1, 11)], cf)
    dv, _ = read_obj(a.deformed)
    pairs = read_pairs(a.corr)
    diag = np.linalg.norm(cv.max(0) - cv.min(0))
    hc, cc = dv[hf].mean(1), cv[cf].mean(1)

    # meshmorph's partners: their mean centroid on the deformed source, their cost.
    count = np.bincount(pairs[:, 1], minlength=len(cf)).astype(float)
    paired = count > 0
    ours = np.zeros((len(cf), 3))
    np.add.at(ours, pairs[:, 1], hc[pairs[:, 0]])
    ours[paired] /= count[paired][:, None]
    cost_ours = np.zeros(len(cf))
    np.add.at(cost_ours, pairs[:, 1], ((source[pairs[:, 0]] - target[pairs[:, 1]]) ** 2).sum(1))
    cost_ours[paired] /= count[paired]

    # The results' partners: a soft minimum over nearby source triangles.
    near = cKDTree(hc).query_ball_point(cc, a.radius * diag)
    theirs = np.full((len(cf), 3), np.nan)
    cost_best = np.zeros(len(cf))
    for t in np.nonzero(paired)[0]:
        cand = np.array(near[t])
        if len(cand) == 0:
            continue
        cost = ((source[cand] - target[t]) ** 2).sum(1)
        best = cost.min()
        w = np.exp(-(cost - best) / (0.25 * best + 1e-12))
        theirs[t] = (w[:, None] * hc[cand]).sum(0) / w.sum()
        cost_best[t] = best
    offset = (theirs - ours) / diag
    sharp = paired & ~np.isnan(theirs[:, 0]) & (cost_ours > 1.5 * cost_best)

    markers = read_markers(a.markers)
    at_marker = np.isin(cf, markers[:, 1]).any(1)
    print("region      triangles (sharp / paired)   median offset x y z     at the markers")
    for name, sel in regions(cc):
        s, m = sharp & sel, sharp & sel & at_marker
        print("%-10s %6d / %6d   %+.4f %+.4f %+.4f   %4d  %+.4f %+.4f %+.4f" % (
            (name, s.sum(), (paired & sel).sum()) + tuple(np.median(offset[s], 0))
            + (m.sum(),) + tuple(np.median(offset[m], 0) if m.any() else (np.nan,) * 3)))

    # Per neck marker: the mean offset of the sharp triangles around its target vertex.
    total = np.zeros((len(cv), 3))
    n = np.zeros(len(cv))
    for k in range(3):
        np.add.at(total, cf[:, k], np.where(sharp[:, None], offset, 0.0))
        np.add.at(n, cf[:, k], sharp.astype(float))
    moved = []
    tree = cKDTree(dv)
    for s, t in markers:
        p = cv[t]
        in_neck = p[2] >= 0.15 and 0.3 <= p[1] < 0.75
        if in_neck and n[t] > 0:
            o = total[t] / n[t]
            s2 = int(tree.query(p + o * diag)[1])
            print("neck marker %5d %5d  offset %+.4f %+.4f %+.4f (%.4f): source vertex %d" % (
                s, t, o[0], o[1], o[2], np.linalg.norm(o), s2))
            moved.append((s2, t))
        else:
            moved.append((s, t))
    if a.write:
        open(a.write, "w").write("".join("%d %d\n" % m for m in moved))


if __name__ == "__main__":
    main()
