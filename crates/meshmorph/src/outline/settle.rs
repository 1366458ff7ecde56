//! The compatible meshes' map from one drawing to another made as rigid
//! as it can be: each triangle's map weighed by how far it is from a
//! rigid motion (the foldover-free energy with its shape and area terms
//! weighed equally, `½ (σ1 + 1/σ1)(σ2 + 1/σ2)`, least for a rigid
//! motion and infinite for a flat triangle), and lowered by moving the
//! inside points and **sliding the boundary points along the outline**.
//! Beside it, with the same weight, the moving mesh's own shapes (each
//! triangle's distortion from an equilateral one, as `mapped::relax`
//! evens them out): both terms are 2 at their best, and without the
//! second, points sliding together along an outline make slivers that
//! the rigidity alone does not mind (on the benchmark's thin arm the
//! smallest angle fell from 15.7° to 2°; with it, 14.3°).
//!
//! A drawing's own outline points and the anchors stay where they are;
//! every other boundary point of a drawing (one that another drawing's
//! matching put there) lies on a straight edge between two fixed points
//! of that drawing, and may slide along it: the outline stays exactly
//! what it is, only which of its points matches which moves. That is
//! where a matching by arc length is wrong: a straight edge whose
//! counterpart bends at an elbow has no feature to align with the elbow,
//! and sliding puts it where the arm on either side stays rigid.
//!
//! Every step keeps every triangle positive (a step that would turn one
//! over is refused), so valid meshes stay valid.
//!
//! **The rigid parts** ([`super::OutlineOptions::rigid_parts`], on for
//! pictures). The settle's energy grows without bound as a triangle
//! flattens, so where the map must squeeze (an arm bent by 150°, whose
//! forearm hides part of the upper arm) it shares the squeeze out along
//! the whole arm, and a picture carried by the map shows its texture
//! stretched everywhere. A second pass, from where the settle ends,
//! lowers instead each triangle's robust distance from a rotation
//! (`√(knee² + |J − R|²)`, [`Energy::rigid`]): like the square below the
//! knee, like the distance above it, so that the map gains most by
//! keeping most triangles rigid and laying the squeeze on a few at the
//! fold. The moving mesh's own shapes keep a tenth of their weight, so
//! that a squeezed triangle does not go flat. On the demo's arm sprite
//! the map from A to B then keeps 54 % of the texture within 10 % of
//! rigid (33 % after the settle alone) with seven anchors, 52 % (8 %)
//! with five.
//!
//! The mesh is graded (small triangles along a finely traced outline,
//! large ones inside), and the shape term of a small triangle is stiffer
//! than a large one's by the square of their sizes: plain L-BFGS crawls.
//! Each unknown's step is scaled by the inverse of the energy's stiffness
//! along it at the start (a diagonal preconditioner), and the settle
//! converges in about 50 steps where 300 plain ones did not (the demo's
//! arm: the map from A to B stretches 1.86 on average after 50, 100 or
//! 300 preconditioned steps; 1.98 after 300 plain ones).

use super::energy::Energy;
use super::lbfgs::{gather, lbfgs_scaled, place, unknowns};
use super::mapped::area_from_boundary;

/// A boundary point of one drawing that may slide: vertex `vertex` on
/// the segment from `from` to `to` (the fixed points on either side of
/// it along its loop).
#[derive(Clone, Copy, Debug)]
pub struct Slide {
    pub vertex: u32,
    pub from: [f64; 2],
    pub to: [f64; 2],
}

impl Slide {
    /// From `from` to `to`.
    fn segment(&self) -> [f64; 2] {
        [self.to[0] - self.from[0], self.to[1] - self.from[1]]
    }

    /// The point a fraction `f` of the way along the segment.
    fn at(&self, f: f64) -> [f64; 2] {
        let d = self.segment();
        [self.from[0] + f * d[0], self.from[1] + f * d[1]]
    }

    /// The fraction of the way along the segment of `p`'s projection onto
    /// it (0 for a segment of no length).
    fn fraction_of(&self, p: [f64; 2]) -> f64 {
        let d = self.segment();
        let length2 = d[0] * d[0] + d[1] * d[1];
        if length2 > 0.0 {
            ((p[0] - self.from[0]) * d[0] + (p[1] - self.from[1]) * d[1]) / length2
        } else {
            0.0
        }
    }
}

/// The boundary points of one drawing (`points`: its boundary vertices,
/// loops one after the other from `loop_start`) that may slide: those
/// not `fixed`, each between the fixed points before and after it on its
/// loop. A loop with fewer than two fixed points slides nowhere.
pub fn slides(points: &[[f64; 2]], loop_start: &[usize], fixed: &[bool]) -> Vec<Slide> {
    let mut out = Vec::new();
    for w in loop_start.windows(2) {
        let (start, len) = (w[0], w[1] - w[0]);
        let Some(first_fixed) = (0..len).find(|&k| fixed[start + k]) else {
            continue;
        };
        // Walk the loop once from a fixed point, each run of free points
        // between two fixed ones.
        let mut last = first_fixed;
        let mut run: Vec<usize> = Vec::new();
        for step in 1..=len {
            let k = (first_fixed + step) % len;
            if fixed[start + k] {
                // (With one fixed point the run has no segment to slide on.)
                for &v in run.iter().filter(|_| k != last) {
                    out.push(Slide {
                        vertex: (start + v) as u32,
                        from: points[start + last],
                        to: points[start + k],
                    });
                }
                run.clear();
                last = k;
            } else {
                run.push(k);
            }
        }
    }
    out
}

