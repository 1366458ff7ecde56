//! Which connected parts of the source and the target may pair their
//! triangles.
//!
//! The triangle matching pairs triangles by nearness alone. Where a
//! character has separate parts that sit close to another part's surface,
//! that pairs across parts that have nothing to do with each other: the
//! front of a target's eyeball with the source's eyelid skin, the target's
//! eyelid skin with the source's eyeball. Then a blink of the source moves
//! the target's eye, and a source eye that looks aside drags the target's
//! lid with it.
//!
//! So parts pair with their partners only. A part's partner is the part of
//! the other mesh that covers the most of its area (the share of its area
//! paired with that part: an eyeball is covered far more by the other
//! eyeball than by the head skin it touches, while the head covers only a
//! sliver of it). A pair of triangles is kept when either's part is the
//! other's partner. A target split into several parts (a hand cut off at a
//! seam) keeps its pairs with a source in one piece, and the other way
//! round; meshes of one part each keep every pair.
//!
//! Nearness alone also lets a small part just under the other's surface
//! win: on a target without eyes, skin whose nearest source centroid is an
//! eye just under the source's skin would turn when the eye looks aside.
//! So the matching (`match_triangles`) first finds the partners from the
//! nearest pairs, then lets each triangle whose nearest lies in another part
//! than its own part's partner look again among the partner's triangles
//! within reach (the skin finds the skin). And a target triangle paired with
//! its own part's partner takes nothing from other parts of the source.

use std::collections::{HashMap, HashSet};

use crate::mesh::topology::Components;
use crate::mesh::Mesh3;

/// Each connected part's partner: the part of the other mesh that covers the
/// most of it (see the module documentation).
pub struct Partners<'a> {
    source_parts: &'a [u32],
    target_parts: &'a [u32],
    /// For each target part, the source part covering the most of it.
    of_target: Vec<Option<u32>>,
    /// For each source part, the target part covering the most of it.
    of_source: Vec<Option<u32>>,
}

impl<'a> Partners<'a> {
    /// The partners the `pairs` (source triangle, target triangle) make,
    /// each part covering its partner by the area of its triangles in pairs
    /// with it (each triangle counted once); ties to the lower number.
    pub fn new(
        pairs: &[[u32; 2]],
        source: &Mesh3,
        source_components: &'a Components,
        target: &Mesh3,
        target_components: &'a Components,
    ) -> Self {
        let (source_parts, target_parts) = (
            &source_components.of_triangle[..],
            &target_components.of_triangle[..],
        );
        let (num_source, num_target) = (source_components.count, target_components.count);
        let (source_areas, target_areas) = (source.triangle_areas(), target.triangle_areas());
        let part_areas = |parts: &[u32], areas: &[f64], n: usize| {
            let mut total = vec![0.0; n];
            for (&p, a) in parts.iter().zip(areas) {
                total[p as usize] += a;
            }
            total
        };
        let source_total = part_areas(source_parts, &source_areas, num_source);
        let target_total = part_areas(target_parts, &target_areas, num_target);
        // The area of each part paired with the other part (each triangle
        // counted once): target side, source side.
        let mut overlap: HashMap<(u32, u32), (f64, f64)> = HashMap::new();
        let (mut seen_source, mut seen_target) = (HashSet::new(), HashSet::new());
        for &[s, t] in pairs {
            let (q, p) = (source_parts[s as usize], target_parts[t as usize]);
            let area = overlap.entry((q, p)).or_default();
            if seen_target.insert((t, q)) {
                area.0 += target_areas[t as usize];
            }
            if seen_source.insert((s, p)) {
                area.1 += source_areas[s as usize];
            }
        }
        let mut best_source: Vec<Option<(u32, f64)>> = vec![None; num_target];
        let mut best_target: Vec<Option<(u32, f64)>> = vec![None; num_source];
        let mut keys: Vec<(u32, u32)> = overlap.keys().copied().collect();
        keys.sort_unstable();
        let better = |best: &Option<(u32, f64)>, score: f64| best.is_none_or(|(_, b)| score > b);
        for (q, p) in keys {
            let (on_target, on_source) = overlap[&(q, p)];
            let covered = on_target / target_total[p as usize];
            if better(&best_source[p as usize], covered) {
                best_source[p as usize] = Some((q, covered));
            }
            let covered = on_source / source_total[q as usize];
            if better(&best_target[q as usize], covered) {
                best_target[q as usize] = Some((p, covered));
            }
        }
        Self {
            source_parts,
            target_parts,
            of_target: best_source.into_iter().map(|b| b.map(|b| b.0)).collect(),
            of_source: best_target.into_iter().map(|b| b.map(|b| b.0)).collect(),
        }
    }

    /// The part of source triangle `s`.
    pub(crate) fn source_part(&self, s: u32) -> u32 {
        self.source_parts[s as usize]
    }

    /// The part of target triangle `t`.
    pub(crate) fn target_part(&self, t: u32) -> u32 {
        self.target_parts[t as usize]
    }

    /// The partner (a target part) of source triangle `s`'s part.
    pub(crate) fn of_source_triangle(&self, s: u32) -> Option<u32> {
        self.of_source[self.source_part(s) as usize]
    }

    /// The partner (a source part) of target triangle `t`'s part.
    pub(crate) fn of_target_triangle(&self, t: u32) -> Option<u32> {
        self.of_target[self.target_part(t) as usize]
    }

    /// The `pairs` whose parts are partners (see the module documentation),
    /// in their order.
    pub fn keep(&self, pairs: Vec<[u32; 2]>) -> Vec<[u32; 2]> {
        let is_partner = |q: u32, p: u32| self.of_target[p as usize] == Some(q);
        let gives = |q: u32, p: u32| self.of_source[q as usize] == Some(p);
        // The target triangles paired with their own part's partner: those
        // take no deformation from another part of the source.
        let mut with_partner = vec![false; self.target_parts.len()];
        for &[s, t] in &pairs {
            if is_partner(self.source_part(s), self.target_part(t)) {
                with_partner[t as usize] = true;
            }
        }
        pairs
            .into_iter()
            .filter(|&[s, t]| {
                let (q, p) = (self.source_part(s), self.target_part(t));
                is_partner(q, p) || (gives(q, p) && !with_partner[t as usize])
            })
            .collect()
    }
}
