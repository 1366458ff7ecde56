//! Compatible improvement of the overlay's triangles: edge flips and
//! vertex smoothing that keep the two meshes' triangles the same and
//! positively oriented in both, each accepted only when it raises the
//! smallest angle it touches (the smaller of the two meshes'), in the
//! spirit of Surazhsky and Gotsman 2004 (without their remeshing).

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A multiplicative hash for edge keys (two vertex indices): the maps of
/// edges are rebuilt every round, where the standard library's keyed
/// hash cost more than the flips themselves.
#[derive(Default)]
struct EdgeHasher(u64);

impl Hasher for EdgeHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }
    fn write_u32(&mut self, x: u32) {
        self.write_u64(u64::from(x));
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

type EdgeMap<V> = HashMap<(u32, u32), V, BuildHasherDefault<EdgeHasher>>;

use super::geometry::{min_angle, orient};

/// Sine of an angle up to 90 degrees, for comparisons with [`quality`].
fn sine(angle: f64) -> f64 {
    angle.clamp(0.0, std::f64::consts::FRAC_PI_2).sin()
}

/// The meshes being improved (two or more): shared triangles, positions
/// in each, and which vertices are fixed (the outline points and
/// anchors).
pub(crate) struct Pair<'a> {
    pub(crate) meshes: &'a mut [Vec<[f64; 2]>],
    pub(crate) triangles: &'a mut Vec<[u32; 3]>,
    pub(crate) fixed: &'a mut Vec<bool>,
}

/// The sine of the smallest angle of triangle `t` in every mesh (the
/// smallest angle is at most 60 degrees, where the sine grows with the
/// angle, so it orders triangles as the angle does, without a
/// trigonometric call); `-1` when it is not positively oriented in
/// any (below `tiny` times its longest edge squared).
#[inline]
fn quality(meshes: &[Vec<[f64; 2]>], t: [u32; 3]) -> f64 {
    meshes
        .iter()
        .map(|p| quality_in(p, t))
        .fold(f64::INFINITY, f64::min)
}

/// [`quality`] in one mesh, at positions `p`.
#[inline]
fn quality_in(p: &[[f64; 2]], t: [u32; 3]) -> f64 {
    let [x, y, z] = t.map(|v| p[v as usize]);
    let area = orient(x, y, z);
    let l = |u: [f64; 2], v: [f64; 2]| (u[0] - v[0]).powi(2) + (u[1] - v[1]).powi(2);
    let (e0, e1, e2) = (l(x, y), l(y, z), l(z, x));
    let longest = e0.max(e1).max(e2);
    if area.is_nan() || area <= 1e-14 * longest {
        return -1.0;
    }
    // The smallest angle faces the shortest edge: its sine is twice
    // the area over the two longer edges.
    let shortest = e0.min(e1).min(e2);
    let middle = e0 + e1 + e2 - longest - shortest;
    area / (longest * middle).sqrt()
}

/// The smallest angle of each mesh, radians.
pub(crate) fn smallest_angles(pair: &Pair) -> Vec<f64> {
    let mut out = vec![f64::INFINITY; pair.meshes.len()];
    for t in pair.triangles.iter() {
        for (k, p) in pair.meshes.iter().enumerate() {
            let [x, y, z] = t.map(|v| p[v as usize]);
            out[k] = out[k].min(min_angle(x, y, z));
        }
    }
    out
}

/// The triangles' edges and qualities carried from one round of flips to
/// the next: each directed edge `(u, v)` to its triangle and the edge's
/// place in it, and each triangle's [`quality`]. Flips change no
/// position, so only the two triangles of a flip change; both are kept
/// up to date as it is made. (Each directed edge is in one triangle: the
/// meshes are valid, every triangle positive, and a flip keeps them so.)
struct Flips {
    edge_of: EdgeMap<(usize, usize)>,
    cached: Vec<f64>,
}

impl Flips {
    fn of(pair: &Pair) -> Self {
        let tris = &*pair.triangles;
        let mut edge_of: EdgeMap<(usize, usize)> =
            EdgeMap::with_capacity_and_hasher(tris.len() * 3, Default::default());
        for (t, tri) in tris.iter().enumerate() {
            for i in 0..3 {
                edge_of.insert((tri[i], tri[(i + 1) % 3]), (t, i));
            }
        }
        let cached = tris.iter().map(|&t| quality(pair.meshes, t)).collect();
        Self { edge_of, cached }
    }
}

