//! Anchors: points kept matched across the drawings, one point per
//! drawing each. An anchor is on the outlines when every one of its points
//! lies within 1 % of its drawing's size from an outline (it is moved onto
//! it and steers the boundary correspondence), or inside the shapes when
//! none does (it becomes a vertex of every mesh, at exactly its point).

use super::boundary::LoopAnchor;
use super::common::CommonBoundary;
use super::geometry::{diagonal, dist, inside_loop};
use super::mapped::all_positive;
use super::untangle::{untangle, Patience};
use super::{snap, Drawing};
use crate::error::{Error, Result};

/// An anchor's point on an outline: its loop, where along it (a fraction
/// of the loop's length) and the point.
#[derive(Clone, Copy, Debug)]
struct OnLoop {
    l: usize,
    t: f64,
    p: [f64; 2],
}

/// The anchors, sorted into those on the outlines and those inside.
pub(crate) struct Placed {
    /// For each anchor on the outlines, its point on each drawing.
    on_outline: Vec<Vec<OnLoop>>,
    /// For each anchor inside, its point in each drawing.
    pub(crate) inside: Vec<Vec<[f64; 2]>>,
    /// For each anchor as given: `Ok(i)` the i-th on the outlines,
    /// `Err(j)` the j-th inside.
    order: Vec<std::result::Result<usize, usize>>,
}

/// Whether `p` lies inside the drawing's region (inside the outer loop
/// and outside every hole).
fn inside_region(d: &Drawing, p: [f64; 2]) -> bool {
    let loops = d.loops();
    inside_loop(p, &loops[0]) && loops[1..].iter().all(|h| !inside_loop(p, h))
}

/// Sorts the anchors, checking each has one finite point per drawing, all
/// on the outlines or all inside.
pub(crate) fn place(drawings: &[Drawing], anchors: &[Vec<[f64; 2]>]) -> Result<Placed> {
    let sizes: Vec<f64> = drawings
        .iter()
        .map(|d| diagonal(d.loops().iter().flatten()))
        .collect();
    let mut placed = Placed {
        on_outline: Vec::new(),
        inside: Vec::new(),
        order: Vec::with_capacity(anchors.len()),
    };
    for (k, anchor) in anchors.iter().enumerate() {
        if anchor.len() != drawings.len() {
            return Err(Error::IncompatibleDrawings(format!(
                "anchor {} has {} point{} but there are {} drawings: give one point per drawing",
                k + 1,
                anchor.len(),
                if anchor.len() == 1 { "" } else { "s" },
                drawings.len()
            )));
        }
        let mut snapped = Vec::with_capacity(drawings.len());
        for (d, (&p, drawing)) in anchor.iter().zip(drawings).enumerate() {
            if !(p[0].is_finite() && p[1].is_finite()) {
                return Err(Error::IncompatibleDrawings(format!(
                    "anchor {}'s point on drawing {} is not finite: {p:?}",
                    k + 1,
                    d + 1
                )));
            }
            let (l, t, q, distance) = snap(drawing.loops(), p);
            let on = distance <= 0.01 * sizes[d];
            if !on && !inside_region(drawing, p) {
                return Err(Error::IncompatibleDrawings(format!(
                    "anchor {}'s point {p:?} lies outside drawing {}: put it on the outline or inside the shape",
                    k + 1,
                    d + 1
                )));
            }
            snapped.push(on.then_some(OnLoop { l, t, p: q }));
        }
        let on_count = snapped.iter().filter(|s| s.is_some()).count();
        if on_count == drawings.len() {
            placed.order.push(Ok(placed.on_outline.len()));
            placed.on_outline.push(
                snapped
                    .into_iter()
                    .map(|s| s.unwrap_or_else(|| unreachable!()))
                    .collect(),
            );
        } else if on_count == 0 {
            placed.order.push(Err(placed.inside.len()));
            placed.inside.push(anchor.clone());
        } else {
            let which: Vec<String> = snapped
                .iter()
                .enumerate()
                .filter(|(_, s)| s.is_some())
                .map(|(d, _)| (d + 1).to_string())
                .collect();
            return Err(Error::IncompatibleDrawings(format!(
                "anchor {} is on the outline of drawing {} but inside the shape in the others: \
                 put all its points on the outlines (within 1 % of each drawing's size) or all inside",
                k + 1,
                which.join(", ")
            )));
        }
    }
    check_apart(&placed, &sizes)?;
    Ok(placed)
}

