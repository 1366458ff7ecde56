//! The fast first try: the first drawing triangulated with good angles
//! (constrained Delaunay refinement, `spade`, the matched boundary kept
//! as it is), then that mesh mapped into the second drawing with its
//! boundary fixed at the matched points: the inside placed by mean-value
//! (convex-combination) weights, then untangled and smoothed by the
//! foldover-free energy of Garanzha, Kaporin, Kudryavtseva, Protais, Ray
//! and Sokolov (2021, "Foldover-free maps in 50 lines of code"),
//! minimised by L-BFGS with a decreasing regularisation.
//!
//! Nothing here is guaranteed: the caller checks that every triangle is
//! positive in both meshes and falls back to the overlay otherwise.

use std::collections::HashSet;

use spade::handles::FixedVertexHandle;
use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation,
};

use super::energy::Energy;
use super::geometry::{diagonal, dist, orient, point_segment_distance};
use super::untangle::{descend_positive, untangle, Patience, Untangling};

/// A mesh of the first drawing: the matched boundary points first (in
/// their order), then the inside points, with counter-clockwise
/// triangles.
pub(crate) struct Refined {
    pub(crate) positions: Vec<[f64; 2]>,
    pub(crate) triangles: Vec<[u32; 3]>,
}

/// Constrained Delaunay refinement of the region bounded by the loops
/// (`loop_start`: first point of each loop, then the total) with the
/// smallest angle aimed at `angle_degrees`, no boundary edge split, and
/// no inside edge joining two boundary points (such an edge would be
/// fixed in the second drawing, where it may well lie outside): those
/// are split by a point at their middle and the refinement run again.
/// `steiner` are inside points put in before the refinement (free
/// vertices, like the refinement's own). `None` when the points do not
/// triangulate as the loops say.
pub(crate) fn refine(
    points: &[[f64; 2]],
    loop_start: &[usize],
    steiner: &[[f64; 2]],
    angle_degrees: f64,
) -> Option<Refined> {
    // The loops' points, then fixed points inside (anchors).
    let n = points.len();
    let mut edges: Vec<[usize; 2]> = Vec::with_capacity(n);
    let mut loop_edge = HashSet::with_capacity(2 * n);
    for w in loop_start.windows(2) {
        for i in w[0]..w[1] {
            let j = if i + 1 == w[1] { w[0] } else { i + 1 };
            edges.push([i, j]);
            loop_edge.insert((i.min(j), i.max(j)));
        }
    }
    let num_edges = edges.len();
    let vertices: Vec<Point2<f64>> = points.iter().map(|p| Point2::new(p[0], p[1])).collect();
    let mut conflicts = 0usize;
    let mut cdt =
        ConstrainedDelaunayTriangulation::<Point2<f64>>::try_bulk_load_cdt(vertices, edges, |_| {
            conflicts += 1
        })
        .ok()?;
    if cdt.num_vertices() != n || conflicts > 0 || cdt.num_constraints() != num_edges {
        return None;
    }
    for p in steiner {
        cdt.insert(Point2::new(p[0], p[1])).ok()?;
    }
    let params = RefinementParameters::<f64>::new()
        .with_angle_limit(AngleLimit::from_deg(angle_degrees))
        .keep_constraint_edges()
        .exclude_outer_faces(true)
        .with_max_additional_vertices(20 * n + 1000);
    for round in 0..6 {
        let result = cdt.refine(params.clone());
        let excluded: HashSet<_> = result.excluded_faces.iter().copied().collect();
        let faces: Vec<[usize; 3]> = cdt
            .inner_faces()
            .filter(|f| !excluded.contains(&f.fix()))
            .map(|f| f.vertices().map(|h| h.fix().index()))
            .collect();
        let mut chords: Vec<(usize, usize)> = faces
            .iter()
            .flat_map(|t| (0..3).map(move |i| (t[i], t[(i + 1) % 3])))
            .filter(|&(u, v)| u < n && v < n && !loop_edge.contains(&(u.min(v), u.max(v))))
            .map(|(u, v)| (u.min(v), u.max(v)))
            .collect();
        if chords.is_empty() {
            return finish(&cdt, n, &faces);
        }
        if round == 5 {
            return None;
        }
        chords.sort_unstable();
        chords.dedup();
        for (u, v) in chords {
            let (p, q) = (points[u], points[v]);
            let mid = Point2::new(0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]));
            cdt.insert(mid).ok()?;
        }
    }
    None
}