/// The knee of the rigid parts' robust distance from a rotation
/// ([`Energy::rigid`]): a triangle whose map is within about 5 % of a
/// rotation counts as rigid, like the distance's square; beyond it, like
/// the distance.
const RIGID_KNEE: f64 = 0.05;

/// The weight of the moving mesh's own shapes beside the rigid parts'
/// term, against the settle's equal weight: enough to keep a squeezed
/// triangle from going flat, not so much that it shares the squeeze out
/// again (on the demo's arm sprite, 0.03 to 0.3 keep the same share of
/// the texture rigid; 1 keeps less of it with five anchors).
const RIGID_SHAPE_WEIGHT: f64 = 0.1;

/// Lowers the map's distortion from `reference` to `moving` (the same
/// triangles): the vertices from `free_from` on move freely, the
/// `slides` along their segments, the rest stay. At most `iterations`
/// L-BFGS steps; then, with `rigid_parts`, as many again on the robust
/// distance from rigid motions ([`Energy::rigid`]), which keeps most
/// triangles rigid and lays what must give on a few. Nothing moves when
/// a triangle is not positive in both.
pub fn settle(
    reference: &[[f64; 2]],
    triangles: &[[u32; 3]],
    moving: &mut [[f64; 2]],
    free_from: usize,
    slides: &[Slide],
    iterations: usize,
    rigid_parts: bool,
) {
    let free = moving.len().saturating_sub(free_from);
    if triangles.is_empty() || free + slides.len() == 0 {
        return;
    }
    let area = area_from_boundary(moving, triangles, free_from);
    let energy = Energy::against(reference, triangles, area, 0.5).with_shape(1.0);
    if energy.min_det(moving) <= 0.0 {
        return;
    }
    let mut passes = vec![energy];
    if rigid_parts {
        passes.push(
            Energy::against(reference, triangles, area, 0.5)
                .with_shape(RIGID_SHAPE_WEIGHT)
                .rigid(RIGID_KNEE),
        );
    }
    // The unknowns: each free vertex's coordinates, then each slide's
    // fraction of its segment.
    let mut x = unknowns(&moving[free_from..]);
    x.extend(
        slides
            .iter()
            .map(|s| s.fraction_of(moving[s.vertex as usize]).clamp(0.0, 1.0)),
    );
    let mut work = moving.to_vec();
    let mut grad = vec![[0.0; 2]; moving.len()];
    let put = |x: &[f64], work: &mut [[f64; 2]]| {
        place(&x[..2 * free], &mut work[free_from..]);
        for (s, &f) in slides.iter().zip(&x[2 * free..]) {
            work[s.vertex as usize] = s.at(f);
        }
    };
    // Each unknown's step scaled by the inverse of the settle's stiffness
    // along it at the start (for a slide, along its segment).
    let stiffness = passes[0].diagonal(moving);
    let scale: Vec<f64> = (free_from..moving.len())
        .flat_map(|v| [1.0 / stiffness[v], 1.0 / stiffness[v]])
        .chain(slides.iter().map(|s| {
            let d = s.segment();
            1.0 / ((d[0] * d[0] + d[1] * d[1]) * stiffness[s.vertex as usize])
        }))
        // (An unknown with no stiffness, such as a slide along a segment
        // of no length, has no gradient either: any scale does.)
        .map(|m| if m.is_finite() && m > 0.0 { m } else { 1.0 })
        .collect();
    for energy in &passes {
        lbfgs_scaled(&mut x, iterations, Some(&scale), |x, g| {
            // A slide stays on its segment: past either end it would leave
            // the outline (where the outline turns at a fixed point)
            // without necessarily turning a triangle over. The line search
            // treats the ends as it treats a triangle turning over: the
            // step is halved.
            if x[2 * free..].iter().any(|f| !(0.0..=1.0).contains(f)) {
                return f64::INFINITY;
            }
            put(x, &mut work);
            let e = energy.eval_positive(&work, Some(&mut grad));
            if e.is_infinite() {
                return e;
            }
            gather(&grad[free_from..], &mut g[..2 * free]);
            for (s, gi) in slides.iter().zip(&mut g[2 * free..]) {
                let (q, d) = (grad[s.vertex as usize], s.segment());
                *gi = q[0] * d[0] + q[1] * d[1];
            }
            e
        });
        put(&x, &mut work);
        if passes[0].min_det(&work) > 0.0 {
            moving.copy_from_slice(&work);
        } else {
            return;
        }
    }
}
