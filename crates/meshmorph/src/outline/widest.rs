//! The untangling's last resort: each free point in turn moved to where
//! the smallest of its triangles is largest, against its size in a
//! reference (the local optimisation of Freitag and Plassmann 2000,
//! "Local optimization-based simplicial mesh untangling and
//! improvement"), sweep after sweep until every triangle is positive.
//!
//! A triangle's signed area is linear in any one of its corners, so for
//! one point the smallest of its triangles' relative areas is the lower
//! envelope of a few planes, and its highest point is where three of
//! them meet: a linear programme in two unknowns, solved here by looking
//! at every triple (a point has a handful of triangles). Around an inner
//! point the areas' gradients add up to nothing (its triangles cover a
//! fixed polygon), so the highest point exists. Unlike the foldover-free
//! energy ([`untangle`](super::untangle)), which can stall with a few
//! triangles turned over against a very bent boundary, every move here
//! raises its point's smallest area, and a point whose neighbours leave
//! it no room is given room when they move in their turn.

use super::geometry::orient;

/// Moves the `free` points of `positions` (the others held) until every
/// triangle at a free point is positive, at most `sweeps` times over and
/// no longer once a tenth of them in a row have not raised the smallest:
/// whether it got there. `rest_areas` are the triangles' areas in the
/// reference (positive), by which each area is measured. `at[v]..at[v +
/// 1]` indexes `corners`, the triangles at `v`.
pub fn widen(
    positions: &mut [[f64; 2]],
    triangles: &[[u32; 3]],
    rest_areas: &[f64],
    free: &[usize],
    (at, corners): (&[usize], &[u32]),
    sweeps: usize,
) -> bool {
    // The smallest relative area of a triangle at a free point.
    let smallest = |positions: &[[f64; 2]]| {
        free.iter()
            .flat_map(|&v| &corners[at[v]..at[v + 1]])
            .map(|&t| {
                let [a, b, c] = triangles[t as usize].map(|w| positions[w as usize]);
                orient(a, b, c) / (2.0 * rest_areas[t as usize]).max(f64::MIN_POSITIVE)
            })
            .fold(f64::INFINITY, f64::min)
    };
    let mut planes: Vec<([f64; 2], f64)> = Vec::new();
    let (mut best, mut since) = (smallest(positions), 0);
    for _ in 0..sweeps {
        if best > 0.0 {
            return true;
        }
        for &v in free {
            planes.clear();
            for &t in &corners[at[v]..at[v + 1]] {
                let tri = triangles[t as usize];
                let k = tri.iter().position(|&w| w as usize == v).unwrap_or(0);
                let a = positions[tri[(k + 1) % 3] as usize];
                let b = positions[tri[(k + 2) % 3] as usize];
                // Twice the area of (v, a, b), over the rest's.
                let scale = 1.0 / (2.0 * rest_areas[t as usize]).max(f64::MIN_POSITIVE);
                planes.push((
                    [(a[1] - b[1]) * scale, (b[0] - a[0]) * scale],
                    (a[0] * b[1] - a[1] * b[0]) * scale,
                ));
            }
            if let Some(p) = highest(&planes, positions[v]) {
                positions[v] = p;
            }
        }
        let now = smallest(positions);
        if now > best {
            (best, since) = (now, 0);
        } else {
            since += 1;
            if since > sweeps / 10 {
                break;
            }
        }
    }
    best > 0.0
}

/// The triangles at each of `n` vertices, as [`widen`] takes them: those
/// at `v` are `corners[at[v]..at[v + 1]]`.
pub fn triangles_at(n: usize, triangles: &[[u32; 3]]) -> (Vec<usize>, Vec<u32>) {
    let mut at = vec![0usize; n + 1];
    for t in triangles {
        for &v in t {
            at[v as usize + 1] += 1;
        }
    }
    for v in 0..n {
        at[v + 1] += at[v];
    }
    let mut fill = at.clone();
    let mut corners = vec![0u32; at[n]];
    for (i, t) in triangles.iter().enumerate() {
        for &v in t {
            corners[fill[v as usize]] = i as u32;
            fill[v as usize] += 1;
        }
    }
    (at, corners)
}

/// The smallest of `planes` (each `g · p + c`) at `p`.
fn lowest(planes: &[([f64; 2], f64)], p: [f64; 2]) -> f64 {
    planes
        .iter()
        .map(|(g, c)| g[0] * p[0] + g[1] * p[1] + c)
        .fold(f64::INFINITY, f64::min)
}

/// Where the lower envelope of `planes` is highest, when that is higher
/// than at `now`: among the points where three planes meet, the best.
fn highest(planes: &[([f64; 2], f64)], now: [f64; 2]) -> Option<[f64; 2]> {
    let mut best = (lowest(planes, now), None);
    let m = planes.len();
    for i in 0..m {
        for j in i + 1..m {
            for k in j + 1..m {
                // g_i · p + c_i = g_j · p + c_j = g_k · p + c_k.
                let (gi, ci) = planes[i];
                let (gj, cj) = planes[j];
                let (gk, ck) = planes[k];
                let r1 = [gi[0] - gj[0], gi[1] - gj[1]];
                let r2 = [gi[0] - gk[0], gi[1] - gk[1]];
                let det = r1[0] * r2[1] - r1[1] * r2[0];
                if det.abs() <= 1e-300 {
                    continue;
                }
                let (b1, b2) = (cj - ci, ck - ci);
                let p = [
                    (b1 * r2[1] - r1[1] * b2) / det,
                    (r1[0] * b2 - b1 * r2[0]) / det,
                ];
                let value = lowest(planes, p);
                if p[0].is_finite() && p[1].is_finite() && value > best.0 {
                    best = (value, Some(p));
                }
            }
        }
    }
    best.1
}
