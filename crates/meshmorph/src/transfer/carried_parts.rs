//! Separate parts of a target that move rigidly with the surface around
//! them: eyes, teeth, gums, a tongue, accessories, pieces split off by
//! unwelded seams.
//!
//! A connected part of the target with few source partners (less than half
//! of its area paired) has no deformation of its own to follow, and on its
//! own it would float. It is carried instead: in each pose it takes the
//! rigid motion (Horn's best-fit rotation and translation) of its anchors,
//! the vertices of the main part (the part with the most paired area) or of
//! a part standing apart from it (a second character) nearest to its own at
//! rest: the eyelids around an eye, the lips around teeth. Not a smaller
//! part beside it: an eyebrow touching an eyeball does not turn when the eye
//! looks aside.
//!
//! A part with exactly half of its area paired (within a relative
//! `HALF_TOLERANCE`, so that rounding cannot tip it one way in some units
//! and the other way in others) counts as paired and follows its partners.
//!
//! A paired part next to the main one (the part with the most paired area)
//! takes its shape from its partners (an eye that looks aside turns), but
//! where it sits is carried by the main part: its partners give its motion
//! in the source, and the main part around it is where the target's own
//! shape put it. A camel's neck is longer than a horse's, so the camel's
//! head does not end where the horse's head goes; its eyes, placed by the
//! horse's eyes alone, would leave their sockets. The part is moved by as
//! much as the main part around it (its anchors, the main part's vertices
//! nearest to its own) stands off where its own pairs would put it
//! (`Transfer::place`). A part whose bounding box, grown by its own size,
//! does not meet the main part's (a second character in the same file) is
//! placed by its pairs alone.

#![allow(non_snake_case)]

use rstar::primitives::GeomWithData;
use rstar::RTree;

use crate::linalg::similarity::rigid_fit;
use crate::linalg::vector::{add, sub};
use crate::mesh::bvh::Aabb;
use crate::mesh::nearest_vertices::{nearest_with_ties, VertexTree};
use crate::mesh::topology::Components;

/// How many nearest vertices of the parts that bear it each vertex of a
/// carried or following part contributes to its anchors (more where several
/// are as near: `nearest_vertices.rs`).
const ANCHORS_PER_VERTEX: usize = 4;

/// How many nearest vertices are looked at for those.
const ANCHOR_SEARCH: usize = 16 * ANCHORS_PER_VERTEX;

/// How close, relative to half a part's area, its paired area counts as
/// exactly half. Far above the rounding of summing the areas (about 1e-16
/// per triangle, relative) and far below any real difference between the
/// paired and the unpaired halves, it makes the decision the same for a
/// target in any units.
const HALF_TOLERANCE: f64 = 1e-9;

/// One carried part.
#[derive(Clone, Debug)]
struct CarriedPart {
    vertices: Vec<u32>,
    anchors: Vec<u32>,
}

/// A paired part whose place follows the main part around it.
#[derive(Clone, Debug)]
pub struct FollowingPart {
    /// Its connected component.
    pub component: u32,
    /// The main part's vertices nearest to its own.
    pub anchors: Vec<u32>,
}

/// The carried parts of a target and their anchors, and the paired parts
/// that follow the main part.
#[derive(Clone, Debug, Default)]
pub struct CarriedParts {
    parts: Vec<CarriedPart>,
    following: Vec<FollowingPart>,
}

