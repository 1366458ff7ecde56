//! The overlay of two triangulations of one convex polygon (Aronov,
//! Seidel and Souvaine 1993): both drawings' disks share their boundary
//! list, so each triangulation is a set of non-crossing chords of one
//! convex polygon with that boundary; laid over each other, the chords
//! cut the polygon into convex faces, and triangulating each face gives
//! one triangulation that refines both.
//!
//! Everything is decided by the order of the boundary points, with no
//! floating-point predicate: two chords cross when their ends interleave,
//! and the crossings along a chord are ordered by where the crossing
//! chords end. A crossing of chord $\alpha$ of the first triangulation and
//! chord $\beta$ of the second is placed, in the first drawing, on
//! $\alpha$ at the fraction $k / (K + 1)$ of its length for the $k$-th of
//! its $K$ crossings (and on $\beta$ likewise in the second). Any
//! increasing placement along each chord keeps every face convex in both
//! drawings: within a triangle of the first triangulation the pieces of
//! the second's chords are straight segments between its sides that do not
//! cross. So every triangle of the overlay is positively oriented in both
//! drawings.

use std::collections::HashMap;

/// A vertex of the overlay.
#[derive(Clone, Copy, Debug)]
pub(crate) enum OverlayVertex {
    /// A copy of the disk's boundary.
    Copy(usize),
    /// A crossing: on the first triangulation's chord `a` (copies, the
    /// smaller first) at fraction `s` from `a.0`, and on the second's
    /// chord `b` at fraction `r` from `b.0`.
    Crossing {
        a: (usize, usize),
        s: f64,
        b: (usize, usize),
        r: f64,
    },
}

/// The overlay: its vertices (the `m` copies first) and its triangles,
/// counter-clockwise.
pub(crate) struct Overlay {
    pub(crate) vertices: Vec<OverlayVertex>,
    pub(crate) triangles: Vec<[u32; 3]>,
}

