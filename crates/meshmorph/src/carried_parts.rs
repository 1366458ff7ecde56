//! Separate parts of a target that move rigidly with the surface around
//! them: eyes, teeth, gums, a tongue, accessories, pieces split off by
//! unwelded seams.
//!
//! A connected part of the target with few source partners (less than half
//! of its area paired) has no deformation of its own to follow, and on its
//! own it would float. It is carried instead: in each pose it takes the
//! rigid motion (Horn's best-fit rotation and translation) of its anchors,
//! the vertices of the other parts nearest to its own at rest: the eyelids
//! around an eye, the gums or lips around teeth.
//!
//! A part with exactly half of its area paired (within a relative
//! `HALF_TOLERANCE`, so that rounding cannot tip it one way in some units
//! and the other way in others) counts as paired and follows its partners.

#![allow(non_snake_case)]

use rstar::primitives::GeomWithData;
use rstar::RTree;

use crate::geometry::{add, sub};
use crate::nearest_vertices::{nearest_with_ties, VertexTree};
use crate::similarity::rigid_fit;
use crate::topology::Components;

/// How many nearest vertices of the surrounding parts each vertex of a
/// carried part contributes to its anchors (more where several are as
/// near: `nearest_vertices.rs`).
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

/// The carried parts of a target and their anchors.
#[derive(Clone, Debug, Default)]
pub struct CarriedParts {
    parts: Vec<CarriedPart>,
}

impl CarriedParts {
    /// Finds the parts to carry: those with less than half of their area in
    /// `paired` triangles (`area[t]` each), when some other part has more
    /// (the part with the most paired area is never carried). A paired area
    /// within `HALF_TOLERANCE` (relative) of half the part's area counts
    /// as half: that part is not carried, at any scale of the target.
    pub fn new(
        positions: &[[f64; 3]],
        components: &Components,
        paired: &[bool],
        area: &[f64],
    ) -> Self {
        let c = components.count;
        let (mut total, mut matched) = (vec![0.0; c], vec![0.0; c]);
        for (t, &part) in components.of_triangle.iter().enumerate() {
            total[part as usize] += area[t];
            if paired[t] {
                matched[part as usize] += area[t];
            }
        }
        let leader = (0..c).max_by(|&a, &b| matched[a].total_cmp(&matched[b]));
        let carried: Vec<bool> = (0..c)
            .map(|p| Some(p) != leader && matched[p] < 0.5 * total[p] * (1.0 - HALF_TOLERANCE))
            .collect();
        if !carried.contains(&true) || leader.is_none_or(|l| matched[l] == 0.0) {
            return Self::default();
        }
        let mut members: Vec<Vec<u32>> = vec![Vec::new(); c];
        let mut others = Vec::new();
        for (v, part) in components.of_vertex.iter().enumerate() {
            let Some(part) = part else { continue };
            if carried[*part as usize] {
                members[*part as usize].push(v as u32);
            } else {
                others.push(GeomWithData::new(positions[v], v as u32));
            }
        }
        let tree: VertexTree = RTree::bulk_load(others);
        let parts = members
            .into_iter()
            .filter(|m| !m.is_empty())
            .map(|vertices| {
                let mut anchors: Vec<u32> = vertices
                    .iter()
                    .flat_map(|&v| {
                        nearest_with_ties(
                            &tree,
                            positions[v as usize],
                            ANCHORS_PER_VERTEX,
                            ANCHOR_SEARCH,
                            |_| true,
                        )
                    })
                    .collect();
                anchors.sort_unstable();
                anchors.dedup();
                CarriedPart { vertices, anchors }
            })
            .collect();
        Self { parts }
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