/// The faces kept, their vertices renumbered: the boundary points first.
fn finish(
    cdt: &ConstrainedDelaunayTriangulation<Point2<f64>>,
    n: usize,
    faces: &[[usize; 3]],
) -> Option<Refined> {
    let mut new_index = vec![u32::MAX; cdt.num_vertices()];
    let mut positions: Vec<[f64; 2]> = Vec::with_capacity(cdt.num_vertices());
    for (v, slot) in new_index.iter_mut().enumerate().take(n) {
        *slot = v as u32;
        let p = cdt.vertex(FixedVertexHandle::from_index(v)).position();
        positions.push([p.x, p.y]);
    }
    let mut triangles = Vec::with_capacity(faces.len());
    for f in faces {
        let mut t = [0u32; 3];
        for k in 0..3 {
            let v = f[k];
            if new_index[v] == u32::MAX {
                new_index[v] = positions.len() as u32;
                let p = cdt.vertex(FixedVertexHandle::from_index(v)).position();
                positions.push([p.x, p.y]);
            }
            t[k] = new_index[v];
        }
        triangles.push(t);
    }
    // Every boundary point must be used.
    let mut used = vec![false; n];
    for t in &triangles {
        for &v in t {
            if (v as usize) < n {
                used[v as usize] = true;
            }
        }
    }
    used.iter().all(|&u| u).then_some(Refined {
        positions,
        triangles,
    })
}

/// Mean-value weights of each inside vertex's neighbours (Floater 2003),
/// from the mesh's positions in the first drawing: `(neighbour, weight)`
/// lists, the boundary vertices' lists empty.
fn mean_value_weights(
    a: &[[f64; 2]],
    triangles: &[[u32; 3]],
    fixed: usize,
) -> Vec<Vec<(u32, f64)>> {
    let mut w: Vec<Vec<(u32, f64)>> = vec![Vec::new(); a.len()];
    for t in triangles {
        for k in 0..3 {
            let (i, j, l) = (t[k] as usize, t[(k + 1) % 3], t[(k + 2) % 3]);
            if i < fixed {
                continue;
            }
            let (pj, pl) = (a[j as usize], a[l as usize]);
            let u = [pj[0] - a[i][0], pj[1] - a[i][1]];
            let v = [pl[0] - a[i][0], pl[1] - a[i][1]];
            let (lu, lv) = (u[0].hypot(u[1]), v[0].hypot(v[1]));
            let angle = (u[0] * v[1] - u[1] * v[0])
                .abs()
                .atan2(u[0] * v[0] + u[1] * v[1]);
            let half = (0.5 * angle).tan();
            w[i].push((j, half / lu));
            w[i].push((l, half / lv));
        }
    }
    for list in &mut w {
        list.sort_unstable_by_key(|e| e.0);
        let mut merged: Vec<(u32, f64)> = Vec::with_capacity(list.len() / 2 + 1);
        for &(j, x) in list.iter() {
            match merged.last_mut() {
                Some(last) if last.0 == j => last.1 += x,
                _ => merged.push((j, x)),
            }
        }
        let total: f64 = merged.iter().map(|e| e.1).sum();
        for e in &mut merged {
            e.1 /= total;
        }
        *list = merged;
    }
    w
}

/// The inside vertices placed in the second drawing: started from the
/// first drawing's mesh moved by the similarity that best lays its
/// boundary onto the second's, then convex combinations of their
/// neighbours by mean-value weights (successive over-relaxation), which
/// reproduce a similarity exactly.
fn place_inside(a: &[[f64; 2]], b_boundary: &[[f64; 2]], triangles: &[[u32; 3]]) -> Vec<[f64; 2]> {
    let n = b_boundary.len();
    // Least-squares similarity z -> s z + t in complex numbers.
    let mean = |p: &[[f64; 2]]| {
        let s = p.iter().fold([0.0, 0.0], |m, q| [m[0] + q[0], m[1] + q[1]]);
        [s[0] / p.len() as f64, s[1] / p.len() as f64]
    };
    let (ca, cb) = (mean(&a[..n]), mean(b_boundary));
    let (mut re, mut im, mut norm) = (0.0, 0.0, 0.0);
    for (p, q) in a[..n].iter().zip(b_boundary) {
        let (x, y) = ([p[0] - ca[0], p[1] - ca[1]], [q[0] - cb[0], q[1] - cb[1]]);
        // conj(x) * y
        re += x[0] * y[0] + x[1] * y[1];
        im += x[0] * y[1] - x[1] * y[0];
        norm += x[0] * x[0] + x[1] * x[1];
    }
    let (re, im) = (re / norm, im / norm);
    let mut b: Vec<[f64; 2]> = a
        .iter()
        .map(|p| {
            let x = [p[0] - ca[0], p[1] - ca[1]];
            [re * x[0] - im * x[1] + cb[0], im * x[0] + re * x[1] + cb[1]]
        })
        .collect();
    b[..n].copy_from_slice(b_boundary);
    let weights = mean_value_weights(a, triangles, n);
    let tol = 1e-13 * diagonal(b_boundary.iter());
    let omega = 1.7;
    for _ in 0..4000 {
        let mut change: f64 = 0.0;
        for i in n..b.len() {
            let mut s = [0.0, 0.0];
            for &(j, w) in &weights[i] {
                let q = b[j as usize];
                s[0] += w * q[0];
                s[1] += w * q[1];
            }
            let p = b[i];
            let d = [s[0] - p[0], s[1] - p[1]];
            change = change.max(d[0].abs()).max(d[1].abs());
            b[i] = [p[0] + omega * d[0], p[1] + omega * d[1]];
        }
        if change <= tol {
            break;
        }
    }
    b
}

