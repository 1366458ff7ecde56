//! Vertices that sit at the same place, welded for the solvers.
//!
//! Many files split a surface's vertices where its texture coordinates or
//! normals change: Blender's PLY export at every UV seam, an Edge Split
//! modifier at sharp edges, most game engines' and glTF exporters' meshes.
//! Each copy then belongs to different triangles, the surface falls apart
//! into pieces that only touch, and a gradient-domain solve moves each
//! piece on its own: in-between frames and transferred poses crack open
//! along the seams. [`Seams`] finds the copies (vertices at exactly the same
//! position in every mesh given) so that the solvers see one vertex
//! ([`Seams::weld`]) and every copy takes its position again in the output
//! ([`Seams::unweld`]). Files keep their own vertices: only the solve works
//! on the welded mesh.

use rayon::prelude::*;

use std::collections::hash_map::Entry;
use std::collections::HashMap;

use crate::mesh::{used_vertices, Mesh};

/// Which vertices of a mesh are copies of one another (see the module
/// documentation).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Seams {
    /// The welded vertex of each vertex.
    welded_of: Vec<u32>,
    /// The first vertex of each welded vertex.
    first_of: Vec<u32>,
    /// The vertices of every welded vertex with more than one, each list
    /// in increasing order.
    groups: Vec<Vec<u32>>,
}

impl Seams {
    /// The copies among the vertices of `meshes` (all with the same vertex
    /// count): vertices at exactly the same position in every mesh. Copies
    /// are never welded when two of them are corners of one triangle (the
    /// triangle would lose a corner). With no mesh, or no copies, every
    /// vertex stays its own ([`Seams::is_empty`]).
    ///
    /// # Panics
    /// If the meshes have different vertex counts.
    pub fn find<const D: usize>(meshes: &[&Mesh<D>]) -> Self {
        let Some(first) = meshes.first() else {
            return Self::none(0);
        };
        let n = first.num_vertices();
        assert!(
            meshes.iter().all(|m| m.num_vertices() == n),
            "meshes with different vertex counts"
        );
        // Candidates: equal positions in the first mesh (found by sorting
        // the positions' bits, +0 and −0 alike), then split by the others.
        let key = |v: u32| -> [u64; D] {
            first.positions()[v as usize].map(|x| if x == 0.0 { 0 } else { x.to_bits() })
        };
        // Only vertices a triangle uses: others take no part in a solve.
        let used = used_vertices(n, first.triangles());
        let mut order: Vec<u32> = (0..n as u32).filter(|&v| used[v as usize]).collect();
        order.par_sort_unstable_by_key(|&v| (key(v), v));
        let mut groups: Vec<Vec<u32>> = Vec::new();
        for run in order.chunk_by(|&a, &b| key(a) == key(b)) {
            if run.len() > 1 {
                split_by_later_meshes(run, &meshes[1..], &mut groups);
            }
        }
        groups.retain(|g| g.len() > 1);
        let mut welded_of = first_copies(n, &groups);
        // Copies along a seam have neighbours that are one vertex or copies
        // of one vertex too; parts that only touch at a point (two cubes
        // corner to corner, a tooth on the gum) do not, and stay apart.
        // Welding must not make an edge that more than two triangles share
        // (the inner and outer sides of a mouth ripped shut, the front and
        // back faces of a double-sided sheet): such copies stay apart, and
        // then so may copies whose neighbours were those.
        loop {
            let count: usize = groups.iter().map(Vec::len).sum();
            groups = keep_manifold(
                along_seams(groups, &welded_of, first.triangles()),
                n,
                first.triangles(),
            );
            welded_of = first_copies(n, &groups);
            // Each pass only parts copies: it ends.
            if groups.iter().map(Vec::len).sum::<usize>() == count {
                break;
            }
        }
        // A triangle with two copies among its corners keeps them apart.
        let mut parted = false;
        for t in first.triangles() {
            let [a, b, c] = t.map(|v| welded_of[v as usize]);
            if a == b || b == c || a == c {
                for &v in t {
                    welded_of[v as usize] = v;
                }
                parted = true;
            }
        }
        if parted {
            groups = regroup(&welded_of);
        }
        // Welded vertices numbered in the order of their first vertex.
        let mut index = vec![u32::MAX; n];
        let mut first_of = Vec::with_capacity(n);
        for v in 0..n {
            let root = welded_of[v] as usize;
            if index[root] == u32::MAX {
                index[root] = first_of.len() as u32;
                first_of.push(v as u32);
            }
            welded_of[v] = index[root];
        }
        Self {
            welded_of,
            first_of,
            groups,
        }
    }