/// One round of flips: every interior edge whose flip raises the smaller
/// of its two triangles' qualities, no triangle flipped twice a round,
/// the edges taken in order. Returns how many edges were flipped.
fn flip_round(pair: &mut Pair, flips: &mut Flips) -> usize {
    let tris = &mut *pair.triangles;
    let Flips { edge_of, cached } = flips;
    let mut touched = vec![false; tris.len()];
    let mut flipped = 0;
    let mut keys: Vec<(u32, u32)> = edge_of.keys().copied().filter(|&(u, v)| u < v).collect();
    keys.sort_unstable();
    for (u, v) in keys {
        // (An edge of a triangle flipped this round is gone, or now in
        // a touched triangle: skipped either way.)
        let (Some(&(t, i)), Some(&(s, j))) = (edge_of.get(&(u, v)), edge_of.get(&(v, u))) else {
            continue;
        };
        if touched[t] || touched[s] {
            continue;
        }
        // t = (u, v, x), s = (v, u, y): flip to (x, y, v) and (y, x, u).
        let x = tris[t][(i + 2) % 3];
        let y = tris[s][(j + 2) % 3];
        if x == y {
            continue;
        }
        if pair.fixed[x as usize] && pair.fixed[y as usize] {
            // A chord: see [`split_chords`].
            continue;
        }
        let old = cached[t].min(cached[s]);
        let (n1, n2) = ([x, y, v], [y, x, u]);
        let (q1, q2) = (quality(pair.meshes, n1), quality(pair.meshes, n2));
        if q1.min(q2) > old + 1e-9 {
            tris[t] = n1;
            tris[s] = n2;
            edge_of.remove(&(u, v));
            edge_of.remove(&(v, u));
            for (k, tri) in [(t, n1), (s, n2)] {
                for c in 0..3 {
                    edge_of.insert((tri[c], tri[(c + 1) % 3]), (k, c));
                }
            }
            cached[t] = q1;
            cached[s] = q2;
            touched[t] = true;
            touched[s] = true;
            flipped += 1;
        }
    }
    flipped
}

/// One round of smoothing: each free vertex moved, in each mesh apart,
/// toward the mean of its neighbours when that raises the smallest
/// quality of its triangles (over every mesh). Returns how many moves
/// were taken.
///
/// A move in one mesh changes only that mesh's qualities, so it can
/// raise the smallest of all only where the other meshes' smallest
/// around the vertex is above this one's: elsewhere the vertex is not
/// tried, and the moves tried are measured in their own mesh alone.
fn smooth_round(pair: &mut Pair) -> usize {
    let n = pair.meshes[0].len();
    let mut around: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (t, tri) in pair.triangles.iter().enumerate() {
        for &v in tri {
            around[v as usize].push(t as u32);
        }
    }
    let triangles = &*pair.triangles;
    let smallest = |p: &[[f64; 2]], v: usize| {
        around[v]
            .iter()
            .map(|&t| quality_in(p, triangles[t as usize]))
            .fold(f64::INFINITY, f64::min)
    };
    let mut moves = 0;
    for v in 0..n {
        if pair.fixed[v] || around[v].is_empty() {
            continue;
        }
        for side in 0..pair.meshes.len() {
            let own = smallest(&pair.meshes[side], v);
            let others = (0..pair.meshes.len())
                .filter(|&k| k != side)
                .map(|k| smallest(&pair.meshes[k], v))
                .fold(f64::INFINITY, f64::min);
            if others <= own {
                continue;
            }
            let p = &mut pair.meshes[side];
            let mut mean = [0.0, 0.0];
            let mut count = 0.0;
            for &t in &around[v] {
                for &w in &triangles[t as usize] {
                    if w as usize != v {
                        let q = p[w as usize];
                        mean[0] += q[0];
                        mean[1] += q[1];
                        count += 1.0;
                    }
                }
            }
            mean = [mean[0] / count, mean[1] / count];
            let old = p[v];
            for step in [1.0, 0.5, 0.25] {
                p[v] = [
                    old[0] + step * (mean[0] - old[0]),
                    old[1] + step * (mean[1] - old[1]),
                ];
                if smallest(p, v).min(others) > own + 1e-12 {
                    moves += 1;
                    break;
                }
                p[v] = old;
            }
        }
    }
    moves
}

/// Splits at its midpoint, in both meshes, the longest inside edge of each
/// triangle whose smallest angle is below `target` (radians), at most
/// one edge a triangle a round and no more than `budget` splits. A
/// midpoint splits both triangles of its edge into two positive ones in
/// each mesh, so the meshes stay valid; smoothing then moves the new
/// point to where it helps. Returns how many edges were split.
fn split_round(pair: &mut Pair, target: f64, budget: usize) -> usize {
    let tris = &mut *pair.triangles;
    let edge_of = triangle_of_edge(tris);
    let target_sine = sine(target);
    let mut touched = vec![false; tris.len()];
    let mut splits = 0;
    let count = tris.len();
    for t in 0..count {
        if splits >= budget || touched[t] || quality(pair.meshes, tris[t]) >= target_sine {
            continue;
        }
        let tri = tris[t];
        let len = |u: u32, v: u32| {
            pair.meshes
                .iter()
                .map(|p| {
                    let (x, y) = (p[u as usize], p[v as usize]);
                    (x[0] - y[0]).hypot(x[1] - y[1])
                })
                .fold(0.0, f64::max)
        };
        let mut best: Option<(f64, u32, u32, usize)> = None;
        for i in 0..3 {
            let (u, v) = (tri[i], tri[(i + 1) % 3]);
            if let Some(&s) = edge_of.get(&(v, u)) {
                if !touched[s] {
                    let l = len(u, v);
                    if best.is_none_or(|b| l > b.0) {
                        best = Some((l, u, v, s));
                    }
                }
            }
        }
        let Some((_, u, v, s)) = best else { continue };
        split_edge(pair.meshes, tris, pair.fixed, (t, s), (u, v));
        touched[t] = true;
        touched[s] = true;
        splits += 1;
    }
    splits
}