/// The least distance between two anchors inside a drawing, as a fraction
/// of its size: closer ones would make triangles of no area between them.
const ANCHORS_APART: f64 = 1e-3;

/// Refuses two anchors inside that lie at (almost) the same place in a
/// drawing (each drawing's points hashed into cells of that size, so that
/// many anchors cost no more than their number).
fn check_apart(placed: &Placed, sizes: &[f64]) -> Result<()> {
    let number = |j: usize| {
        placed
            .order
            .iter()
            .position(|o| *o == Err(j))
            .map_or(j + 1, |i| i + 1)
    };
    for (d, size) in sizes.iter().enumerate() {
        let least = ANCHORS_APART * size;
        let cell = |p: [f64; 2]| ((p[0] / least).floor() as i64, (p[1] / least).floor() as i64);
        let mut cells: std::collections::HashMap<(i64, i64), Vec<usize>> =
            std::collections::HashMap::new();
        for (j, a) in placed.inside.iter().enumerate() {
            let (x, y) = cell(a[d]);
            for near in (x - 1..=x + 1).flat_map(|x| (y - 1..=y + 1).map(move |y| (x, y))) {
                for &i in cells.get(&near).into_iter().flatten() {
                    let apart = dist(placed.inside[i][d], a[d]);
                    if apart < least {
                        return Err(Error::IncompatibleDrawings(format!(
                            "anchors {} and {} lie {apart} apart on drawing {}, less than {} % of its size: give each its own place, or drop one",
                            number(i),
                            number(j),
                            d + 1,
                            100.0 * ANCHORS_APART
                        )));
                    }
                }
            }
            cells.entry((x, y)).or_default().push(j);
        }
    }
    Ok(())
}

impl Placed {
    /// The anchors on the outlines that lie on loop `l` of the first
    /// drawing and loop `m` of drawing `k`, for matching those loops.
    pub(crate) fn on_loops(&self, k: usize, l: usize, m: usize) -> Result<Vec<LoopAnchor>> {
        let mut out = Vec::new();
        for (i, points) in self.on_outline.iter().enumerate() {
            let (x, y) = (points[0], points[k]);
            if (x.l == l) != (y.l == m) {
                return Err(Error::IncompatibleDrawings(format!(
                    "anchor {} is on loop {} of the first drawing and loop {} of drawing {}, which do not pair (loop {l} pairs with loop {m}): put its points on loops that pair, outer with outer",
                    self.given_number(Ok(i)),
                    x.l,
                    y.l,
                    k + 1
                )));
            }
            if x.l == l {
                out.push(LoopAnchor {
                    ta: x.t,
                    tb: y.t,
                    a: x.p,
                    b: y.p,
                });
            }
        }
        Ok(out)
    }

    /// The anchor's number as given, counted from 1.
    fn given_number(&self, which: std::result::Result<usize, usize>) -> usize {
        self.order.iter().position(|&o| o == which).unwrap_or(0) + 1
    }

    /// The vertex of each anchor as given: on the outlines, the boundary
    /// vertex at its point in the first drawing; inside, `n` + its place
    /// among those inside.
    pub(crate) fn vertices(&self, boundary: &CommonBoundary, n: usize) -> Vec<u32> {
        self.order
            .iter()
            .map(|o| match *o {
                Ok(i) => {
                    let p = self.on_outline[i][0].p;
                    (0..n)
                        .min_by(|&u, &v| {
                            dist(boundary.points[0][u], p)
                                .total_cmp(&dist(boundary.points[0][v], p))
                        })
                        .unwrap_or(0) as u32
                }
                Err(j) => (n + j) as u32,
            })
            .collect()
    }
}

