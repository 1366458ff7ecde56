//! A planar frame's outline with its edges on the straight blend of their
//! lengths.
//!
//! Where two drawings' maps disagree a great deal (a star into a curl, a
//! hand into a hammer), the least-squares fit of the triangles' maps pulls
//! the outline in: each triangle's own map keeps its outline edge within a
//! few per cent of the blend of the edge's two lengths, but the fit of maps
//! that disagree shortens nearly every edge, by 10 to 17 % at half-way.
//! The outline is given the lengths the blend asks for, as in Sederberg,
//! Gao, Wang and Mu, "2-D shape blending: an intrinsic solution to the
//! vertex path problem" (SIGGRAPH 1993), with the directions of its edges
//! taken from the fit (whose rotations are consistent: a part that turns
//! past half a turn keeps turning the same way) and the area the fit gives
//! it (which the stretch keeps on its blend):
//!
//! 1. each loop is the least-squares fit of edges of the blended lengths
//!    `(1 − u) ℓ₀ + u ℓ₁` in the fit's directions, a change of direction
//!    weighing [`TURN_WEIGHT`] of the same change of length (so where the
//!    loop must close, its edges turn rather than stretch);
//! 2. it is brought to the area of the fit's loop by the least change in
//!    that measure (a few Newton steps on the area);
//! 3. it is placed where its points are closest to the fit's;
//! 4. the inside is solved again with the outline held: the frame
//!    minimises the same energy as the fit with the outline's points
//!    pinned. The fit minimises it free, so the inside moves by the
//!    solution of the normal matrix reduced to the inside with the
//!    outline's moves as pinned values (`A_ff δ_f = −A_fp δ_p`): one more
//!    back-substitution, with a factor made once.
//!
//! With [`InterpolatorOptions::outline_straight`](super::InterpolatorOptions::outline_straight)
//! the outline is instead put on the straight blend of its points' places
//! in the two keys (in place of steps 1 to 3), then the inside solved the
//! same way: a photo's rectangle stays the frames' rectangle.
//!
//! A rigid turn's outline already has its lengths and its area: it does
//! not move (to rounding). The frames at the keys are the keys. Where the
//! outline knots, the untying that follows ([`InterpolatorOptions::
//! untie_outlines`](super::InterpolatorOptions::untie_outlines)) cuts the
//! knot, and its edges lose their lengths there.

use super::{Dimension, RestSystem};
use crate::error::Result;
use crate::gradient::solve::{FactorKind, PinnedSystem};
use crate::linalg::block_chain::{Block, PlanarChain};
use crate::linalg::Space;
use crate::mesh::topology::boundary_loops;
use crate::outline::geometry::lerp;

/// What giving a planar sequence's frames the blended outline lengths
/// needs: the outline's loops, what the outline is put on, and the normal
/// matrix factored with the outline held.
#[derive(Debug)]
pub struct OutlineLengths {
    /// The boundary loops, as vertices in order; edge `i` of a loop runs
    /// from its point `i` to its point `i + 1` (wrapping).
    loops: Vec<Vec<u32>>,
    /// What each frame's outline is put on.
    target: Target,
    /// The fit's normal matrix with the outline's points (and the vertices
    /// no triangle uses) pinned.
    held: PinnedSystem,
}

/// What a frame's outline is put on, from each key's: the blend of its
/// edges' lengths, or of its points' places.
#[derive(Debug)]
enum Target {
    Lengths {
        /// Each key's edge lengths, the loops' edges one loop after another.
        lengths: Vec<Vec<f64>>,
        /// Each edge's weight in its loop's fit: one over its mean length
        /// in the keys.
        weights: Vec<f64>,
    },
    /// With [`InterpolatorOptions::outline_straight`](super::InterpolatorOptions::outline_straight):
    /// each key's outline points, the loops' points one loop after
    /// another.
    Places(Vec<Vec<[f64; 2]>>),
}

