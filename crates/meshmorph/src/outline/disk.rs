//! Each drawing, opened along its cuts into one topological disk, and
//! triangulated without points inside: a constrained Delaunay
//! triangulation (`spade`) of its loop and cut points, with the loops and
//! cuts as constraints.
//!
//! The disk's boundary is a cyclic list of *copies* of points: every
//! point once, except the ends of each cut, met twice (going out along
//! the cut and coming back). Both drawings share the list; only the
//! positions differ. A triangle corner at a point with two copies belongs
//! to the copy whose wedge of the disk (between the boundary edges that
//! leave and enter that copy) holds the corner's bisector.

use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use super::cuts::Cut;
use super::geometry::sub;
use crate::error::{Error, Result};

/// The disk's boundary: for each copy, the point it is (an index into
/// the points: the outer loop's matched points, then each hole's).
pub(crate) struct Disk {
    pub(crate) copies: Vec<usize>,
    /// First point index of each loop (outer first), then the total.
    pub(crate) loop_start: Vec<usize>,
}

impl Disk {
    /// The boundary of the drawings opened along `cuts` (one per hole, in
    /// hole order); `loop_lengths` are the matched loops' point counts.
    pub(crate) fn new(loop_lengths: &[usize], cuts: &[Cut]) -> Self {
        let mut loop_start = vec![0];
        for &n in loop_lengths {
            loop_start.push(loop_start[loop_start.len() - 1] + n);
        }
        let mut at_outer: Vec<Option<usize>> = vec![None; loop_lengths[0]];
        for (h, c) in cuts.iter().enumerate() {
            at_outer[c.outer] = Some(h);
        }
        let mut copies = Vec::with_capacity(loop_start[loop_start.len() - 1] + 2 * cuts.len());
        for j in 0..loop_lengths[0] {
            copies.push(j);
            if let Some(h) = at_outer[j] {
                let n = loop_lengths[h + 1];
                let start = loop_start[h + 1];
                for k in 0..=n {
                    copies.push(start + (cuts[h].hole + k) % n);
                }
                copies.push(j);
            }
        }
        Self { copies, loop_start }
    }

    /// Triangulates the disk with the positions `points` (one per point):
    /// `#T × 3` copy indices, counter-clockwise, `#T` = copies − 2.
    ///
    /// # Errors
    /// [`Error::IncompatibleDrawings`] when the triangulation does not come
    /// out as a disk (points that coincide or constraints that cross after
    /// the matching: not expected from checked drawings).
    /// `chords` (point pairs known to be diagonals inside the drawing that
    /// cross neither each other nor the cuts) are kept as edges.
    pub(crate) fn triangulate(
        &self,
        points: &[[f64; 2]],
        chords: &[[usize; 2]],
        name: &str,
    ) -> Result<Vec<[usize; 3]>> {
        let m = self.copies.len();
        let mut edges: Vec<[usize; 2]> = Vec::with_capacity(m);
        for c in 0..m {
            edges.push([self.copies[c], self.copies[(c + 1) % m]]);
        }
        // Each cut edge appears twice, once each way: keep one.
        let mut seen = std::collections::HashSet::with_capacity(edges.len());
        edges.retain(|&[u, v]| seen.insert((u.min(v), u.max(v))));
        edges.extend(
            chords
                .iter()
                .filter(|&&[u, v]| seen.insert((u.min(v), u.max(v)))),
        );
        let failure = |what: String| {
            Error::IncompatibleDrawings(format!(
                "the {name} could not be triangulated after matching its outline ({what}); please report it with the two drawings"
            ))
        };
        let vertices: Vec<Point2<f64>> = points.iter().map(|p| Point2::new(p[0], p[1])).collect();
        let num_edges = edges.len();
        let mut conflicts = 0usize;
        let cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::try_bulk_load_cdt(
            vertices,
            edges,
            |_| conflicts += 1,
        )
        .map_err(|e| failure(format!("{e:?}")))?;
        if cdt.num_vertices() != points.len() {
            return Err(failure("two points coincide".into()));
        }
        if conflicts > 0 || cdt.num_constraints() != num_edges {
            return Err(failure("edges cross or pass through a point".into()));
        }
        // The copies of each point, with their boundary neighbours.
        let mut first_copy = vec![usize::MAX; points.len()];
        let mut more: std::collections::HashMap<usize, Vec<usize>> = Default::default();
        for (c, &p) in self.copies.iter().enumerate() {
            if first_copy[p] == usize::MAX {
                first_copy[p] = c;
            } else {
                more.entry(p).or_insert_with(|| vec![first_copy[p]]).push(c);
            }
        }
        let angle = |u: [f64; 2], v: [f64; 2]| {
            (u[0] * v[1] - u[1] * v[0])
                .atan2(u[0] * v[0] + u[1] * v[1])
                .rem_euclid(std::f64::consts::TAU)
        };
        // Inside or outside by crossing loop edges from the hull (a
        // centroid test misjudges the slivers between nearly collinear
        // outline points).
        let mut loop_edge = std::collections::HashSet::with_capacity(m);
        for w in self.loop_start.windows(2) {
            for i in w[0]..w[1] {
                let j = if i + 1 == w[1] { w[0] } else { i + 1 };
                loop_edge.insert((i.min(j), i.max(j)));
            }
        }
        let faces: Vec<[usize; 3]> = cdt
            .inner_faces()
            .map(|f| f.vertices().map(|h| h.fix().index()))
            .collect();
        let mut face_of = std::collections::HashMap::with_capacity(faces.len() * 3);
        for (f, v) in faces.iter().enumerate() {
            for i in 0..3 {
                face_of.insert((v[i], v[(i + 1) % 3]), f);
            }
        }
        let is_loop = |u: usize, v: usize| loop_edge.contains(&(u.min(v), u.max(v)));
        let mut parity: Vec<Option<bool>> = vec![None; faces.len()];
        let mut queue = std::collections::VecDeque::new();
        for (f, v) in faces.iter().enumerate() {
            for i in 0..3 {
                let (u, w) = (v[i], v[(i + 1) % 3]);
                if !face_of.contains_key(&(w, u)) && parity[f].is_none() {
                    parity[f] = Some(is_loop(u, w));
                    queue.push_back(f);
                }
            }
        }
        while let Some(f) = queue.pop_front() {
            let v = faces[f];
            let here = parity[f].unwrap_or(false);
            for i in 0..3 {
                let (u, w) = (v[i], v[(i + 1) % 3]);
                if let Some(&g) = face_of.get(&(w, u)) {
                    if parity[g].is_none() {
                        parity[g] = Some(here ^ is_loop(u, w));
                        queue.push_back(g);
                    }
                }
            }
        }
        let mut triangles = Vec::with_capacity(m.saturating_sub(2));
        for (f, &v) in faces.iter().enumerate() {
            if parity[f] != Some(true) {
                continue;
            }
            let mut tri = [0usize; 3];
            for i in 0..3 {
                let p = v[i];
                tri[i] = match more.get(&p) {
                    None => first_copy[p],
                    Some(copies) => {
                        let x = points[p];
                        let (y, z) = (points[v[(i + 1) % 3]], points[v[(i + 2) % 3]]);
                        let unit = |d: [f64; 2]| {
                            let l = d[0].hypot(d[1]);
                            [d[0] / l, d[1] / l]
                        };
                        let (dy, dz) = (unit(sub(y, x)), unit(sub(z, x)));
                        let bis = [dy[0] + dz[0], dy[1] + dz[1]];
                        let mut best = (f64::NEG_INFINITY, copies[0]);
                        for &cp in copies {
                            let next = points[self.copies[(cp + 1) % m]];
                            let prev = points[self.copies[(cp + m - 1) % m]];
                            let (u, w) = (sub(next, x), sub(prev, x));
                            let span = angle(u, w);
                            let span = if span == 0.0 {
                                std::f64::consts::TAU
                            } else {
                                span
                            };
                            let at = angle(u, bis);
                            let margin = at.min(span - at);
                            if margin > best.0 {
                                best = (margin, cp);
                            }
                        }
                        best.1
                    }
                };
            }
            triangles.push(tri);
        }
        if triangles.len() + 2 != m {
            return Err(failure(format!(
                "{} triangles where a disk of {m} boundary points has {}",
                triangles.len(),
                m - 2
            )));
        }
        Ok(triangles)
    }
}