/// The chords (edges not on the boundary) of a triangulation of the
/// convex `m`-gon, the smaller copy first.
fn chords(m: usize, triangles: &[[usize; 3]]) -> Vec<(usize, usize)> {
    let mut out: Vec<(usize, usize)> = triangles
        .iter()
        .flat_map(|t| (0..3).map(move |i| (t[i].min(t[(i + 1) % 3]), t[i].max(t[(i + 1) % 3]))))
        .filter(|&(u, v)| v - u != 1 && !(u == 0 && v == m - 1))
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// Whether `x` lies strictly inside the open range `(lo, hi)`.
#[inline]
fn between(x: usize, lo: usize, hi: usize) -> bool {
    lo < x && x < hi
}

/// Whether copy `x` lies on the cyclic open arc going from `from` to `to`
/// counter-clockwise.
#[inline]
fn on_arc(x: usize, from: usize, to: usize, m: usize) -> bool {
    let (d, e) = ((x + m - from) % m, (to + m - from) % m);
    d > 0 && d < e
}

/// Puts the crossings along a chord `(a, b)` (`a < b`) in order from `a`,
/// each given as (its end inside the arc `(a, b)`, its other end unwrapped
/// past `b`, which chord): a chord nearer `a` on the arc `(a, b)`, or from
/// the same end and nearer `a` on the other arc, crosses nearer `a`.
fn ordered(crossing: &mut [(usize, usize, usize)]) {
    crossing.sort_by(|x, y| x.0.cmp(&y.0).then(y.1.cmp(&x.1)));
}

/// Overlays two triangulations of the convex polygon of `m` copies.
pub(crate) fn overlay(m: usize, first: &[[usize; 3]], second: &[[usize; 3]]) -> Overlay {
    let ca = chords(m, first);
    let cb = chords(m, second);
    // Crossings of each chord of the first with each of the second.
    let key = |chord: (usize, usize), other: (usize, usize)| {
        let (a, b) = chord;
        let (inner, outer) = if between(other.0, a, b) {
            (other.0, other.1)
        } else {
            (other.1, other.0)
        };
        let outer = if outer < a { outer + m } else { outer };
        (inner, outer)
    };
    let mut on_a: Vec<Vec<(usize, usize, usize)>> = vec![Vec::new(); ca.len()];
    let mut on_b: Vec<Vec<(usize, usize, usize)>> = vec![Vec::new(); cb.len()];
    for (i, &(a, b)) in ca.iter().enumerate() {
        for (j, &(c, d)) in cb.iter().enumerate() {
            if between(c, a, b) != between(d, a, b) && c != a && c != b && d != a && d != b {
                let (ki, ko) = key((a, b), (c, d));
                on_a[i].push((ki, ko, j));
                let (ki, ko) = key((c, d), (a, b));
                on_b[j].push((ki, ko, i));
            }
        }
    }
    let mut crossing_id: HashMap<(usize, usize), u32> = HashMap::new();
    let mut vertices: Vec<OverlayVertex> = (0..m).map(OverlayVertex::Copy).collect();
    for (i, list) in on_a.iter_mut().enumerate() {
        ordered(list);
        let k = list.len();
        for (rank, &(_, _, j)) in list.iter().enumerate() {
            crossing_id.insert((i, j), vertices.len() as u32);
            vertices.push(OverlayVertex::Crossing {
                a: ca[i],
                s: (rank + 1) as f64 / (k + 1) as f64,
                b: cb[j],
                r: 0.0,
            });
        }
    }
    for (j, list) in on_b.iter_mut().enumerate() {
        ordered(list);
        let k = list.len();
        for (rank, &(_, _, i)) in list.iter().enumerate() {
            let id = crossing_id[&(i, j)] as usize;
            if let OverlayVertex::Crossing { r, .. } = &mut vertices[id] {
                *r = (rank + 1) as f64 / (k + 1) as f64;
            }
        }
    }
    let index_a: HashMap<(usize, usize), usize> =
        ca.iter().enumerate().map(|(i, &c)| (c, i)).collect();
    // The second's chords at each copy.
    let mut b_at: Vec<Vec<usize>> = vec![Vec::new(); m];
    for (j, &(c, d)) in cb.iter().enumerate() {
        b_at[c].push(j);
        b_at[d].push(j);
    }
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(first.len() * 2);
    // Local polygon of a triangle: (overlay vertex, chord of the second
    // crossing there or usize::MAX at a corner).
    let mut local: Vec<(u32, usize)> = Vec::new();
    let mut ends: HashMap<usize, Vec<usize>> = HashMap::new();
    for t in first {
        local.clear();
        ends.clear();
        for side in 0..3 {
            let (u, v) = (t[side], t[(side + 1) % 3]);
            local.push((u as u32, usize::MAX));
            let chord = (u.min(v), u.max(v));
            if let Some(&i) = index_a.get(&chord) {
                let list = &on_a[i];
                let ids: Vec<(u32, usize)> = list
                    .iter()
                    .map(|&(_, _, j)| (crossing_id[&(i, j)], j))
                    .collect();
                if u < v {
                    local.extend(ids);
                } else {
                    local.extend(ids.into_iter().rev());
                }
            }
        }
        for (pos, &(_, j)) in local.iter().enumerate() {
            if j != usize::MAX {
                ends.entry(j).or_default().push(pos);
            }
        }
        // Chords of the second from a corner into the triangle.
        for corner in 0..3 {
            let (x, y, z) = (t[corner], t[(corner + 1) % 3], t[(corner + 2) % 3]);
            let pos = local
                .iter()
                .position(|&(v, j)| j == usize::MAX && v as usize == x);
            let Some(pos) = pos else { continue };
            for &j in &b_at[x] {
                let (c, d) = cb[j];
                let other = if c == x { d } else { c };
                if on_arc(other, y, z, m) {
                    ends.entry(j).or_default().push(pos);
                }
            }
        }
        let l = local.len();
        let mut nbrs: Vec<Vec<usize>> =
            (0..l).map(|p| vec![(p + 1) % l, (p + l - 1) % l]).collect();
        for e in ends.values() {
            if e.len() == 2 && e[0] != e[1] {
                nbrs[e[0]].push(e[1]);
                nbrs[e[1]].push(e[0]);
            }
        }
        for (p, n) in nbrs.iter_mut().enumerate() {
            n.sort_by_key(|&w| (w + l - p) % l);
            n.dedup();
        }
        // Trace the inner faces: forward boundary edges and chords both ways.
        let mut used: HashMap<(usize, usize), ()> = HashMap::new();
        let mut starts: Vec<(usize, usize)> = (0..l).map(|p| (p, (p + 1) % l)).collect();
        for (p, n) in nbrs.iter().enumerate() {
            for &w in n {
                if w != (p + 1) % l && w != (p + l - 1) % l {
                    starts.push((p, w));
                }
            }
        }
        for (u0, v0) in starts {
            if used.contains_key(&(u0, v0)) {
                continue;
            }
            let mut face = vec![u0];
            let (mut u, mut v) = (u0, v0);
            let mut steps = 0;
            loop {
                used.insert((u, v), ());
                if v == u0 {
                    break;
                }
                face.push(v);
                let n = &nbrs[v];
                let k = n.iter().position(|&w| w == u).unwrap_or(0);
                let w = n[(k + n.len() - 1) % n.len()];
                u = v;
                v = w;
                steps += 1;
                if steps > l + 1 {
                    break;
                }
            }
            for k in 1..face.len().saturating_sub(1) {
                triangles.push([local[face[0]].0, local[face[k]].0, local[face[k + 1]].0]);
            }
        }
    }
    Overlay {
        vertices,
        triangles,
    }
}