/// Puts the anchors inside into compatible meshes that have none: each
/// added in the first drawing's triangle that holds it (inside it, where
/// every mesh has it by the same barycentric coordinates), the vertices
/// renumbered so that the anchors follow the `n` boundary points, then in
/// every drawing moved to its point with the boundary and the other
/// anchors fixed and the rest untangled. `fixed[d]` holds drawing `d`'s
/// boundary points, then its anchors.
///
/// # Errors
/// [`Error::IncompatibleDrawings`] when an anchor cannot be reached
/// without turning a triangle over.
pub(crate) fn insert_inside(
    meshes: &mut [Vec<[f64; 2]>],
    triangles: &mut Vec<[u32; 3]>,
    fixed: &[Vec<[f64; 2]>],
    n: usize,
) -> Result<()> {
    let m = fixed[0].len() - n;
    let mut added = Vec::with_capacity(m);
    for j in 0..m {
        let q = fixed[0][n + j];
        // The triangle of the first mesh holding q deepest.
        let mut best: Option<(f64, usize, [f64; 3])> = None;
        for (t, tri) in triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|v| meshes[0][v as usize]);
            let det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
            let l1 = ((q[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (q[1] - a[1])) / det;
            let l2 = ((b[0] - a[0]) * (q[1] - a[1]) - (q[0] - a[0]) * (b[1] - a[1])) / det;
            let l = [1.0 - l1 - l2, l1, l2];
            let depth = l[0].min(l[1]).min(l[2]);
            if depth.is_finite() && best.is_none_or(|b| depth > b.0) {
                best = Some((depth, t, l));
            }
        }
        let Some((_, t, l)) = best else {
            return Err(Error::IncompatibleDrawings(
                "an anchor inside lies in no triangle of the first drawing's mesh".into(),
            ));
        };
        // Strictly inside the triangle, so that every mesh stays valid.
        let l = l.map(|x| x.max(0.02));
        let sum = l[0] + l[1] + l[2];
        let l = l.map(|x| x / sum);
        let tri = triangles[t];
        let w = meshes[0].len() as u32;
        for mesh in meshes.iter_mut() {
            let [a, b, c] = tri.map(|v| mesh[v as usize]);
            mesh.push([
                l[0] * a[0] + l[1] * b[0] + l[2] * c[0],
                l[0] * a[1] + l[1] * b[1] + l[2] * c[1],
            ]);
        }
        let [a, b, c] = tri;
        triangles[t] = [a, b, w];
        triangles.push([b, c, w]);
        triangles.push([c, a, w]);
        added.push(w);
    }
    // Renumbered: the boundary, the anchors, then the rest.
    let total = meshes[0].len();
    let mut order: Vec<u32> = (0..n as u32).collect();
    order.extend(&added);
    let mut is_anchor = vec![false; total];
    for &w in &added {
        is_anchor[w as usize] = true;
    }
    order.extend((n as u32..total as u32).filter(|&v| !is_anchor[v as usize]));
    let mut new_index = vec![0u32; total];
    for (i, &v) in order.iter().enumerate() {
        new_index[v as usize] = i as u32;
    }
    for mesh in meshes.iter_mut() {
        *mesh = order.iter().map(|&v| mesh[v as usize]).collect();
    }
    for tri in triangles.iter_mut() {
        *tri = tri.map(|v| new_index[v as usize]);
    }
    // Each drawing's anchors moved to their points in steps, the rest
    // untangled after each, shaped like the first drawing's mesh.
    const STEPS: usize = 8;
    for d in 0..meshes.len() {
        let reference = meshes[0].clone();
        let start: Vec<[f64; 2]> = meshes[d][n..n + m].to_vec();
        let mut moved = meshes[d].clone();
        for step in 1..=STEPS {
            let s = step as f64 / STEPS as f64;
            for j in 0..m {
                let (p, q) = (start[j], fixed[d][n + j]);
                moved[n + j] = [p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])];
            }
            moved = untangle(&reference, triangles, moved, n + m, Patience::LONG);
        }
        if !all_positive(&moved, triangles) {
            return Err(Error::IncompatibleDrawings(format!(
                "the anchors inside could not be put in place in drawing {} without turning a triangle over \
                 (distinct points inside can always be matched without a fold, but this mesh did not find the way): \
                 check that each anchor is at the corresponding place in every drawing, move anchors that sit \
                 very close to the outline or to each other apart, or add anchors on the outlines",
                d + 1
            )));
        }
        meshes[d] = moved;
    }
    Ok(())
}
