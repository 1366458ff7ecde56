//! Where each vertex of a head takes its motion from: its place on the
//! template fitted onto it.
//!
//! 1. Each vertex looks for its place alone ([`place_of`]): the closest
//!    point of a template triangle facing its way, so that a point of a
//!    closed upper lip finds the upper lip and not the lower one, or the
//!    closest point of all at a fold.
//! 2. The places must be as connected as the head is: two vertices joined
//!    by an edge of the head have places joined by a path along the
//!    template not much longer than that edge ([`PATH_STRETCH`]). Where
//!    the fitted template is a little off, near a mouth's corner, a few
//!    vertices of one lip can still find the other lip, which lies as close
//!    in space but far along the surface (around the corner or through the
//!    mouth). Cutting the head's edges whose ends' places are not joined
//!    leaves such vertices as islands ([`ISLAND_SHARE`]) apart from the
//!    rest of the head.
//! 3. Each island vertex, from the island's shore inwards, takes its place
//!    among the template triangles joined to the places of its neighbours
//!    already settled, by the same rule as in 1.
//!
//! A head whose mouth is modelled closed, its lips one surface, keeps the
//! cut between its lips: each side reaches the rest of the head around the
//! mouth's corners, and neither is an island.

use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap, HashSet, VecDeque};

use rayon::prelude::*;

use crate::linalg::vector::{add, dot, norm, scale, sub};
use crate::mesh::closest::{
    closest_point_on_triangle, closest_region, unit_normal, vertex_normals, Angle, ClosestPoint,
    SurfaceIndex,
};
use crate::mesh::topology::VertexStar;
use crate::mesh::Mesh3;

/// How far a head vertex's normal may turn from the template triangle it
/// takes its motion from, in degrees.
pub const LOOKUP_ANGLE: f64 = 60.0;

/// How much farther than the closest point a point facing a vertex's way
/// may be and still be taken, as a fraction of the head's diagonal.
pub const FOLD_SLACK: f64 = 0.01;

/// How much longer than the head's edge between two vertices the path
/// along the template between their places may be (plus each vertex's
/// distance to its place) for the two places to count as joined. Paths
/// along a triangulation's edges are up to about 1.3 times the straight
/// line on a smooth surface; around a lip's corner from one lip to the
/// other is several times the lips' distance.
pub const PATH_STRETCH: f64 = 2.0;

/// The largest share of the head's vertices a piece cut off from the rest
/// by unjoined places may hold and be an island, its places taken again
/// from around it.
pub const ISLAND_SHARE: f64 = 0.01;

/// Where a head vertex takes its motion from: a template triangle and the
/// barycentric coordinates of a point on it.
#[derive(Clone, Copy, Debug)]
pub struct Place {
    pub triangle: u32,
    pub weights: [f64; 3],
}

/// What the lookups need of the fitted template.
pub struct Template<'a> {
    /// The template laid onto the head, where places are looked up.
    pub mesh: &'a Mesh3,
    pub index: SurfaceIndex,
    /// The template before it was laid onto the head, where paths between
    /// places are measured: laying it on can crumple it where the head
    /// differs (a hairline, a crease), the paths across it with it.
    pub smooth: &'a [[f64; 3]],
    pub star: VertexStar,
}

impl Template<'_> {
    /// Where `hit`'s point is on the smooth template.
    fn smooth_point(&self, hit: &ClosestPoint) -> [f64; 3] {
        let t = hit.triangle as usize;
        let w = closest_region(hit.point, self.mesh.corners(t)).barycentric();
        let tri = self.mesh.triangles()[t];
        (0..3).fold([0.0; 3], |acc, i| {
            add(acc, scale(self.smooth[tri[i] as usize], w[i]))
        })
    }

    /// The longest edge of triangle `t` on the smooth template.
    fn longest_edge(&self, t: u32) -> f64 {
        let [a, b, c] = self.mesh.triangles()[t as usize].map(|v| self.smooth[v as usize]);
        norm(sub(a, b)).max(norm(sub(b, c))).max(norm(sub(c, a)))
    }
}

/// Each vertex's place, and what the search for them found.
pub struct Places {
    /// Each vertex's place.
    pub places: Vec<Place>,
    /// The head's edges whose ends' places are not joined, each vertex pair
    /// smaller first: where the head is one surface and the template two
    /// (lips or eyelids modelled joined), and around islands.
    pub cut: Vec<(u32, u32)>,
}