/// The triangle running along each directed edge `(u, v)`.
fn triangle_of_edge(tris: &[[u32; 3]]) -> EdgeMap<usize> {
    let mut edge_of: EdgeMap<usize> =
        EdgeMap::with_capacity_and_hasher(tris.len() * 3, Default::default());
    for (t, tri) in tris.iter().enumerate() {
        for i in 0..3 {
            edge_of.insert((tri[i], tri[(i + 1) % 3]), t);
        }
    }
    edge_of
}

/// Splits the edge from `u` to `v` at its midpoint in every mesh: `t`
/// is its triangle running from `u` to `v`, `s` the one running back.
/// Both become two, each positive wherever its half was, and the new
/// point is free.
fn split_edge(
    meshes: &mut [Vec<[f64; 2]>],
    tris: &mut Vec<[u32; 3]>,
    fixed: &mut Vec<bool>,
    (t, s): (usize, usize),
    (u, v): (u32, u32),
) {
    let x = tris[t].into_iter().find(|&w| w != u && w != v).unwrap_or(u);
    let y = tris[s].into_iter().find(|&w| w != u && w != v).unwrap_or(u);
    let w = meshes[0].len() as u32;
    for p in meshes.iter_mut() {
        let (m, n) = (p[u as usize], p[v as usize]);
        p.push([(m[0] + n[0]) * 0.5, (m[1] + n[1]) * 0.5]);
    }
    fixed.push(false);
    tris[t] = [u, w, x];
    tris[s] = [v, w, y];
    tris.push([w, v, x]);
    tris.push([w, u, y]);
}

/// Splits every inside edge between two fixed points (a chord across the
/// drawing from one outline point to another, or to an anchor) at its
/// midpoint, until none is left; returns how many were split. A triangle
/// whose three corners are fixed can be put right by no inside point: in
/// a frame that bends the outline there (a jagged stretch straightened,
/// a slit closed) it turns over, and neither the mend nor the untangling
/// can reach it. With no chord, every triangle has a free corner, and
/// every free point a free neighbour across each chord there was.
/// [`flip_round`] makes no new chord.
pub(crate) fn split_chords(pair: &mut Pair) -> usize {
    let mut splits = 0;
    loop {
        let tris = &mut *pair.triangles;
        let edge_of = triangle_of_edge(tris);
        let mut chords: Vec<(u32, u32)> = edge_of
            .keys()
            .copied()
            .filter(|&(u, v)| {
                u < v
                    && pair.fixed[u as usize]
                    && pair.fixed[v as usize]
                    && edge_of.contains_key(&(v, u))
            })
            .collect();
        // The same meshes whatever the map's order.
        chords.sort_unstable();
        let mut touched = vec![false; tris.len()];
        let before = splits;
        for (u, v) in chords {
            let (t, s) = (edge_of[&(u, v)], edge_of[&(v, u)]);
            if touched[t] || touched[s] {
                continue;
            }
            split_edge(pair.meshes, tris, pair.fixed, (t, s), (u, v));
            touched[t] = true;
            touched[s] = true;
            splits += 1;
        }
        if splits == before {
            return splits;
        }
    }
}

/// Alternates splits of poor triangles' edges, flips and smoothing for up
/// to `rounds` rounds, stopping early when nothing changes. Splits stop
/// once `extra` vertices have been added. When the smallest angle comes
/// out lower than it went in, the meshes are put back as they were.
pub(crate) fn improve(pair: &mut Pair, rounds: usize, target: f64, extra: usize) {
    let before = smallest_angles(pair);
    let saved = (
        pair.meshes.to_vec(),
        pair.triangles.clone(),
        pair.fixed.clone(),
    );
    improve_rounds(pair, rounds, target, extra);
    let worst = |angles: &[f64]| angles.iter().copied().fold(f64::INFINITY, f64::min);
    if worst(&smallest_angles(pair)) < worst(&before) {
        pair.meshes.clone_from_slice(&saved.0);
        (*pair.triangles, *pair.fixed) = (saved.1, saved.2);
    }
}

fn improve_rounds(pair: &mut Pair, rounds: usize, target: f64, extra: usize) {
    let limit = pair.meshes[0].len() + extra;
    for _ in 0..rounds {
        let mut changed = 0;
        let budget = limit.saturating_sub(pair.meshes[0].len());
        changed += split_round(pair, target, budget);
        let mut flips = Flips::of(pair);
        for _ in 0..8 {
            let f = flip_round(pair, &mut flips);
            changed += f;
            if f == 0 {
                break;
            }
        }
        changed += smooth_round(pair);
        if changed == 0 {
            break;
        }
    }
}