/// Maps the first drawing's mesh `a` (boundary points first, `n` of
/// them) into the second drawing, whose boundary points are
/// `b_boundary`: positions for every vertex, the boundary exactly
/// `b_boundary`. The result may still hold turned-over triangles; the
/// caller checks.
pub(crate) fn map_into(
    a: &[[f64; 2]],
    triangles: &[[u32; 3]],
    b_boundary: &[[f64; 2]],
    patience: Patience<'_>,
) -> Vec<[f64; 2]> {
    let b = place_inside(a, b_boundary, triangles);
    untangle(a, triangles, b, b_boundary.len(), patience)
}

/// Moves the vertices from `n` on of a valid mesh (the first `n` stay) to
/// lower the sum over its triangles of their conformal distortion from an
/// equilateral triangle (the MIPS energy of Hormann and Greiner 2000,
/// `|J|² / det J`, the shape part of the foldover-free energy): angles
/// evened out, and a barrier that keeps every triangle positive, so the
/// result is valid when the start is. At most `iterations` L-BFGS steps.
pub(crate) fn relax(b: &mut [[f64; 2]], triangles: &[[u32; 3]], n: usize, iterations: usize) {
    if b.len() <= n || triangles.is_empty() {
        return;
    }
    let energy = Energy::equilateral(triangles);
    if energy.min_det(b) <= 0.0 {
        return;
    }
    descend_positive(&energy, b, n, iterations);
}

/// The second drawing's area, from its boundary loops (signed, as the
/// triangles' boundary edges run).
pub fn area_from_boundary(b: &[[f64; 2]], triangles: &[[u32; 3]], n: usize) -> f64 {
    // Boundary edges are the directed edges whose reverse is absent, both
    // ends on the boundary.
    let mut edges: HashSet<(u32, u32)> = HashSet::with_capacity(triangles.len() * 3);
    for t in triangles {
        for k in 0..3 {
            edges.insert((t[k], t[(k + 1) % 3]));
        }
    }
    let mut twice = 0.0;
    for t in triangles {
        for k in 0..3 {
            let (u, v) = (t[k], t[(k + 1) % 3]);
            if (u as usize) < n && (v as usize) < n && !edges.contains(&(v, u)) {
                let (p, q) = (b[u as usize], b[v as usize]);
                twice += p[0] * q[1] - q[0] * p[1];
            }
        }
    }
    0.5 * twice
}

/// Whether every triangle is positive in `positions`, by more than a
/// relative `1e-12` of its longest edge squared.
pub(crate) fn all_positive(positions: &[[f64; 2]], triangles: &[[u32; 3]]) -> bool {
    triangles.iter().all(|t| {
        let [x, y, z] = t.map(|v| positions[v as usize]);
        let l = |u: [f64; 2], v: [f64; 2]| (u[0] - v[0]).powi(2) + (u[1] - v[1]).powi(2);
        let longest = l(x, y).max(l(y, z)).max(l(z, x));
        let area = orient(x, y, z);
        area.is_finite() && area > 1e-12 * longest
    })
}