impl OutlineLengths {
    /// The lengths of the frames of the sequence from `rest`'s source
    /// through `keys` (every key, the first included, as positions of the
    /// source's vertices), or with `straight` the places of their outline
    /// points; none when the source's boundary is not a set of simple
    /// loops.
    ///
    /// # Errors
    /// [`Error::Solver`](crate::Error::Solver) when the system with the
    /// outline held cannot be factored.
    pub(crate) fn new<'k, const D: usize>(
        rest: &RestSystem<D>,
        keys: impl Iterator<Item = &'k [[f64; 2]]>,
        factor: FactorKind,
        straight: bool,
    ) -> Result<Option<Self>>
    where
        Space<D>: Dimension<D>,
    {
        let Ok(loops) = boundary_loops(rest.source().triangles()) else {
            return Ok(None);
        };
        if loops.is_empty() {
            return Ok(None);
        }
        let target = if straight {
            Target::Places(
                keys.map(|key| loops.iter().flatten().map(|&v| key[v as usize]).collect())
                    .collect(),
            )
        } else {
            let lengths: Vec<Vec<f64>> = keys
                .map(|key| {
                    loops
                        .iter()
                        .flat_map(|lp| edges(lp, key).map(|e| e[0].hypot(e[1])))
                        .collect()
                })
                .collect();
            let weights = (0..lengths[0].len())
                .map(|i| {
                    let mean = lengths.iter().map(|l| l[i]).sum::<f64>() / lengths.len() as f64;
                    1.0 / mean.max(f64::MIN_POSITIVE)
                })
                .collect();
            Target::Lengths { lengths, weights }
        };
        let mut pinned: Vec<usize> = loops.iter().flatten().map(|&v| v as usize).collect();
        pinned.extend(rest.loose_vertices().iter().map(|&v| v as usize));
        let held = PinnedSystem::new(&rest.normal_matrix(), &pinned, factor)?;
        Ok(Some(Self {
            loops,
            target,
            held,
        }))
    }

    /// Gives `frame`, at time `u` between keys `j` and `j + 1`, the blended
    /// outline lengths (or the straight blend of the outline's places),
    /// and moves its inside with the outline; `rows` is scratch. A loop
    /// with an edge of no length (or not finite) in the frame is left as
    /// it is.
    pub(crate) fn apply(&self, j: usize, u: f64, frame: &mut [[f64; 2]], rows: &mut Vec<[f64; 2]>) {
        rows.clear();
        rows.resize(frame.len(), [0.0; 2]);
        let mut first = 0;
        let mut moved = false;
        for lp in &self.loops {
            let edges = first..first + lp.len();
            first += lp.len();
            let placed = match &self.target {
                Target::Places(places) => places[j][edges.clone()]
                    .iter()
                    .zip(&places[j + 1][edges])
                    .map(|(&p, &q)| lerp(p, q, u))
                    .collect(),
                Target::Lengths { lengths, weights } => {
                    let (a, b) = (&lengths[j][edges.clone()], &lengths[j + 1][edges.clone()]);
                    let blend = |i: usize| (1.0 - u) * a[i] + u * b[i];
                    match outline_loop(lp, frame, blend, &weights[edges]) {
                        Some(placed) => placed,
                        None => continue,
                    }
                }
            };
            for (&v, y) in lp.iter().zip(placed) {
                let x = frame[v as usize];
                let d = [y[0] - x[0], y[1] - x[1]];
                moved |= d != [0.0; 2];
                rows[self.held.row_of(v as usize)] = d;
            }
        }
        if !moved {
            return;
        }
        self.held.solve_in_rows(rows);
        for (v, p) in frame.iter_mut().enumerate() {
            let d = rows[self.held.row_of(v)];
            *p = [p[0] + d[0], p[1] + d[1]];
        }
    }
}

/// The edges of loop `lp` in `positions`, from each point to the next.
fn edges<'a>(lp: &'a [u32], positions: &'a [[f64; 2]]) -> impl Iterator<Item = [f64; 2]> + 'a {
    (0..lp.len()).map(move |i| {
        let (a, b) = (
            positions[lp[i] as usize],
            positions[lp[(i + 1) % lp.len()] as usize],
        );
        [b[0] - a[0], b[1] - a[1]]
    })
}

/// How much a change of an edge's direction weighs against the same change
/// of its length: the outline's edges keep their blended lengths and turn
/// a little where the loop must close or keep its area. Of 0.01, 0.03, 0.1
/// and 0.3, tried on the drawings' benchmark and 270 random pairs, 0.01 and
/// 0.03 did alike; 0.1 left one random pair's frames with triangles turned
/// over, and 0.3 left the edges half as far off again (BENCHMARKS.md).
const TURN_WEIGHT: f64 = 0.03;