/// Each vertex of `surface`'s place on `deformed` (the template laid onto
/// it), islands taken again from around them; `smooth` is the template in
/// the head's place before it was laid on (the same triangles).
pub fn find_places(deformed: &Mesh3, smooth: &[[f64; 3]], surface: &Mesh3) -> Places {
    let template = Template {
        mesh: deformed,
        index: SurfaceIndex::new(deformed.positions(), deformed.triangles()),
        smooth,
        star: VertexStar::new(deformed.num_vertices(), deformed.triangles()),
    };
    let normals = vertex_normals(surface.positions(), surface.triangles());
    let diagonal = surface.bounding_box_diagonal();
    let positions = surface.positions();
    let mut hits: Vec<ClosestPoint> = positions
        .par_iter()
        .zip(&normals)
        .map(|(&p, &n)| place_of(&template.index, p, n, diagonal))
        .collect();

    let head_star = VertexStar::new(surface.num_vertices(), surface.triangles());
    let cut = cut_edges(&template, &head_star, positions, &hits);
    let islands = islands(&head_star, positions.len(), &cut);
    retake_islands(
        &template, &head_star, positions, &normals, diagonal, &islands, &mut hits,
    );

    let places = positions
        .par_iter()
        .zip(&hits)
        .map(|(&p, hit)| Place {
            triangle: hit.triangle,
            weights: closest_region(p, deformed.corners(hit.triangle as usize)).barycentric(),
        })
        .collect();
    let mut cut: Vec<(u32, u32)> = cut.into_iter().collect();
    cut.sort_unstable();
    Places { places, cut }
}

/// The point of the template a head vertex at `p` with unit normal `n`
/// takes its motion from: the closest point on a triangle facing within
/// [`LOOKUP_ANGLE`] of `n`, so that a point of a closed upper lip finds the
/// upper lip, whose surface faces down there, not the lower one facing up;
/// but only if it is at most [`FOLD_SLACK`] of the `diagonal` farther than
/// the closest point of all. Else the closest point: at a fold (the corner
/// of a mouth, where upper and lower lip meet) the head's normal points
/// across the fold, away from every triangle there, and the nearest facing
/// one lies on another part of the face.
pub fn place_of(index: &SurfaceIndex, p: [f64; 3], n: [f64; 3], diagonal: f64) -> ClosestPoint {
    let closest = index.closest(p).expect("the template has triangles");
    facing_or_closest(closest, diagonal, |within| {
        index.closest_compatible(p, n, within, Angle::degrees(LOOKUP_ANGLE))
    })
}

/// [`place_of`]'s rule: the closest facing point that `facing_within`
/// finds within [`FOLD_SLACK`] of the `diagonal` farther than `closest`,
/// else `closest`.
fn facing_or_closest(
    closest: ClosestPoint,
    diagonal: f64,
    facing_within: impl FnOnce(f64) -> Option<ClosestPoint>,
) -> ClosestPoint {
    facing_within(closest.distance + FOLD_SLACK * diagonal).unwrap_or(closest)
}

/// The head's edges whose ends' places are not [`joined`].
pub fn cut_edges(
    template: &Template,
    head: &VertexStar,
    positions: &[[f64; 3]],
    hits: &[ClosestPoint],
) -> HashSet<(u32, u32)> {
    (0..positions.len())
        .into_par_iter()
        .flat_map_iter(|u| {
            head.neighbours(u)
                .iter()
                .filter(move |&&v| v as usize > u)
                .filter(move |&&v| {
                    let v = v as usize;
                    let bound = PATH_STRETCH * norm(sub(positions[u], positions[v]))
                        + hits[u].distance
                        + hits[v].distance;
                    !joined(template, &hits[u], &hits[v], bound)
                })
                .map(move |&v| (u as u32, v))
        })
        .collect()
}

/// The head's vertices cut off from the rest by the `cut` edges, in pieces
/// of at most [`ISLAND_SHARE`] of them.
pub fn islands(head: &VertexStar, n: usize, cut: &HashSet<(u32, u32)>) -> HashSet<u32> {
    if cut.is_empty() {
        return HashSet::new();
    }
    let largest_island = (ISLAND_SHARE * n as f64) as usize;
    let mut seen = vec![false; n];
    let mut islands = HashSet::new();
    let mut stack = Vec::new();
    for start in 0..n {
        if seen[start] {
            continue;
        }
        seen[start] = true;
        let mut piece = vec![start as u32];
        stack.push(start);
        while let Some(u) = stack.pop() {
            for &v in head.neighbours(u) {
                let pair = (u.min(v as usize) as u32, u.max(v as usize) as u32);
                if !seen[v as usize] && !cut.contains(&pair) {
                    seen[v as usize] = true;
                    piece.push(v);
                    stack.push(v as usize);
                }
            }
        }
        if piece.len() <= largest_island {
            islands.extend(piece);
        }
    }
    // A head cut to pieces everywhere has no shore to take places from.
    if islands.len() == n {
        islands.clear();
    }
    islands
}