    /// Every vertex of a mesh of `n` vertices its own: nothing welded.
    pub fn none(n: usize) -> Self {
        Self {
            welded_of: (0..n as u32).collect(),
            first_of: (0..n as u32).collect(),
            groups: Vec::new(),
        }
    }

    /// Whether no two vertices are welded.
    pub fn is_empty(&self) -> bool {
        self.groups.is_empty()
    }

    /// The number of vertices welded into another (the vertex count of the
    /// mesh minus that of the welded mesh).
    pub fn num_welded(&self) -> usize {
        self.welded_of.len() - self.first_of.len()
    }

    /// The welded vertex of vertex `v` (a marker's or a pin's vertex in the
    /// file, for the solvers).
    ///
    /// # Panics
    /// If `v` is out of range.
    pub fn welded(&self, v: u32) -> u32 {
        self.welded_of[v as usize]
    }

    /// `mesh` with its copies welded: the first copy's position, triangles
    /// over the welded vertices (in the order of their first vertex).
    ///
    /// # Panics
    /// If `mesh` has another vertex count than the meshes the seams were
    /// found in.
    pub fn weld<const D: usize>(&self, mesh: &Mesh<D>) -> Mesh<D> {
        assert_eq!(
            mesh.num_vertices(),
            self.welded_of.len(),
            "mesh of another vertex count"
        );
        if self.is_empty() {
            return mesh.clone();
        }
        let positions = self
            .first_of
            .iter()
            .map(|&v| mesh.positions()[v as usize])
            .collect();
        let triangles = mesh
            .triangles()
            .iter()
            .map(|t| t.map(|v| self.welded_of[v as usize]))
            .collect();
        Mesh::new(positions, triangles)
            .expect("welding keeps positions finite and never collapses a triangle")
    }

    /// Positions of the welded vertices from positions of every vertex:
    /// each welded vertex at the mean of its copies (which coincide in the
    /// meshes the seams were found in).
    ///
    /// # Panics
    /// If `positions` has another length than the meshes' vertex count.
    pub fn weld_positions<const D: usize>(&self, positions: &[[f64; D]]) -> Vec<[f64; D]> {
        assert_eq!(positions.len(), self.welded_of.len(), "wrong vertex count");
        let mut welded: Vec<[f64; D]> = self
            .first_of
            .iter()
            .map(|&v| positions[v as usize])
            .collect();
        for g in &self.groups {
            let mut mean = [0.0; D];
            for &v in g {
                for i in 0..D {
                    mean[i] += positions[v as usize][i];
                }
            }
            welded[self.welded_of[g[0] as usize] as usize] = mean.map(|x| x / g.len() as f64);
        }
        welded
    }

    /// How many welded vertices' copies are apart in `positions` (a pose
    /// that moves copies apart: [`Seams::weld_positions`] puts them at their
    /// mean).
    pub fn num_apart<const D: usize>(&self, positions: &[[f64; D]]) -> usize {
        self.groups
            .iter()
            .filter(|g| {
                g[1..]
                    .iter()
                    .any(|&v| positions[v as usize] != positions[g[0] as usize])
            })
            .count()
    }

    /// Positions of every vertex from the welded vertices' positions: each
    /// copy where its welded vertex is.
    ///
    /// # Panics
    /// If `welded` has another length than the welded vertex count.
    pub fn unweld<const D: usize>(&self, welded: &[[f64; D]]) -> Vec<[f64; D]> {
        assert_eq!(
            welded.len(),
            self.first_of.len(),
            "wrong welded vertex count"
        );
        self.welded_of.iter().map(|&w| welded[w as usize]).collect()
    }
}

/// Splits `run` (vertices at one position in the first mesh) into the
/// groups whose positions also agree in every one of `later` meshes.
fn split_by_later_meshes<const D: usize>(
    run: &[u32],
    later: &[&Mesh<D>],
    groups: &mut Vec<Vec<u32>>,
) {
    let bits = |m: &Mesh<D>, v: u32| {
        m.positions()[v as usize].map(|x| if x == 0.0 { 0 } else { x.to_bits() })
    };
    let order = |a: &u32, b: &u32| {
        later
            .iter()
            .map(|m| bits(m, *a).cmp(&bits(m, *b)))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
            .then(a.cmp(b))
    };
    let mut sorted = run.to_vec();
    sorted.sort_unstable_by(order);
    for same in sorted.chunk_by(|a, b| later.iter().all(|m| bits(m, *a) == bits(m, *b))) {
        groups.push(same.to_vec());
    }
}