/// The chords of the first drawing's triangulation (as point pairs) that
/// are also diagonals of the second drawing, as many as fit without
/// crossing: kept in the second's triangulation they cross nothing in
/// the overlay, so a pair of similar shapes needs few Steiner points.
pub(crate) fn shared_chords(
    disk: &Disk,
    triangles: &[[usize; 3]],
    points: &[[f64; 2]],
    cut_segments: &[[usize; 2]],
) -> Vec<[usize; 2]> {
    use super::geometry::{diagonal, point_segment_distance, segments_meet};
    let m = disk.copies.len();
    let loops: Vec<Vec<[f64; 2]>> = disk
        .loop_start
        .windows(2)
        .map(|w| points[w[0]..w[1]].to_vec())
        .collect();
    let at = |p: usize| {
        let l = disk.loop_start.partition_point(|&s| s <= p) - 1;
        (l, p - disk.loop_start[l])
    };
    let tol = 1e-9 * diagonal(points.iter());
    let taken: Vec<([f64; 2], [f64; 2])> = cut_segments
        .iter()
        .map(|&[u, v]| (points[u], points[v]))
        .collect();
    let mut chords: Vec<[usize; 2]> = triangles
        .iter()
        .flat_map(|t| (0..3).map(move |i| (t[i], t[(i + 1) % 3])))
        .filter(|&(u, v)| (u + 1) % m != v && (v + 1) % m != u)
        .map(|(u, v)| {
            let (p, q) = (disk.copies[u], disk.copies[v]);
            [p.min(q), p.max(q)]
        })
        .collect();
    chords.sort_unstable();
    chords.dedup();
    let mut kept: Vec<[usize; 2]> = Vec::with_capacity(chords.len());
    for [u, v] in chords {
        let (p, q) = (points[u], points[v]);
        if cut_segments
            .iter()
            .any(|c| (c[0] == u && c[1] == v) || (c[0] == v && c[1] == u))
        {
            continue;
        }
        if !super::cuts::clear(&loops, &taken, at(u), at(v), tol) {
            continue;
        }
        let fits = kept.iter().all(|&[x, y]| {
            let (a, b) = (points[x], points[y]);
            if x == u || x == v || y == u || y == v {
                let (shared, other) = if x == u || x == v { (a, b) } else { (b, a) };
                let far = if shared == p { q } else { p };
                point_segment_distance(other, p, q) > tol && point_segment_distance(far, a, b) > tol
            } else {
                !segments_meet(p, q, a, b, tol)
            }
        });
        if fits {
            kept.push([u, v]);
        }
    }
    kept
}