/// Gives each island vertex a place joined to those of its settled
/// neighbours, from the islands' shores inwards.
pub fn retake_islands(
    template: &Template,
    head: &VertexStar,
    positions: &[[f64; 3]],
    normals: &[[f64; 3]],
    diagonal: f64,
    islands: &HashSet<u32>,
    hits: &mut [ClosestPoint],
) {
    let mut settled: Vec<bool> = (0..positions.len() as u32)
        .map(|v| !islands.contains(&v))
        .collect();
    let mut queue: VecDeque<u32> = islands
        .iter()
        .copied()
        .filter(|&v| {
            head.neighbours(v as usize)
                .iter()
                .any(|&w| settled[w as usize])
        })
        .collect();
    queue.make_contiguous().sort_unstable();
    while let Some(v) = queue.pop_front() {
        let v = v as usize;
        if settled[v] {
            continue;
        }
        let p = positions[v];
        let mut candidates = HashSet::new();
        for &w in head.neighbours(v) {
            let w = w as usize;
            if !settled[w] {
                continue;
            }
            let bound = PATH_STRETCH * norm(sub(p, positions[w]))
                + 2.0 * hits[w].distance
                + template.longest_edge(hits[w].triangle);
            candidates.insert(hits[w].triangle);
            walk(template, &hits[w], bound, |c, _| {
                candidates.extend(template.star.triangles(c as usize));
                false
            });
        }
        let mut candidates: Vec<u32> = candidates.into_iter().collect();
        candidates.sort_unstable();
        hits[v] = closest_among(template.mesh, &candidates, p, normals[v], diagonal);
        settled[v] = true;
        for &w in head.neighbours(v) {
            if !settled[w as usize] {
                queue.push_back(w);
            }
        }
    }
}

/// [`place_of`]'s rule among the `candidates` triangles of `template`.
fn closest_among(
    template: &Mesh3,
    candidates: &[u32],
    p: [f64; 3],
    n: [f64; 3],
    diagonal: f64,
) -> ClosestPoint {
    let facing = Angle::degrees(LOOKUP_ANGLE);
    let hits: Vec<(ClosestPoint, bool)> = candidates
        .iter()
        .map(|&t| {
            let corners = template.corners(t as usize);
            let point = closest_point_on_triangle(p, corners);
            let hit = ClosestPoint {
                triangle: t,
                point,
                distance: norm(sub(point, p)),
            };
            (hit, facing.admits(dot(unit_normal(corners), n)))
        })
        .collect();
    let nearest = |facing_only: bool| {
        hits.iter()
            .filter(|(_, f)| *f || !facing_only)
            .min_by(|a, b| a.0.distance.total_cmp(&b.0.distance))
            .map(|(h, _)| *h)
    };
    let closest = nearest(false).expect("a settled neighbour's triangle is a candidate");
    facing_or_closest(closest, diagonal, |within| {
        nearest(true).filter(|f| f.distance <= within)
    })
}

/// Whether the places `a` and `b` are joined by a path along the
/// template's edges of at most `bound`, from `a`'s point through the
/// corners to `b`'s point (places on triangles sharing a corner always
/// are).
fn joined(template: &Template, a: &ClosestPoint, b: &ClosestPoint, bound: f64) -> bool {
    let tris = template.mesh.triangles();
    let (ta, tb) = (tris[a.triangle as usize], tris[b.triangle as usize]);
    if ta.iter().any(|c| tb.contains(c)) {
        return true;
    }
    let positions = template.smooth;
    let b_point = template.smooth_point(b);
    // Through the corners rather than straight across: up to each
    // triangle's size longer.
    let bound = bound + template.longest_edge(a.triangle) + template.longest_edge(b.triangle);
    walk(template, a, bound, |c, d| {
        tb.contains(&c) && d + norm(sub(positions[c as usize], b_point)) <= bound
    })
}

/// Walks the template's vertices in order of their distance along its
/// edges from `from`'s point (through the corners of its triangle), as far
/// as `bound`, calling `visit(vertex, distance)` on each until it returns
/// true; returns whether one did.
fn walk(
    template: &Template,
    from: &ClosestPoint,
    bound: f64,
    mut visit: impl FnMut(u32, f64) -> bool,
) -> bool {
    let positions = template.smooth;
    let start = template.smooth_point(from);
    let mut best: HashMap<u32, f64> = HashMap::new();
    let mut heap = BinaryHeap::new();
    for &c in &template.mesh.triangles()[from.triangle as usize] {
        let d = norm(sub(positions[c as usize], start));
        if d <= bound && best.get(&c).is_none_or(|&x| d < x) {
            best.insert(c, d);
            heap.push(Reached(d, c));
        }
    }
    while let Some(Reached(d, c)) = heap.pop() {
        if best.get(&c).is_some_and(|&x| x < d) {
            continue;
        }
        if visit(c, d) {
            return true;
        }
        for &w in template.star.neighbours(c as usize) {
            let dw = d + norm(sub(positions[w as usize], positions[c as usize]));
            if dw <= bound && best.get(&w).is_none_or(|&x| dw < x) {
                best.insert(w, dw);
                heap.push(Reached(dw, w));
            }
        }
    }
    false
}

/// A vertex reached at a distance, nearest first in a [`BinaryHeap`].
struct Reached(f64, u32);

impl PartialEq for Reached {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Reached {}
impl PartialOrd for Reached {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Reached {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}