/// Splits each group of coincident vertices into the copies that a seam
/// joins: two copies belong together when a neighbour of one and a neighbour
/// of the other are the same vertex or coincide (`root`: each vertex's first
/// coincident vertex). Groups of one are dropped.
fn along_seams(groups: Vec<Vec<u32>>, root: &[u32], triangles: &[[u32; 3]]) -> Vec<Vec<u32>> {
    if groups.is_empty() {
        return groups;
    }
    // The neighbours' roots of every vertex in a group, sorted.
    let mut slot = vec![u32::MAX; root.len()];
    let mut count = 0;
    for g in &groups {
        for &v in g {
            slot[v as usize] = count;
            count += 1;
        }
    }
    let mut near: Vec<Vec<u32>> = vec![Vec::new(); count as usize];
    for t in triangles {
        for k in 0..3 {
            let s = slot[t[k] as usize];
            if s != u32::MAX {
                let list = &mut near[s as usize];
                list.push(root[t[(k + 1) % 3] as usize]);
                list.push(root[t[(k + 2) % 3] as usize]);
            }
        }
    }
    for list in &mut near {
        list.sort_unstable();
        list.dedup();
    }
    let mut out = Vec::new();
    for g in groups {
        // Connected copies, by a small union-find over the group: each
        // neighbour's root joins the copies that have it.
        let mut parent: Vec<usize> = (0..g.len()).collect();
        fn find(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        let mut first_with: HashMap<u32, usize> = HashMap::new();
        for (a, &v) in g.iter().enumerate() {
            for &r in &near[slot[v as usize] as usize] {
                match first_with.entry(r) {
                    Entry::Occupied(e) => {
                        let (ra, rb) = (find(&mut parent, a), find(&mut parent, *e.get()));
                        parent[ra.max(rb)] = ra.min(rb);
                    }
                    Entry::Vacant(e) => {
                        e.insert(a);
                    }
                }
            }
        }
        let mut by_root: std::collections::BTreeMap<usize, Vec<u32>> = Default::default();
        for i in 0..g.len() {
            by_root.entry(find(&mut parent, i)).or_default().push(g[i]);
        }
        out.extend(by_root.into_values().filter(|c| c.len() > 1));
    }
    out
}

/// Drops the groups whose welding would give an edge more than two
/// triangles share (where it does not already).
fn keep_manifold(groups: Vec<Vec<u32>>, n: usize, triangles: &[[u32; 3]]) -> Vec<Vec<u32>> {
    if groups.is_empty() {
        return groups;
    }
    let root = first_copies(n, &groups);
    let mut group_of = vec![u32::MAX; n];
    for (k, g) in groups.iter().enumerate() {
        for &v in g {
            group_of[v as usize] = k as u32;
        }
    }
    // Triangles per edge, welded and as they are, for edges at a copy.
    let mut welded: HashMap<(u32, u32), u32> = HashMap::new();
    let mut plain: HashMap<(u32, u32), u32> = HashMap::new();
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    for t in triangles {
        if t.iter().all(|&v| group_of[v as usize] == u32::MAX) {
            continue;
        }
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *welded
                .entry(key(root[a as usize], root[b as usize]))
                .or_default() += 1;
            *plain.entry(key(a, b)).or_default() += 1;
        }
    }
    let mut drop = vec![false; groups.len()];
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let (ga, gb) = (group_of[a as usize], group_of[b as usize]);
            if ga == u32::MAX && gb == u32::MAX {
                continue;
            }
            let now = welded[&key(root[a as usize], root[b as usize])];
            if now > 2 && now > plain[&key(a, b)] {
                for g in [ga, gb] {
                    if g != u32::MAX {
                        drop[g as usize] = true;
                    }
                }
            }
        }
    }
    groups
        .into_iter()
        .zip(drop)
        .filter(|(_, d)| !d)
        .map(|(g, _)| g)
        .collect()
}

/// Each vertex's first copy (itself when it has none) for `groups`, each
/// listed in increasing order.
fn first_copies(n: usize, groups: &[Vec<u32>]) -> Vec<u32> {
    let mut first: Vec<u32> = (0..n as u32).collect();
    for g in groups {
        for &v in &g[1..] {
            first[v as usize] = g[0];
        }
    }
    first
}

/// The groups of more than one vertex of a map to root vertices.
fn regroup(welded_of: &[u32]) -> Vec<Vec<u32>> {
    let mut by_root: std::collections::BTreeMap<u32, Vec<u32>> = Default::default();
    for (v, &r) in welded_of.iter().enumerate() {
        if r as usize != v {
            by_root.entry(r).or_insert_with(|| vec![r]).push(v as u32);
        }
    }
    by_root
        .into_values()
        .map(|mut g| {
            g.sort_unstable();
            g
        })
        .collect()
}
