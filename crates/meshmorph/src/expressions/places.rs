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
pub(crate) struct Place {
    pub triangle: u32,
    pub weights: [f64; 3],
}

/// What the lookups need of the fitted template.
struct Template<'a> {
    /// The template laid onto the head, where places are looked up.
    mesh: &'a Mesh3,
    index: SurfaceIndex,
    /// The template before it was laid onto the head, where paths between
    /// places are measured: laying it on can crumple it where the head
    /// differs (a hairline, a crease), the paths across it with it.
    smooth: &'a [[f64; 3]],
    star: VertexStar,
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
pub(crate) struct Places {
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
pub(crate) fn find_places(deformed: &Mesh3, smooth: &[[f64; 3]], surface: &Mesh3) -> Places {
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
pub(crate) fn place_of(
    index: &SurfaceIndex,
    p: [f64; 3],
    n: [f64; 3],
    diagonal: f64,
) -> ClosestPoint {
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
fn cut_edges(
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
fn islands(head: &VertexStar, n: usize, cut: &HashSet<(u32, u32)>) -> HashSet<u32> {
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
fn retake_islands(
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed mouth: an upper lip's underside facing down at y = 0, a
    /// lower lip's top facing up a thousandth below it, both ending at
    /// x = 1, and past that the cheek, facing forward, 0.05 in front.
    fn lips() -> SurfaceIndex {
        let lip = |y: f64| [[-1.0, y, -1.0], [1.0, y, -1.0], [1.0, y, 3.0]];
        let [a, b, c] = lip(-0.001);
        let cheek = [[1.05, -1.0, 0.05], [2.05, -1.0, 0.05], [1.05, 1.0, 0.05]];
        let corners = [lip(0.0), [a, c, b], cheek];
        let positions: Vec<[f64; 3]> = corners.iter().flatten().copied().collect();
        SurfaceIndex::new(&positions, &[[0, 1, 2], [3, 4, 5], [6, 7, 8]])
    }

    #[test]
    fn a_vertex_takes_the_lip_facing_its_way_but_the_closest_point_at_a_fold() {
        let index = lips();
        let diagonal = 4.0;
        // Nearer the other lip by a hair: the lip facing its way.
        let upper = place_of(&index, [0.9, -0.0006, 0.0], [0.0, -1.0, 0.0], diagonal);
        assert_eq!(upper.triangle, 0);
        let lower = place_of(&index, [0.9, -0.0004, 0.0], [0.0, 1.0, 0.0], diagonal);
        assert_eq!(lower.triangle, 1);
        // At the lips' corner the normal points across the fold (here
        // forward): the cheek faces that way but lies 0.11 away, against
        // 0.0004 for the upper lip.
        let fold = place_of(&index, [0.95, -0.0004, 0.0], [0.0, 0.0, 1.0], diagonal);
        assert_eq!(fold.triangle, 0);
    }

    /// A grid of `nx × nz` vertices, `at(i, j)` each, its triangles
    /// turned so that their normals point along `+y` where the grid is
    /// flat.
    fn grid(nx: usize, nz: usize, at: impl Fn(usize, usize) -> [f64; 3]) -> Mesh3 {
        let positions = (0..nx)
            .flat_map(|i| (0..nz).map(move |j| (i, j)))
            .map(|(i, j)| at(i, j))
            .collect();
        let v = |i: usize, j: usize| (i * nz + j) as u32;
        let triangles = (0..nx - 1)
            .flat_map(|i| (0..nz - 1).map(move |j| (i, j)))
            .flat_map(|(i, j)| {
                [
                    [v(i, j), v(i, j + 1), v(i + 1, j)],
                    [v(i + 1, j), v(i, j + 1), v(i + 1, j + 1)],
                ]
            })
            .collect();
        Mesh3::new(positions, triangles).unwrap()
    }

    /// Two lips 0.1 apart, joined at their corner `x = 1` by a half
    /// circle: one sheet folded, each lip's surface facing the other.
    fn folded_lips() -> Mesh3 {
        let gap = 0.1;
        let (lip, around) = (2.0, std::f64::consts::PI * gap / 2.0);
        let length = 2.0 * lip + around;
        let steps = 60;
        grid(steps + 1, 11, |i, j| {
            let s = length * i as f64 / steps as f64;
            let z = -0.5 + 0.1 * j as f64;
            if s <= lip {
                [-1.0 + s, 0.0, z]
            } else if s <= lip + around {
                let a = (s - lip) / (gap / 2.0);
                [1.0 + gap / 2.0 * a.sin(), gap / 2.0 * (1.0 - a.cos()), z]
            } else {
                [1.0 - (s - lip - around), gap, z]
            }
        })
    }

    #[test]
    fn a_vertex_that_found_the_other_lip_takes_its_place_from_around_it() {
        let lips = folded_lips();
        let template = Template {
            mesh: &lips,
            index: SurfaceIndex::new(lips.positions(), lips.triangles()),
            smooth: lips.positions(),
            star: VertexStar::new(lips.num_vertices(), lips.triangles()),
        };
        // The lower lip of a head, a hair above the template's, facing up.
        let head = grid(21, 11, |i, j| {
            [-1.0 + 0.09 * i as f64, 0.005, -0.5 + 0.1 * j as f64]
        });
        let normals = vertex_normals(head.positions(), head.triangles());
        let diagonal = head.bounding_box_diagonal();
        let lower = |hit: &ClosestPoint| hit.point[1] < 0.05;
        let mut hits: Vec<ClosestPoint> = head
            .positions()
            .iter()
            .zip(&normals)
            .map(|(&p, &n)| place_of(&template.index, p, n, diagonal))
            .collect();
        assert!(hits.iter().all(lower));
        let star = VertexStar::new(head.num_vertices(), head.triangles());
        assert!(cut_edges(&template, &star, head.positions(), &hits).is_empty());

        // One vertex in the middle finds the upper lip, 0.095 away in
        // space, 2 along the template around the corner.
        let wrong = 10 * 11 + 5;
        let above = [hits[wrong].point[0], 0.2, hits[wrong].point[2]];
        hits[wrong] = template.index.closest(above).unwrap();
        assert!(!lower(&hits[wrong]));
        let cut = cut_edges(&template, &star, head.positions(), &hits);
        assert_eq!(cut.len(), 6, "{cut:?}");
        let found = islands(&star, head.num_vertices(), &cut);
        assert_eq!(found, HashSet::from([wrong as u32]));
        retake_islands(
            &template,
            &star,
            head.positions(),
            &normals,
            diagonal,
            &found,
            &mut hits,
        );
        assert!(lower(&hits[wrong]), "{:?}", hits[wrong]);
        let p = head.positions()[wrong];
        assert!(norm(sub(hits[wrong].point, [p[0], 0.0, p[2]])) < 1e-9);
    }

    #[test]
    fn a_mesh_onto_itself_has_no_cut_edges_and_each_vertex_its_own_place() {
        let lips = folded_lips();
        let found = find_places(&lips, lips.positions(), &lips);
        assert!(found.cut.is_empty());
        for (v, place) in found.places.iter().enumerate() {
            let tri = lips.triangles()[place.triangle as usize];
            let k = tri.iter().position(|&c| c as usize == v).unwrap();
            assert!((place.weights[k] - 1.0).abs() < 1e-9, "{v}: {place:?}");
        }
    }
}