/// Free points around each anchor inside of one drawing (`points`: the
/// loops' points up to `loop_start`'s last entry, then the anchors),
/// `rings` rings of six each, the outermost at 0.6 of the way to the
/// nearest loop or 0.3 of the way to the nearest other anchor (0.6 of
/// half-way), whichever is nearer. The anchor's own
/// triangles then have no other fixed corner: a fixed corner beside a
/// fixed anchor pins a triangle's edge in every drawing, where the
/// anchor and that corner may well sit the other way round, and the
/// rings give the untangling the room to turn and shear the anchor's
/// neighbourhood.
pub(crate) fn rings_around_anchors(
    points: &[[f64; 2]],
    loop_start: &[usize],
    rings: usize,
) -> Vec<[f64; 2]> {
    let n = loop_start[loop_start.len() - 1];
    let mut out = Vec::with_capacity(6 * rings * (points.len() - n));
    for (j, &p) in points.iter().enumerate().skip(n) {
        let to_loops = loop_start
            .windows(2)
            .flat_map(|w| (w[0]..w[1]).map(move |i| (i, if i + 1 == w[1] { w[0] } else { i + 1 })))
            .map(|(i, k)| point_segment_distance(p, points[i], points[k]))
            .fold(f64::INFINITY, f64::min);
        let to_anchors = points[n..]
            .iter()
            .enumerate()
            .filter(|&(k, _)| k + n != j)
            .map(|(_, &q)| 0.5 * dist(p, q))
            .fold(f64::INFINITY, f64::min);
        let reach = 0.6 * to_loops.min(to_anchors);
        for r in 1..=rings {
            let radius = reach * r as f64 / rings as f64;
            // Each ring turned by half a step from the one inside it.
            let turn = 0.5 * (r % 2) as f64;
            for k in 0..6 {
                let angle = (k as f64 + turn) * std::f64::consts::FRAC_PI_3;
                out.push([p[0] + radius * angle.cos(), p[1] + radius * angle.sin()]);
            }
        }
    }
    out
}

/// Drawing `source` refined for the fast way (its fixed points
/// `fixed[source]`: the loops' points, then any anchors inside; with
/// `rings` of free points around each anchor,
/// [`rings_around_anchors`]). `None` when it does not triangulate as its
/// loops say or a triangle comes out flat.
pub(crate) fn source_mesh(
    fixed: &[Vec<[f64; 2]>],
    source: usize,
    loop_start: &[usize],
    rings: usize,
    angle_degrees: f64,
) -> Option<Refined> {
    let steiner = rings_around_anchors(&fixed[source], loop_start, rings);
    let refined = refine(&fixed[source], loop_start, &steiner, angle_degrees)?;
    all_positive(&refined.positions, &refined.triangles).then_some(refined)
}

/// One drawing's refined mesh being mapped into every other drawing
/// with its own fixed points: placed ([`place_inside`]), then untangled,
/// one drawing after another, as far as the patience given so far.
pub(crate) struct Mapping<'r> {
    source: usize,
    refined: &'r Refined,
    /// The untangling into each drawing (none into the source).
    into: Vec<Option<Untangling<'r>>>,
}

impl<'r> Mapping<'r> {
    /// `refined` (drawing `source`'s mesh, [`source_mesh`]) placed in
    /// every other drawing at its fixed points, nothing untangled yet.
    pub(crate) fn start(fixed: &[Vec<[f64; 2]>], source: usize, refined: &'r Refined) -> Self {
        let into = fixed
            .iter()
            .enumerate()
            .map(|(k, points)| {
                (k != source).then(|| {
                    let b = place_inside(&refined.positions, points, &refined.triangles);
                    Untangling::new(&refined.positions, &refined.triangles, b, points.len())
                })
            })
            .collect();
        Self {
            source,
            refined,
            into,
        }
    }

    /// Untangles into each drawing in turn as far as `patience` (counted
    /// from the start, [`Patience`]); whether every one is untangled. A
    /// drawing left tangled stops the ones after it, which are taken up
    /// with the next call.
    pub(crate) fn go(&mut self, patience: Patience<'_>) -> bool {
        self.into
            .iter_mut()
            .flatten()
            .all(|untangling| untangling.go(patience))
    }

    /// The positions in every drawing and the triangles, when every
    /// triangle is positive in all (by [`all_positive`]).
    pub(crate) fn finish(self) -> Option<super::Positioned> {
        let mut meshes = Vec::with_capacity(self.into.len());
        for (k, untangling) in self.into.into_iter().enumerate() {
            meshes.push(match untangling {
                None if k == self.source => self.refined.positions.clone(),
                None => return None,
                Some(u) => {
                    let b = u.finish();
                    if !all_positive(&b, &self.refined.triangles) {
                        return None;
                    }
                    b
                }
            });
        }
        Some((meshes, self.refined.triangles.clone()))
    }
}

/// The fast way whole: drawing `source` refined ([`source_mesh`]),
/// mapped into every other drawing with its own fixed points
/// ([`Mapping`]), all checked: the positions in every drawing and the
/// triangles. `None` when any triangle is not positive in any.
pub(crate) fn compatible(
    fixed: &[Vec<[f64; 2]>],
    source: usize,
    loop_start: &[usize],
    rings: usize,
    angle_degrees: f64,
    patience: Patience<'_>,
) -> Option<super::Positioned> {
    let refined = source_mesh(fixed, source, loop_start, rings, angle_degrees)?;
    let mut mapping = Mapping::start(fixed, source, &refined);
    if !mapping.go(patience) {
        return None;
    }
    mapping.finish()
}
