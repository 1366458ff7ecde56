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
pub(crate) struct Partners<'a> {
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
    pub(crate) fn new(
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
    pub(crate) fn keep(&self, pairs: Vec<[u32; 2]>) -> Vec<[u32; 2]> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes::tube;
    use crate::mesh::topology::connected_components;

    /// The `pairs` (source triangle, target triangle) whose parts are partners
    /// (see the module documentation), in their order; `source_components`
    /// are the source's connected parts.
    fn between_partner_parts(
        pairs: Vec<[u32; 2]>,
        source: &Mesh3,
        source_components: &Components,
        target: &Mesh3,
    ) -> Vec<[u32; 2]> {
        let target_components = connected_components(target.num_vertices(), target.triangles());
        if source_components.count <= 1 && target_components.count <= 1 {
            return pairs;
        }
        Partners::new(
            &pairs,
            source,
            source_components,
            target,
            &target_components,
        )
        .keep(pairs)
    }

    fn parts(m: &Mesh3) -> Components {
        connected_components(m.num_vertices(), m.triangles())
    }

    /// `m` with only the triangles whose vertices all `keep` (its vertices
    /// all kept).
    fn with_triangles_of(m: &Mesh3, keep: &dyn Fn(u32) -> bool) -> Mesh3 {
        let tris: Vec<[u32; 3]> = m
            .triangles()
            .iter()
            .copied()
            .filter(|t| t.iter().all(|&v| keep(v)))
            .collect();
        Mesh3::new(m.positions().to_vec(), tris).unwrap()
    }

    /// `a` and `b` (moved by `by`) as one mesh.
    fn joined(a: &Mesh3, b: &Mesh3, by: [f64; 3]) -> Mesh3 {
        let n = a.num_vertices() as u32;
        let mut positions = a.positions().to_vec();
        positions.extend(
            b.positions()
                .iter()
                .map(|p| [p[0] + by[0], p[1] + by[1], p[2] + by[2]]),
        );
        let mut triangles = a.triangles().to_vec();
        triangles.extend(b.triangles().iter().map(|t| t.map(|v| v + n)));
        Mesh3::new(positions, triangles).unwrap()
    }

    #[test]
    fn an_eye_pairs_with_the_eye_and_a_split_body_with_the_whole() {
        let (head, eye) = (tube(2.0, 0.5, 9, 8), tube(0.2, 0.1, 3, 6));
        let mesh = joined(&head, &eye, [1.0, 0.55, 0.0]);
        let (h, e) = (head.num_triangles() as u32, eye.num_triangles() as u32);
        // Every triangle with itself, and a few of the eye with the head
        // and of the head with the eye, both ways.
        let mut pairs: Vec<[u32; 2]> = (0..h + e).map(|t| [t, t]).collect();
        pairs.extend([[h, 3], [h + 1, 4], [5, h + 2], [6, h + 3]]);
        let kept = between_partner_parts(pairs.clone(), &mesh, &parts(&mesh), &mesh);
        assert_eq!(kept, (0..h + e).map(|t| [t, t]).collect::<Vec<_>>());
        // A target in two pieces (the head cut in half along its rings) and
        // a source in one: every pair is kept.
        let near = with_triangles_of(&head, &|v| v < 4 * 8);
        let far = with_triangles_of(&head, &|v| (4 * 8..9 * 8).contains(&v));
        let split = joined(&near, &far, [0.0; 3]);
        let n = near.num_triangles() as u32;
        let pairs: Vec<[u32; 2]> = (0..split.num_triangles() as u32)
            .map(|t| [if t < n { t } else { t + 2 * 8 }, t])
            .collect();
        assert_eq!(
            between_partner_parts(pairs.clone(), &head, &parts(&head), &split),
            pairs
        );
    }

    #[test]
    fn a_source_eye_gives_nothing_to_skin_its_partner_covers() {
        // Source: a head and an eye; target: the head alone. The eye pairs
        // with two skin triangles the source's head covers too, and with one
        // it alone covers (as a source hand cut off at a seam covers the
        // target's hand): only that pair is kept.
        let (head, eye) = (tube(2.0, 0.5, 9, 8), tube(0.2, 0.1, 3, 6));
        let source = joined(&head, &eye, [1.0, 0.55, 0.0]);
        let h = head.num_triangles() as u32;
        let mut pairs: Vec<[u32; 2]> = (0..h).filter(|&t| t != 7).map(|t| [t, t]).collect();
        pairs.extend([[h, 3], [h + 1, 4], [h + 2, 7]]);
        pairs.sort_unstable();
        let kept = between_partner_parts(pairs.clone(), &source, &parts(&source), &head);
        let mut expected: Vec<[u32; 2]> = (0..h).filter(|&t| t != 7).map(|t| [t, t]).collect();
        expected.push([h + 2, 7]);
        expected.sort_unstable();
        assert_eq!(kept, expected);
    }

    #[test]
    fn a_hand_cut_off_keeps_its_pairs_with_the_body_beside_a_watch() {
        // Source: a long body in one piece and a small watch near its far
        // end. Target: the same body cut into a long piece and its end (a
        // hand), which the watch also pairs with.
        let body = tube(10.0, 0.5, 41, 8);
        let watch = tube(0.3, 0.3, 3, 8);
        let source = joined(&body, &watch, [9.5, 0.0, 0.0]);
        let nv = body.num_vertices() as u32;
        let near = with_triangles_of(&body, &|v| v < 37 * 8 || v == nv - 2);
        let far = with_triangles_of(&body, &|v| (37 * 8..41 * 8).contains(&v) || v == nv - 1);
        let target = joined(&near, &far, [0.0; 3]);
        let mut pairs: Vec<[u32; 2]> = Vec::new();
        for (k, t) in target.triangles().iter().enumerate() {
            let t = t.map(|v| v % nv);
            if let Some(s) = body.triangles().iter().position(|&b| b == t) {
                pairs.push([s as u32, k as u32]);
            }
        }
        let hand = near.num_triangles() as u32;
        let (b, w) = (body.num_triangles() as u32, watch.num_triangles() as u32);
        for i in 0..w {
            pairs.push([b + i, hand + (i % 8)]);
        }
        pairs.sort_unstable();
        let with_body =
            |pairs: &[[u32; 2]]| pairs.iter().filter(|p| p[1] >= hand && p[0] < b).count();
        let kept = between_partner_parts(pairs.clone(), &source, &parts(&source), &target);
        assert!(with_body(&pairs) > 0);
        assert_eq!(with_body(&kept), with_body(&pairs));
    }
}
