//! Connectivity: the edges of a triangle list, triangle adjacency across
//! edges, connected components.
//!
//! Everything here works on plain `#T × 3` index lists and is robust to
//! boundaries and non-manifold edges: an edge shared by three to
//! [`ALL_PAIRS_UP_TO`] triangles makes all of them neighbours of one
//! another; past that, each is the neighbour of the next in order (see
//! [`linked_pairs`]), so that every structure over neighbours stays linear
//! in the number of triangles whatever the mesh (a book of 100,000 pages on
//! one spine, one triangle repeated 100,000 times).

use rayon::slice::ParallelSliceMut;

use crate::mesh::Mesh;

/// An undirected edge `v[0] < v[1]` and the triangles that contain it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Edge {
    /// The two vertices, smaller index first.
    pub vertices: [u32; 2],
    /// The triangles containing the edge: one on a boundary, two inside a
    /// manifold surface, more at a non-manifold edge.
    pub triangles: Vec<u32>,
}

/// The most triangles on one edge that are all neighbours of one another.
///
/// Eight covers every surface met in practice (a manifold edge has two, a
/// double-sided sheet four, a few sheets meeting six or eight) and bounds
/// the neighbour pairs at `21 #T` for any mesh (`6 #T` on a manifold one).
pub const ALL_PAIRS_UP_TO: usize = 8;

/// The pairs `(a, b)` of triangles that are neighbours across one edge,
/// given the triangles on it, `on_edge` (increasing, without repeats):
/// every pair, `a` before `b`, in the order of `on_edge`, when there are at
/// most [`ALL_PAIRS_UP_TO`]; past that, each triangle and the next (a chain
/// that still connects them all).
///
/// # Performance
/// At most `max(ALL_PAIRS_UP_TO - 1, 1)` pairs per triangle on the edge.
pub fn linked_pairs(on_edge: &[u32]) -> impl Iterator<Item = (u32, u32)> + '_ {
    let all = on_edge.len() <= ALL_PAIRS_UP_TO;
    on_edge.iter().enumerate().flat_map(move |(k, &a)| {
        let rest = &on_edge[k + 1..];
        let partners = if all {
            rest
        } else {
            &rest[..rest.len().min(1)]
        };
        partners.iter().map(move |&b| (a, b))
    })
}

/// All undirected edges of `triangles`, sorted by vertex pair.
pub fn edges(triangles: &[[u32; 3]]) -> Vec<Edge> {
    let mut half: Vec<([u32; 2], u32)> = Vec::with_capacity(3 * triangles.len());
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            half.push(([a.min(b), a.max(b)], t as u32));
        }
    }
    half.sort_unstable();
    let mut out: Vec<Edge> = Vec::with_capacity(half.len() / 2 + 1);
    for (v, t) in half {
        match out.last_mut() {
            Some(e) if e.vertices == v => {
                if e.triangles.last() != Some(&t) {
                    e.triangles.push(t)
                }
            }
            _ => out.push(Edge {
                vertices: v,
                triangles: vec![t],
            }),
        }
    }
    out
}

/// Triangle adjacency in compressed form: the neighbours of triangle `t` are
/// `neighbors[offsets[t]..offsets[t + 1]]`, every triangle sharing an edge
/// with `t` (as [`linked_pairs`] links them at an edge shared by more than
/// [`ALL_PAIRS_UP_TO`]), in increasing order, without repeats.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TriangleAdjacency {
    /// `#T + 1` offsets into `neighbors`.
    pub offsets: Vec<usize>,
    /// Concatenated neighbour lists.
    pub neighbors: Vec<u32>,
}