impl CarriedParts {
    /// Finds the parts to carry: those with less than half of their area in
    /// `paired` triangles (`area[t]` each), when some other part has more
    /// (the main part, with the most paired area, the lowest numbered of
    /// equals, is never carried). A paired area within `HALF_TOLERANCE`
    /// (relative) of half the part's area counts as half: that part is not
    /// carried, at any scale of the target. The other paired parts whose
    /// bounding box, grown by its own size, meets the main part's follow
    /// the main part (see the module documentation). Parts `held` (by a
    /// user's pin) are neither: the pins place them.
    pub fn new(
        positions: &[[f64; 3]],
        components: &Components,
        paired: &[bool],
        area: &[f64],
        held: &[bool],
    ) -> Self {
        let c = components.count;
        let (mut total, mut matched) = (vec![0.0; c], vec![0.0; c]);
        for (t, &part) in components.of_triangle.iter().enumerate() {
            total[part as usize] += area[t];
            if paired[t] {
                matched[part as usize] += area[t];
            }
        }
        let leader = (0..c).max_by(|&a, &b| matched[a].total_cmp(&matched[b]).then(b.cmp(&a)));
        let Some(leader) = leader.filter(|&l| matched[l] > 0.0) else {
            return Self::default();
        };
        let mut members: Vec<Vec<u32>> = vec![Vec::new(); c];
        for (v, part) in components.of_vertex.iter().enumerate() {
            if let Some(p) = part {
                members[*p as usize].push(v as u32);
            }
        }
        let is_held = |p: usize| held.get(p).copied().unwrap_or(false);
        let carried: Vec<bool> = (0..c)
            .map(|p| {
                p != leader && !is_held(p) && matched[p] < 0.5 * total[p] * (1.0 - HALF_TOLERANCE)
            })
            .collect();
        let bounds = |p: usize| Aabb::around(members[p].iter().map(|&v| positions[v as usize]));
        let main_box = bounds(leader);
        let follows: Vec<bool> = (0..c)
            .map(|p| {
                p != leader && !carried[p] && !is_held(p) && !members[p].is_empty() && {
                    let part_box = bounds(p);
                    part_box.grown(part_box.diagonal()).meets(&main_box)
                }
            })
            .collect();
        if !carried.contains(&true) && !follows.contains(&true) {
            return Self::default();
        }
        // A following part is anchored to the main part. A carried part is
        // anchored to the main part or to a part standing apart from it (a
        // second character's body), whichever is nearest: not to a smaller
        // part beside it (an eyebrow to the head, not to the eyeball it
        // touches).
        let tree_of = |keep: &dyn Fn(usize) -> bool| -> VertexTree {
            RTree::bulk_load(
                (0..c)
                    .filter(|&p| keep(p))
                    .flat_map(|p| members[p].iter())
                    .map(|&v| GeomWithData::new(positions[v as usize], v))
                    .collect(),
            )
        };
        let main_tree = tree_of(&|p| p == leader);
        let following = (0..c)
            .filter(|&p| follows[p])
            .map(|p| FollowingPart {
                component: p as u32,
                anchors: anchors(&main_tree, positions, &members[p]),
            })
            .collect();
        let parts = if carried.contains(&true) {
            let bearers = tree_of(&|p| !carried[p] && !follows[p]);
            (0..c)
                .filter(|&p| carried[p] && !members[p].is_empty())
                .map(|p| CarriedPart {
                    anchors: anchors(&bearers, positions, &members[p]),
                    vertices: members[p].clone(),
                })
                .collect()
        } else {
            Vec::new()
        };
        Self { parts, following }
    }

    /// The paired parts next to the main one, whose place follows it.
    pub fn following(&self) -> &[FollowingPart] {
        &self.following
    }

    /// Number of carried parts.
    pub fn len(&self) -> usize {
        self.parts.len()
    }

    /// Whether no part is carried.
    pub fn is_empty(&self) -> bool {
        self.parts.is_empty()
    }

    /// Moves every carried part in `out` by the rigid motion that best takes
    /// its anchors from `rest` to their positions in `out`.
    pub fn carry(&self, rest: &[[f64; 3]], out: &mut [[f64; 3]]) {
        for part in &self.parts {
            let (ca, cb, R) = rigid_fit(&part.anchors, |a| rest[a], |a| out[a]);
            for &v in &part.vertices {
                let d = sub(rest[v as usize], ca);
                let turned =
                    std::array::from_fn(|i| R[i][0] * d[0] + R[i][1] * d[1] + R[i][2] * d[2]);
                out[v as usize] = add(cb, turned);
            }
        }
    }
}

/// The vertices of `tree` nearest to each of `vertices` (sorted, each
/// once): a part's anchors.
fn anchors(tree: &VertexTree, positions: &[[f64; 3]], vertices: &[u32]) -> Vec<u32> {
    let mut anchors: Vec<u32> = vertices
        .iter()
        .flat_map(|&v| {
            nearest_with_ties(
                tree,
                positions[v as usize],
                ANCHORS_PER_VERTEX,
                ANCHOR_SEARCH,
                |_| true,
            )
        })
        .collect();
    anchors.sort_unstable();
    anchors.dedup();
    anchors
}