/// Loop `lp` of `frame` with edge `i` as close as it can be to the blended
/// length `length(i)` in the frame's direction, measured by
/// `Σ_i w_i [(t_i · d_i − ℓ_i)² + TURN_WEIGHT (n_i · d_i)²]` over the
/// loop's edges `d_i` (`t_i`, `n_i` the fit's edge direction and its
/// normal, `w_i = weight[i]`), with the area of the fit's loop, and moved
/// to where its points are closest to the fit's; none when an edge has no
/// direction or the system cannot be solved.
fn outline_loop(
    lp: &[u32],
    frame: &[[f64; 2]],
    length: impl Fn(usize) -> f64,
    weight: &[f64],
) -> Option<Vec<[f64; 2]>> {
    let m = lp.len();
    if m < 3 {
        return None;
    }
    let fitted: Vec<[f64; 2]> = lp.iter().map(|&v| frame[v as usize]).collect();
    // The loop's first point is held where the fit has it (the loop is
    // moved afterwards): the others, 1 to m − 1, are a chain.
    let mut diagonal = vec![[[0.0; 2]; 2]; m - 1];
    let mut next = vec![[[0.0; 2]; 2]; m - 2];
    let mut rhs = vec![[0.0; 2]; m - 1];
    for (i, e) in edges(lp, frame).enumerate() {
        let (now, want, w) = (e[0].hypot(e[1]), length(i), weight[i]);
        if !(now > 0.0 && now.is_finite() && want.is_finite()) {
            return None;
        }
        let t = [e[0] / now, e[1] / now];
        // K = w (t tᵀ + β n nᵀ) = w (β I + (1 − β) t tᵀ), and K f = w ℓ t
        // for the edge f = ℓ t it should be.
        let k: Block = std::array::from_fn(|a| {
            std::array::from_fn(|b| {
                w * (TURN_WEIGHT * f64::from(u8::from(a == b)) + (1.0 - TURN_WEIGHT) * t[a] * t[b])
            })
        });
        let kf = [w * want * t[0], w * want * t[1]];
        let kx0 = [
            k[0][0] * fitted[0][0] + k[0][1] * fitted[0][1],
            k[1][0] * fitted[0][0] + k[1][1] * fitted[0][1],
        ];
        let add = |to: &mut Block| {
            *to = std::array::from_fn(|a| std::array::from_fn(|b| to[a][b] + k[a][b]))
        };
        // The edge's term (y_q − y_p − f)ᵀ K (y_q − y_p − f), p = i, q = i + 1.
        if i == 0 {
            add(&mut diagonal[0]);
            rhs[0] = [rhs[0][0] + kf[0] + kx0[0], rhs[0][1] + kf[1] + kx0[1]];
        } else if i == m - 1 {
            add(&mut diagonal[m - 2]);
            rhs[m - 2] = [
                rhs[m - 2][0] - kf[0] + kx0[0],
                rhs[m - 2][1] - kf[1] + kx0[1],
            ];
        } else {
            let (p, q) = (i - 1, i);
            add(&mut diagonal[p]);
            add(&mut diagonal[q]);
            next[p] = std::array::from_fn(|a| std::array::from_fn(|b| -k[a][b]));
            rhs[p] = [rhs[p][0] - kf[0], rhs[p][1] - kf[1]];
            rhs[q] = [rhs[q][0] + kf[0], rhs[q][1] + kf[1]];
        }
    }
    let chain = PlanarChain::new(&diagonal, next)?;
    chain.solve(&mut rhs);
    let mut points = Vec::with_capacity(m);
    points.push(fitted[0]);
    points.extend(rhs);
    keep_area(&mut points, area(&fitted), &chain);
    place_on(&mut points, &fitted);
    Some(points)
}

/// Moves `placed` to where its points are closest to `fitted`'s (their
/// mean on `fitted`'s).
fn place_on(placed: &mut [[f64; 2]], fitted: &[[f64; 2]]) {
    let count = placed.len() as f64;
    let mut shift = [0.0; 2];
    for (y, x) in placed.iter().zip(fitted) {
        shift = [
            shift[0] + (x[0] - y[0]) / count,
            shift[1] + (x[1] - y[1]) / count,
        ];
    }
    for y in placed {
        *y = [y[0] + shift[0], y[1] + shift[1]];
    }
}

/// The signed area of the polygon `points`.
fn area(points: &[[f64; 2]]) -> f64 {
    let m = points.len();
    0.5 * (0..m)
        .map(|i| {
            let (p, q) = (points[i], points[(i + 1) % m]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum::<f64>()
}

/// Newton steps on the loop's area, each the least change to its edges
/// (in `edge_change`'s measure) that gives the area `target` to first
/// order.
const AREA_STEPS: usize = 4;

/// Brings the loop `points` to the signed area `target` with the least
/// change to its edges in the measure whose system `chain` has factored
/// (the loop's points after the first, which is held): a few Newton
/// steps, each moving the points by `λ H⁻¹ ∇area`.
fn keep_area(points: &mut [[f64; 2]], target: f64, chain: &PlanarChain) {
    let m = points.len();
    let mut moves = vec![[0.0; 2]; m - 1];
    for _ in 0..AREA_STEPS {
        let gap = target - area(points);
        if gap.is_nan() || gap.abs() <= 1e-12 * target.abs() {
            return;
        }
        let gradient = |i: usize| {
            let (prev, next) = (points[(i + m - 1) % m], points[(i + 1) % m]);
            [0.5 * (next[1] - prev[1]), 0.5 * (prev[0] - next[0])]
        };
        for (i, z) in moves.iter_mut().enumerate() {
            *z = gradient(i + 1);
        }
        chain.solve(&mut moves);
        let along: f64 = moves
            .iter()
            .enumerate()
            .map(|(i, z)| {
                let g = gradient(i + 1);
                g[0] * z[0] + g[1] * z[1]
            })
            .sum();
        if along.is_nan() || along <= 0.0 {
            return;
        }
        let lambda = gap / along;
        for (p, z) in points[1..].iter_mut().zip(&moves) {
            *p = [p[0] + lambda * z[0], p[1] + lambda * z[1]];
        }
    }
}