impl TriangleAdjacency {
    /// Builds the adjacency from the edges of `triangles`.
    ///
    /// # Performance
    /// One parallel sort of `3 #T` small records, then bucketing by
    /// triangle; no allocation per edge or triangle. At most `21 #T`
    /// neighbour pairs, whatever the mesh.
    pub fn new(triangles: &[[u32; 3]]) -> Self {
        let mut half: Vec<(u64, u32)> = Vec::with_capacity(3 * triangles.len());
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                half.push((((a.min(b) as u64) << 32) | a.max(b) as u64, t as u32));
            }
        }
        // Every record is distinct (an edge and a triangle), so the order
        // is the same on any number of threads.
        half.par_sort_unstable();
        let mut pairs: Vec<(u32, u32)> = Vec::with_capacity(half.len());
        let mut on_edge: Vec<u32> = Vec::new();
        for run in half.chunk_by(|x, y| x.0 == y.0) {
            on_edge.clear();
            // A degenerate triangle may hold one edge twice.
            on_edge.extend(run.iter().map(|&(_, t)| t));
            on_edge.dedup();
            for (a, b) in linked_pairs(&on_edge) {
                pairs.push((a, b));
                pairs.push((b, a));
            }
        }
        Self::from_pairs(triangles.len(), pairs)
    }

    /// Builds the adjacency of `num_triangles` triangles from their edges.
    pub fn from_edges(num_triangles: usize, edges: &[Edge]) -> Self {
        let mut pairs = Vec::new();
        for e in edges {
            for (a, b) in linked_pairs(&e.triangles) {
                pairs.push((a, b));
                pairs.push((b, a));
            }
        }
        Self::from_pairs(num_triangles, pairs)
    }

    /// Compresses `(triangle, neighbour)` pairs ([`bucket_pairs`]).
    fn from_pairs(num_triangles: usize, pairs: Vec<(u32, u32)>) -> Self {
        let (offsets, neighbors) = bucket_pairs(num_triangles, pairs);
        Self { offsets, neighbors }
    }

    /// The neighbours of triangle `t`.
    #[inline]
    pub fn of(&self, t: usize) -> &[u32] {
        &self.neighbors[self.offsets[t]..self.offsets[t + 1]]
    }

    /// Where the neighbours of triangle `t` start in the list of all
    /// neighbour pairs (for values kept per pair).
    #[inline]
    pub fn offset(&self, t: usize) -> usize {
        self.offsets[t]
    }

    /// Components of triangles connected across edges (a bow-tie of two
    /// fans meeting at one vertex is two of them): the label of each
    /// triangle, numbered in order of their first triangle, and the count.
    pub fn edge_components(&self) -> (Vec<u32>, usize) {
        self.edge_components_where(|_, _| true)
    }

    /// [`TriangleAdjacency::edge_components`] crossing only the edges
    /// between neighbours `t` and `u` for which `crosses(t, u)` holds.
    pub fn edge_components_where(
        &self,
        crosses: impl Fn(usize, usize) -> bool,
    ) -> (Vec<u32>, usize) {
        let mut label = vec![u32::MAX; self.len()];
        let mut count = 0u32;
        let mut stack = Vec::new();
        for start in 0..self.len() {
            if label[start] != u32::MAX {
                continue;
            }
            label[start] = count;
            stack.push(start);
            while let Some(t) = stack.pop() {
                for &u in self.of(t) {
                    let u = u as usize;
                    if label[u] == u32::MAX && crosses(t, u) {
                        label[u] = count;
                        stack.push(u);
                    }
                }
            }
            count += 1;
        }
        (label, count as usize)
    }

    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// True when there are no triangles.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Connected components of a mesh, where two triangles are connected when
/// they share a vertex.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Components {
    /// Component of each vertex; `None` for a vertex no triangle uses.
    pub of_vertex: Vec<Option<u32>>,
    /// Component of each triangle.
    pub of_triangle: Vec<u32>,
    /// Number of components.
    pub count: usize,
}

/// Counts that describe a surface ([`Mesh::surface_counts`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct SurfaceCounts {
    /// Edges of one triangle only: the surface's boundary (0 when closed).
    pub boundary_edges: usize,
    /// Edges of more than two triangles: where the surface is not a
    /// manifold (fins, faces given twice, surfaces glued along an edge).
    pub crowded_edges: usize,
    /// Connected parts (sets of triangles joined through shared vertices).
    pub parts: usize,
}

impl<const D: usize> Mesh<D> {
    /// Its boundary edges, non-manifold edges and connected parts.
    pub fn surface_counts(&self) -> SurfaceCounts {
        let edges = edges(self.triangles());
        SurfaceCounts {
            boundary_edges: edges.iter().filter(|e| e.triangles.len() == 1).count(),
            crowded_edges: edges.iter().filter(|e| e.triangles.len() > 2).count(),
            parts: connected_components(self.num_vertices(), self.triangles()).count,
        }
    }
}

/// Where the boundary of a triangle list is not a set of simple loops.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoundaryBreak {
    /// Two boundary edges leave this vertex: the boundary meets itself there.
    PassesTwice(u32),
    /// No boundary edge leaves this vertex though one arrives: neighbouring
    /// triangles list their shared edge the same way round.
    Stops(u32),
}

/// The boundary loops of `triangles`: the edges that no triangle lists the
/// other way round, each loop as its vertices in the order the triangles
/// run, loops in the order of their first edge in `triangles`. Empty for a
/// closed surface.
///
/// # Errors
/// [`BoundaryBreak`] where the boundary edges do not make simple loops.
pub fn boundary_loops(triangles: &[[u32; 3]]) -> Result<Vec<Vec<u32>>, BoundaryBreak> {
    use std::collections::{HashMap, HashSet};
    let directed: HashSet<(u32, u32)> = triangles
        .iter()
        .flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3])))
        .collect();
    let mut next: HashMap<u32, u32> = HashMap::new();
    let mut order: Vec<u32> = Vec::new();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if directed.contains(&(b, a)) {
                continue;
            }
            if next.insert(a, b).is_some() {
                return Err(BoundaryBreak::PassesTwice(a));
            }
            order.push(a);
        }
    }
    let mut seen = HashSet::new();
    let mut loops = Vec::new();
    for &start in &order {
        if seen.contains(&start) {
            continue;
        }
        let mut vertices = Vec::new();
        let mut v = start;
        while seen.insert(v) {
            vertices.push(v);
            v = *next.get(&v).ok_or(BoundaryBreak::Stops(v))?;
        }
        loops.push(vertices);
    }
    Ok(loops)
}

