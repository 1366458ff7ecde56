//! Compatible improvement of the overlay's triangles: edge flips and
//! vertex smoothing that keep the two meshes' triangles the same and
//! positively oriented in both, each accepted only when it raises the
//! smallest angle it touches (the smaller of the two meshes'), in the
//! spirit of Surazhsky and Gotsman 2004 (without their remeshing).

use std::collections::HashMap;

use super::geometry::{min_angle, orient};

/// The two meshes being improved: shared triangles, positions in each,
/// and which vertices are fixed (the outline points).
pub(crate) struct Pair<'a> {
    pub(crate) a: &'a mut [[f64; 2]],
    pub(crate) b: &'a mut [[f64; 2]],
    pub(crate) triangles: &'a mut Vec<[u32; 3]>,
    pub(crate) fixed: &'a [bool],
}

/// Smallest angle of triangle `t` in both meshes; `-1` when it is not
/// positively oriented in either (below `tiny` times its longest edge
/// squared).
fn quality(a: &[[f64; 2]], b: &[[f64; 2]], t: [u32; 3]) -> f64 {
    let mut q = f64::INFINITY;
    for p in [a, b] {
        let [x, y, z] = t.map(|v| p[v as usize]);
        let area = orient(x, y, z);
        let scale = [x, y, z]
            .iter()
            .zip([y, z, x].iter())
            .map(|(u, v)| (u[0] - v[0]).powi(2) + (u[1] - v[1]).powi(2))
            .fold(0.0, f64::max);
        if area.is_nan() || area <= 1e-14 * scale {
            return -1.0;
        }
        q = q.min(min_angle(x, y, z));
    }
    q
}

/// The smallest angle over both meshes, radians.
pub(crate) fn smallest_angles(pair: &Pair) -> [f64; 2] {
    let mut out = [f64::INFINITY; 2];
    for t in pair.triangles.iter() {
        for (k, p) in [&*pair.a, &*pair.b].into_iter().enumerate() {
            let [x, y, z] = t.map(|v| p[v as usize]);
            out[k] = out[k].min(min_angle(x, y, z));
        }
    }
    out
}

/// One round of flips: every interior edge whose flip raises the smaller
/// of its two triangles' qualities, no triangle flipped twice a round.
/// Returns how many edges were flipped.
fn flip_round(pair: &mut Pair) -> usize {
    let tris = &mut *pair.triangles;
    let mut edge_of: HashMap<(u32, u32), (usize, usize)> = HashMap::with_capacity(tris.len() * 3);
    for (t, tri) in tris.iter().enumerate() {
        for i in 0..3 {
            edge_of.insert((tri[i], tri[(i + 1) % 3]), (t, i));
        }
    }
    let mut touched = vec![false; tris.len()];
    let mut flips = 0;
    let mut keys: Vec<(u32, u32)> = edge_of.keys().copied().filter(|&(u, v)| u < v).collect();
    keys.sort_unstable();
    for (u, v) in keys {
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
        let old = quality(pair.a, pair.b, tris[t]).min(quality(pair.a, pair.b, tris[s]));
        let (n1, n2) = ([x, y, v], [y, x, u]);
        let new = quality(pair.a, pair.b, n1).min(quality(pair.a, pair.b, n2));
        if new > old + 1e-9 {
            tris[t] = n1;
            tris[s] = n2;
            touched[t] = true;
            touched[s] = true;
            flips += 1;
        }
    }
    flips
}

/// One round of smoothing: each free vertex moved, in each mesh apart,
/// toward the mean of its neighbours when that raises the smallest
/// quality of its triangles. Returns how many moves were taken.
fn smooth_round(pair: &mut Pair) -> usize {
    let n = pair.a.len();
    let mut around: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (t, tri) in pair.triangles.iter().enumerate() {
        for &v in tri {
            around[v as usize].push(t as u32);
        }
    }
    let mut moves = 0;
    for v in 0..n {
        if pair.fixed[v] || around[v].is_empty() {
            continue;
        }
        for side in 0..2 {
            let mut mean = [0.0, 0.0];
            let mut count = 0.0;
            for &t in &around[v] {
                for &w in &pair.triangles[t as usize] {
                    if w as usize != v {
                        let p = if side == 0 {
                            pair.a[w as usize]
                        } else {
                            pair.b[w as usize]
                        };
                        mean[0] += p[0];
                        mean[1] += p[1];
                        count += 1.0;
                    }
                }
            }
            mean = [mean[0] / count, mean[1] / count];
            let score = |pair: &Pair| {
                around[v]
                    .iter()
                    .map(|&t| quality(pair.a, pair.b, pair.triangles[t as usize]))
                    .fold(f64::INFINITY, f64::min)
            };
            let before = score(pair);
            let old = if side == 0 { pair.a[v] } else { pair.b[v] };
            for step in [1.0, 0.5, 0.25] {
                let p = [
                    old[0] + step * (mean[0] - old[0]),
                    old[1] + step * (mean[1] - old[1]),
                ];
                if side == 0 {
                    pair.a[v] = p;
                } else {
                    pair.b[v] = p;
                }
                if score(pair) > before + 1e-12 {
                    moves += 1;
                    break;
                }
                if side == 0 {
                    pair.a[v] = old;
                } else {
                    pair.b[v] = old;
                }
            }
        }
    }
    moves
}

/// Alternates flips and smoothing for up to `rounds` rounds, stopping
/// early when nothing changes.
pub(crate) fn improve(pair: &mut Pair, rounds: usize) {
    for _ in 0..rounds {
        let mut changed = 0;
        for _ in 0..8 {
            let f = flip_round(pair);
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
