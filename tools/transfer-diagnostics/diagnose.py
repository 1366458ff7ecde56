#!/usr/bin/env python3
"""Where the error of horse -> camel transfer lies, against Sumner's own results.

An analysis tool, not part of the tests (it needs numpy and scipy:
`pip install numpy scipy`). It reads ../shared/data/dt/horse-camel in place and
a correspondence saved by `meshmorph correspond -o FILE --deformed-source DEF`,
and re-implements the transfer's least-squares fit (Sumner and Popovic 2004,
with fourth vertices) with scipy, so that what the fit is given can be varied
one thing at a time while the correspondence stays fixed. The files' own
orientation is used throughout (the correspondence's turn is not applied), so
the figures compare with `NOALIGN=1` rows of BENCHMARKS.md, not the default.

usage: tools/transfer-diagnostics/diagnose.py CORR DEFORMED [--data DIR]

Prints, mean / worst over the ten poses (error: RMS vertex distance after
centring over the camel reference's bounding-box diagonal):
  1. the fit as meshmorph makes it (gaps filled by smoothness);
  2. other weightings of the same pairs (each target triangle by its area or
     by its number of pairs, partners averaged or summed);
  3. the gaps given Sumner's own gradients (a bound on what filling gaps can gain);
  4. the pairs matched again after the deformed source's front half (z > 0:
     the neck and head) is moved back along z: how much the neck's
     correspondence weighs;
  5. per region, the mean rotation vector of Sumner's triangles and of the
     transferred ones (degrees), for the poses given with --poses.
"""
import argparse
import os
import sys

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spl
from scipy.spatial import cKDTree


def read_obj(path):
    v, f = [], []
    with open(path) as fh:
        for line in fh:
            if line.startswith("v "):
                v.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                f.append([int(c.split("/")[0]) - 1 for c in line.split()[1:]])
    return np.array(v), np.array(f)


def read_pairs(path):
    lines = open(path).read().split("\n")
    start = next(k for k, l in enumerate(lines) if l.startswith("pairs")) + 1
    return np.array([[int(x) for x in l.split()] for l in lines[start:] if l.strip()])


def frames(v, f):
    """Sumner's frames [v2-v1, v3-v1, n/sqrt|n|] (columns) and the areas."""
    e1, e2 = v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]
    n = np.cross(e1, e2)
    ln = np.linalg.norm(n, axis=1)
    return np.stack([e1, e2, n / np.sqrt(ln)[:, None]], axis=2), ln / 2


def gradients(rest, posed, f):
    return frames(posed, f)[0] @ np.linalg.inv(frames(rest, f)[0])


def rotation_vectors(g):
    u, _, vt = np.linalg.svd(g)
    d = np.sign(np.linalg.det(u @ vt))
    u[:, :, 2] *= d[:, None]
    r = u @ vt
    angle = np.arccos(np.clip((np.trace(r, axis1=1, axis2=2) - 1) / 2, -1, 1))
    w = np.stack([r[:, 2, 1] - r[:, 1, 2], r[:, 0, 2] - r[:, 2, 0], r[:, 1, 0] - r[:, 0, 1]], 1)
    n = np.linalg.norm(w, axis=1)
    n[n == 0] = 1
    return np.degrees(w / n[:, None] * angle[:, None])


def rms_centred(a, b):
    return np.sqrt((((a - a.mean(0)) - (b - b.mean(0))) ** 2).sum(1).mean())


def unit_normals(v, f):
    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    return n / np.linalg.norm(n, axis=1)[:, None]