/// Compresses `(item, other)` pairs over `count` items into offsets
/// (`count + 1`) and the concatenated lists: each item's others in
/// increasing order, repeats dropped. The pairs are bucketed by item (each
/// bucket holds a few), not sorted as a whole.
fn bucket_pairs(count: usize, pairs: Vec<(u32, u32)>) -> (Vec<usize>, Vec<u32>) {
    let mut start = vec![0usize; count + 1];
    for &(a, _) in &pairs {
        start[a as usize + 1] += 1;
    }
    for t in 0..count {
        start[t + 1] += start[t];
    }
    let mut bucketed = vec![0u32; pairs.len()];
    let mut fill = start.clone();
    for &(a, b) in &pairs {
        bucketed[fill[a as usize]] = b;
        fill[a as usize] += 1;
    }
    drop(pairs);
    let mut offsets = Vec::with_capacity(count + 1);
    offsets.push(0);
    let mut lists = Vec::with_capacity(bucketed.len());
    for t in 0..count {
        let bucket = &mut bucketed[start[t]..start[t + 1]];
        bucket.sort_unstable();
        for (k, &b) in bucket.iter().enumerate() {
            if k == 0 || bucket[k - 1] != b {
                lists.push(b);
            }
        }
        offsets.push(lists.len());
    }
    (offsets, lists)
}

/// What lies around each vertex of a mesh: the vertices it shares an edge
/// with, and the triangles that use it.
#[derive(Clone, Debug)]
pub struct VertexStar {
    neighbour_offsets: Vec<usize>,
    neighbours: Vec<u32>,
    triangle_offsets: Vec<usize>,
    triangles: Vec<u32>,
}

impl VertexStar {
    /// The stars of the `num_vertices` vertices of `triangles`.
    pub fn new(num_vertices: usize, triangles: &[[u32; 3]]) -> Self {
        let mut edges = Vec::with_capacity(6 * triangles.len());
        let mut uses = Vec::with_capacity(3 * triangles.len());
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                if a != b {
                    edges.push((a, b));
                    edges.push((b, a));
                }
                uses.push((a, t as u32));
            }
        }
        let (neighbour_offsets, neighbours) = bucket_pairs(num_vertices, edges);
        let (triangle_offsets, triangles) = bucket_pairs(num_vertices, uses);
        Self {
            neighbour_offsets,
            neighbours,
            triangle_offsets,
            triangles,
        }
    }

    /// The vertices sharing an edge with vertex `v`, in increasing order.
    #[inline]
    pub fn neighbours(&self, v: usize) -> &[u32] {
        &self.neighbours[self.neighbour_offsets[v]..self.neighbour_offsets[v + 1]]
    }

    /// The triangles using vertex `v`, in increasing order.
    #[inline]
    pub fn triangles(&self, v: usize) -> &[u32] {
        &self.triangles[self.triangle_offsets[v]..self.triangle_offsets[v + 1]]
    }
}

/// Connected components of `triangles` over `num_vertices` vertices,
/// numbered in order of their first triangle.
pub fn connected_components(num_vertices: usize, triangles: &[[u32; 3]]) -> Components {
    let mut parent: Vec<u32> = (0..num_vertices as u32).collect();
    fn find(parent: &mut [u32], mut x: u32) -> u32 {
        while parent[x as usize] != x {
            let p = parent[x as usize];
            parent[x as usize] = parent[p as usize];
            x = p;
        }
        x
    }
    for tri in triangles {
        let r0 = find(&mut parent, tri[0]);
        for &v in &tri[1..] {
            let r = find(&mut parent, v);
            if r != r0 {
                // Union by index keeps the loop simple; path halving keeps it fast.
                let (lo, hi) = (r.min(r0), r.max(r0));
                parent[hi as usize] = lo;
            }
        }
    }
    let mut label: Vec<Option<u32>> = vec![None; num_vertices];
    let mut of_triangle = Vec::with_capacity(triangles.len());
    let mut count = 0u32;
    for tri in triangles {
        let r = find(&mut parent, tri[0]) as usize;
        let c = *label[r].get_or_insert_with(|| {
            count += 1;
            count - 1
        });
        of_triangle.push(c);
    }
    let mut of_vertex = vec![None; num_vertices];
    for (tri, &c) in triangles.iter().zip(&of_triangle) {
        for &v in tri {
            of_vertex[v as usize] = Some(c);
        }
    }
    Components {
        of_vertex,
        of_triangle,
        count: count as usize,
    }
}