class Fit:
    """min sum_t w_t |X G_t - S_t|^2 over vertices and fourth vertices, plus
    smoothness |X G_a - X G_b|^2 (weight (w_a + w_b) / 2) across the edges of
    the triangles marked as gaps, whose own fit weight is 0."""

    def __init__(self, v, f, weights, gap=None):
        n, m = len(v), len(f)
        self.n = n
        inv = np.linalg.inv(frames(v, f)[0])
        g = np.zeros((m, 4, 3))
        g[:, 1:, :] = inv
        g[:, 0, :] = -inv.sum(1)
        idx = np.concatenate([f, (n + np.arange(m))[:, None]], 1)
        gap = np.zeros(m, bool) if gap is None else gap
        fit_w = np.sqrt(np.where(gap, 0.0, weights))
        rows = np.repeat((np.arange(m)[:, None] * 3 + np.arange(3))[:, :, None], 4, 2)
        cols = np.repeat(idx[:, None, :], 3, 1)
        vals = np.transpose(g, (0, 2, 1)) * fit_w[:, None, None]
        self.a = sp.csr_matrix((vals.ravel(), (rows.ravel(), cols.ravel())), shape=(3 * m, n + m))
        self.sw = np.repeat(fit_w[:, None], 3, 1)
        normal = self.a.T @ self.a
        if gap.any():
            normal = normal + self._smoothness(f, g, idx, weights, gap, n + m)
        normal = (normal + sp.eye(n + m) * 1e-9 * normal.diagonal().mean()).tocsc()
        self.lu = spl.splu(normal)

    @staticmethod
    def _smoothness(f, g, idx, weights, gap, size):
        edges = {}
        for t, tri in enumerate(f):
            for i in range(3):
                edges.setdefault(tuple(sorted((tri[i], tri[(i + 1) % 3]))), []).append(t)
        pairs = np.array([p for p in edges.values() if len(p) == 2])
        pairs = pairs[gap[pairs[:, 0]] | gap[pairs[:, 1]]]
        k = len(pairs)
        w = np.sqrt(0.5 * (weights[pairs[:, 0]] + weights[pairs[:, 1]]))
        rows, cols, vals = [], [], []
        for j in range(3):
            r = np.arange(k) * 3 + j
            for side, sign in ((0, 1.0), (1, -1.0)):
                t = pairs[:, side]
                for c in range(4):
                    rows.append(r)
                    cols.append(idx[t, c])
                    vals.append(sign * g[t, c, j] * w)
        b = sp.csr_matrix(
            (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(3 * k, size)
        )
        return b.T @ b

    def solve(self, targets):
        out = np.zeros((self.n, 3))
        for i in range(3):
            out[:, i] = self.lu.solve(self.a.T @ (targets[:, i, :] * self.sw).ravel())[: self.n]
        return out


def nearest_compatible(qc, qn, tc, tn, limit, k=32):
    d, i = cKDTree(tc).query(qc, k)
    ok = (np.einsum("ij,ikj->ik", qn, tn[i]) > 0) & (d < limit)
    first = np.where(ok.any(1), ok.argmax(1), -1)
    return np.where(first >= 0, i[np.arange(len(qc)), np.maximum(first, 0)], -1)


def match(deformed, hf, camel, cf, limit):
    """meshmorph's matching: nearest compatible centroid both ways, the union."""
    hc, cc = deformed[hf].mean(1), camel[cf].mean(1)
    hn, cn = unit_normals(deformed, hf), unit_normals(camel, cf)
    fw = nearest_compatible(hc, hn, cc, cn, limit)
    bw = nearest_compatible(cc, cn, hc, hn, limit)
    pairs = [[s, t] for s, t in enumerate(fw) if t >= 0] + [[s, t] for t, s in enumerate(bw) if s >= 0]
    return np.unique(np.array(pairs), axis=0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("corr")
    ap.add_argument("deformed")
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--data", default=os.path.join(here, "../../../shared/data/dt/horse-camel"))
    ap.add_argument("--poses", default="2,9")
    args = ap.parse_args()
    d = args.data
    horse, hf = read_obj(f"{d}/horse-poses/horse-reference.obj")
    camel, cf = read_obj(f"{d}/camel-poses/camel-reference.obj")
    deformed, _ = read_obj(args.deformed)
    pairs = read_pairs(args.corr)
    diag = np.linalg.norm(camel.max(0) - camel.min(0))
    h_area, c_area = frames(horse, hf)[1], frames(camel, cf)[1]
    weights = c_area / c_area.mean()
    poses = []
    for k in range(1, 11):
        hk, _ = read_obj(f"{d}/horse-poses/horse-{k:02d}.obj")
        ck, _ = read_obj(f"{d}/camel-poses/camel-{k:02d}.obj")
        poses.append((gradients(horse, hk, hf), gradients(camel, ck, cf), ck))

    def partner_means(p, g, pair_weight):
        s, w = np.zeros((len(cf), 3, 3)), np.zeros(len(cf))
        np.add.at(s, p[:, 1], g[p[:, 0]] * pair_weight[:, None, None])
        np.add.at(w, p[:, 1], pair_weight)
        paired = w > 0
        s[paired] /= w[paired][:, None, None]
        return s, paired

    def run(label, p, fit, pair_weight=None, gaps="smooth"):
        scores = []
        for gh, gc, ck in poses:
            s, paired = partner_means(p, gh, h_area[p[:, 0]] if pair_weight is None else pair_weight)
            if gaps == "sumner":
                s[~paired] = gc[~paired]
            scores.append(rms_centred(fit.solve(s), ck) / diag)
        print(f"| {label} | {np.mean(scores):.5f} / {np.max(scores):.5f} |", flush=True)

    gap = np.bincount(pairs[:, 1], minlength=len(cf)) == 0
    print(f"{len(pairs)} pairs, {gap.sum()} camel triangles in none\n")
    print("| fit | mean / worst |\n|---|---|")
    run("as meshmorph fits (by area, partners averaged by area, gaps by smoothness)", pairs, Fit(camel, cf, weights, gap))
    plain = Fit(camel, cf, weights)
    run("gaps given Sumner's own gradients", pairs, plain, gaps="sumner")
    run("(same gaps) partners averaged with equal weights", pairs, plain, np.ones(len(pairs)), "sumner")
    count = np.maximum(np.bincount(pairs[:, 1], minlength=len(cf)), 1).astype(float)
    run("(same gaps) the paper's sum over pairs", pairs, Fit(camel, cf, count), np.ones(len(pairs)), "sumner")
    run("(same gaps) every target triangle weighing 1", pairs, Fit(camel, cf, np.ones(len(cf))), None, "sumner")

    print("\n| deformed source's front half (z > 0) moved along z by | pairs matched again: mean / worst |\n|---|---|")
    limit = 0.01 * diag
    front = deformed[:, 2] > 0
    for dz in (0.0, -0.004, -0.008, -0.012, 0.004):
        moved = deformed.copy()
        moved[front, 2] += dz * diag
        p = match(moved, hf, camel, cf, limit)
        g = np.bincount(p[:, 1], minlength=len(cf)) == 0
        run(f"{dz:+.3f} of the diagonal ({g.sum()} in no pair)", p, Fit(camel, cf, weights, g))

    centres = camel[cf].mean(1)
    y, z = centres[:, 1], centres[:, 2]
    regions = {
        "legs (y < 0.35)": y < 0.35,
        "body (z < 0.2)": (y >= 0.35) & (z < 0.2),
        "neck base": (y >= 0.35) & (z >= 0.2) & (y < 0.6),
        "upper neck": (y >= 0.6) & (z < 0.35),
        "head": (y >= 0.6) & (z >= 0.35),
    }
    fit = Fit(camel, cf, weights, gap)
    for k in (int(x) for x in args.poses.split(",")):
        gh, gc, ck = poses[k - 1]
        s, paired = partner_means(pairs, gh, h_area[pairs[:, 0]])
        result = gradients(camel, fit.solve(s), cf)
        print(f"\npose {k:02d}: mean rotation vector (degrees, x y z) by region\n")
        print("| region | transferred | the fit's result | Sumner's |\n|---|---|---|---|")
        rs, rr, rc = rotation_vectors(s), rotation_vectors(result), rotation_vectors(gc)
        for name, region in regions.items():
            q = region & paired
            a = c_area[q, None]
            mean = lambda r: " ".join(f"{x:.1f}" for x in (r[q] * a).sum(0) / a.sum())
            print(f"| {name} | {mean(rs)} | {mean(rr)} | {mean(rc)} |")


if __name__ == "__main__":
    sys.exit(main())
