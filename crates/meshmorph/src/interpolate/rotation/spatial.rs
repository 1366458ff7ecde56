//! Rotations of space: principal unit quaternions, and logarithms that are
//! a whole-turn vector and a principal rotation vector.
//!
//! A triangle's rotation along the segment from key `j` to `j + 1` is
//! `exp(u c) exp(u e) R_j`, where `e` is the principal rotation vector of
//! `R_{j+1} R_jᵀ` and `c` its whole turns (see [`super::patches`]); from key
//! 0 (`R_0 = I`) this is the rotation interpolated along its axis by angle,
//! with whole turns where a part turns by more than half a turn.
//!
//! Between later keys the whole turns `c` are chosen as a key's branches
//! are, by the same patches ([`super::patches`]), over the rotations
//! relative to the previous key, `R_{j+1} R_jᵀ`: the patch of each part's
//! seed (the triangle that turns least from key 0 in key `j + 1`, whose
//! branch continues the previous key's) takes the shortest way, and where
//! the relative rotations jump across a half turn between neighbours, the
//! patches beyond take the whole turns that continue their neighbours'. A
//! segment whose relative rotations stay under half a turn therefore goes
//! the shortest way without a tear, a part that turns further relative to
//! its seed turns through, and where all rotations share an axis this is
//! the plane's rule (the difference of the keys' angles with branches,
//! the seed's turning by at most half a turn between keys). The keys'
//! lifted rotation vectors are not subtracted: in space rotation vectors
//! do not (`log(AB) ≠ log A + log B`; for a tail bent by 200 degrees then
//! twisted by 90 about its bent axis, or a part turned by 170 degrees about
//! one axis then by 170 about another, they differ by more than half a
//! turn from the relative rotation), and rounding the difference gave some
//! triangles a whole turn about a stray direction and their neighbours
//! none.
#![allow(non_snake_case)]

use super::patches::{nearest_whole_turns, whole_turns};
use super::{Rotations, Space};
use crate::linalg::lanes::{array, Lanes};
use crate::linalg::matrix::Mat3;
use crate::linalg::polar::{polar_decomposition3, SymmetricEigen3};
use crate::linalg::quaternion::{
    matrix_of, product, quat_axis_angle, quat_conj, quat_dot, quat_exp, quat_from_matrix, quat_log,
    quat_mul, quat_principal, quat_to_matrix, Quat,
};
use crate::linalg::trig::sin_cos_lanes;
use crate::linalg::vector::{add, norm, sub};
use crate::mesh::topology::TriangleAdjacency;

use rayon::prelude::*;
use std::collections::HashMap;

/// The logarithm of a rotation in space with its branch: the rotation
/// `exp(turns) exp(principal)`, where `principal` is the principal rotation
/// vector (axis times angle, angle in `[0, π]`) and `turns` a whole-turn
/// vector `2πk u` (`k` whole turns about the unit axis `u`, the identity as
/// a rotation, but turned through when interpolated). Interpolated, it is
/// `exp(t · turns) exp(t · principal)`: along the rotation's own axis by
/// angle when `u` is that axis.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RotationLog3 {
    /// The whole-turn vector `2πk u`.
    pub turns: [f64; 3],
    /// The principal rotation vector.
    pub principal: [f64; 3],
    /// For a later key of a sequence (branches chosen with a previous key),
    /// the whole-turn vector `c` of the way from the previous key's rotation
    /// `R_j` to this one, `exp(u c) exp(u e) R_j` with `e` the principal
    /// rotation vector of `R_{j+1} R_jᵀ`: chosen over the triangle adjacency
    /// like the branches, from the rotations relative to the previous key.
    /// `None` for a first key and for blends.
    pub turns_from_previous: Option<[f64; 3]>,
}

impl RotationLog3 {
    /// The rotation vector of the whole rotation, `turns + principal` (exact
    /// when the two are parallel).
    pub fn lifted(&self) -> [f64; 3] {
        add(self.turns, self.principal)
    }
}

/// A rotation vector as a unit axis and an angle (any axis for angle 0).
#[derive(Clone, Copy, Debug)]
pub struct AxisAngle {
    pub axis: [f64; 3],
    pub angle: f64,
}

impl AxisAngle {
    pub fn new(w: [f64; 3]) -> Self {
        let angle = norm(w);
        if angle > 0.0 {
            Self {
                axis: w.map(|x| x / angle),
                angle,
            }
        } else {
            Self {
                axis: [1.0, 0.0, 0.0],
                angle: 0.0,
            }
        }
    }

    /// The quaternion of the rotation by `u` times the angle.
    #[inline]
    pub fn quat_at(&self, u: f64) -> Quat {
        quat_axis_angle(self.axis, self.angle * u)
    }
}

/// One triangle's rotation along one segment: `exp(u c) exp(u e) R_j`,
/// with `c` one of the segment's shared whole-turn vectors.
#[derive(Clone, Copy, Debug)]
pub struct SegmentRotation {
    base: Quat,
    principal: AxisAngle,
    /// The index of `c` among the segment's whole-turn vectors, or
    /// [`NO_TURNS`].
    turns: u32,
}

/// The distinct whole-turn vectors of one segment, which its
/// [`SegmentRotation`]s refer to by index.
#[derive(Clone, Debug, Default)]
pub struct SegmentTurns(pub Vec<AxisAngle>);

/// [`SegmentRotation::turns`] of a triangle that takes no whole turn.
const NO_TURNS: u32 = u32::MAX;

impl SegmentRotation {
    /// The rotation a fraction `u` along the segment, from its start or, with
    /// `has_base`, from key 0.
    #[inline(always)]
    fn at(&self, turns_at: &[Quat], u: f64, has_base: bool) -> Mat3 {
        let turn = turn_quats([self], [turns_at], Lanes([u]));
        let mut q = array(|k| turn[k].0[0]);
        if has_base {
            q = quat_mul(q, self.base);
        }
        quat_to_matrix(q)
    }
}

/// The quaternions `exp(u c) exp(u e)` of the rotations from the start of
/// `segments[l]` a fraction `u[l]` along it, lane by lane, with the whole
/// turns `turns_at[l]` of its segment at that fraction.
#[inline(always)]
fn turn_quats<const L: usize>(
    segments: [&SegmentRotation; L],
    turns_at: [&[Quat]; L],
    u: Lanes<L>,
) -> [Lanes<L>; 4] {
    let half = Lanes(array(|l| 0.5 * (segments[l].principal.angle * u.0[l])));
    let (s, c) = sin_cos_lanes(half);
    let axis = |k: usize| Lanes(array(|l| segments[l].principal.axis[k]));
    let q = [c, s * axis(0), s * axis(1), s * axis(2)];
    let mut any_turns = false;
    for segment in &segments {
        any_turns |= segment.turns != NO_TURNS;
    }
    if !any_turns {
        return q;
    }
    // Lanes without whole turns turn by the identity.
    let turns = array(|k| {
        Lanes(array(|l| match segments[l].turns {
            NO_TURNS => [1.0, 0.0, 0.0, 0.0][k],
            c => turns_at[l][c as usize][k],
        }))
    });
    product(turns, q)
}

/// One triangle's rotation from `from` to `to`: its base, its principal
/// rotation vector `e` and its whole-turn vector `c` (zero without
/// `whole_turns`). Between later keys, the whole turns chosen with `to`'s
/// branches, `e` from the relative rotation they were chosen for (bit for
/// bit, so that a triangle turned by exactly half a turn keeps the side of
/// it the choice saw); from a first key (the identity), the whole turns of
/// `to`'s branch.
fn segment(
    (from, from_log): (&Quat, &RotationLog3),
    (to, to_log): (&Quat, &RotationLog3),
    whole_turns: bool,
) -> (Quat, [f64; 3], [f64; 3]) {
    let base = *from;
    match to_log.turns_from_previous {
        Some(c) if whole_turns => (base, quat_log(relative_rotation(to, from_log)), c),
        _ => {
            let e = quat_log(quat_mul(*to, quat_conj(base)));
            let c = if whole_turns {
                nearest_whole_turns(sub(sub(to_log.lifted(), from_log.lifted()), e))
            } else {
                [0.0; 3]
            };
            (base, e, c)
        }
    }
}

/// The rotation `R_{j+1} R_jᵀ` from the rotation whose logarithm is `from`
/// to `to`.
#[inline]
fn relative_rotation(to: &Quat, from: &RotationLog3) -> Quat {
    quat_mul(*to, quat_conj(quat_exp(from.principal)))
}

/// The whole-turn vector of every triangle's way from the previous key
/// (`previous`: its logarithms) to `rotations` (the principal rotations of
/// the next key): the branch choice of [`whole_turns`] applied to the
/// rotations relative to the previous key, `R_{j+1} R_jᵀ`, over patches
/// between their jumps, the patch of each part's seed taking no whole
/// turns.
fn turns_from_previous(
    previous: &[RotationLog3],
    rotations: &[Quat],
    adjacency: &TriangleAdjacency,
    edge_weight: &dyn Fn(usize, usize) -> f64,
    seeds: &[usize],
) -> Vec<[f64; 3]> {
    // Relative rotations by exactly half a turn are not settled: the
    // segment turns each by its own `e`, on whichever side of the half turn
    // rounding puts it, and the patches give those on the other side than
    // their neighbours the whole turn that joins them.
    let relative: Vec<Quat> = rotations
        .par_iter()
        .zip(previous)
        .map(|(q, p)| quat_principal(relative_rotation(q, p)))
        .collect();
    whole_turns(&relative, adjacency, edge_weight, seeds, None)
}

impl Rotations<3> for Space<3> {
    /// A unit quaternion with scalar part `≥ 0`.
    type Principal = Quat;
    type Log = RotationLog3;
    type Segment = SegmentRotation;
    type SegmentTurns = SegmentTurns;
    type StretchPowers = SymmetricEigen3;

    const IDENTITY: Quat = [1.0, 0.0, 0.0, 0.0];

    fn polar(A: &Mat3) -> (Quat, Mat3) {
        let p = polar_decomposition3(*A);
        (quat_from_matrix(&p.rotation), p.stretch)
    }

    fn angle(q: &Quat) -> f64 {
        let v = norm([q[1], q[2], q[3]]);
        2.0 * v.atan2(q[0].abs())
    }

    /// A rotation by exactly half a turn has two principal quaternions,
    /// `(0, ±v)`, and which one rounding gives decides on which side of a
    /// half-turn jump the triangle falls (see `choose_branches`).
    /// Triangles within `1e-12` of a half turn take the sign that agrees
    /// with most of their neighbours (the rotation moves by at most `4e-12`
    /// radians), so that a ring of them turning by exactly half a turn
    /// joins its neighbours rather than splitting at random.
    fn settle_half_turns(rotations: &mut [Quat], adjacency: &TriangleAdjacency) {
        let flips: Vec<usize> = (0..rotations.len())
            .filter(|&t| {
                rotations[t][0].abs() < 1e-12 && {
                    let agree: f64 = adjacency
                        .of(t)
                        .iter()
                        .map(|&u| quat_dot(rotations[t], rotations[u as usize]))
                        .sum();
                    agree < 0.0
                }
            })
            .collect();
        for t in flips {
            let q = rotations[t];
            rotations[t] = [q[0].abs(), -q[1], -q[2], -q[3]];
        }
    }

    fn principal_log(q: &Quat) -> RotationLog3 {
        RotationLog3 {
            turns: [0.0; 3],
            principal: quat_log(*q),
            turns_from_previous: None,
        }
    }

    /// Whole turns of the patches between the edges across which the
    /// principal rotations jump: each region between jumps takes one
    /// whole-turn vector, decided from all its boundary at once, and only
    /// where it removes a tear (a walk from triangle to triangle adds up
    /// errors in space, where neighbours' axes differ).
    fn choose_branches(
        rotations: &[Quat],
        adjacency: &TriangleAdjacency,
        edge_weight: &dyn Fn(usize, usize) -> f64,
        seeds: &[usize],
        previous: Option<(&[RotationLog3], &[f64])>,
    ) -> Vec<RotationLog3> {
        let lifted: Option<Vec<[f64; 3]>> =
            previous.map(|(logs, _)| logs.iter().map(RotationLog3::lifted).collect());
        let continued = lifted.as_deref().zip(previous.map(|(_, areas)| areas));
        let mut logs: Vec<RotationLog3> =
            whole_turns(rotations, adjacency, edge_weight, seeds, continued)
                .into_iter()
                .zip(rotations)
                .map(|(turns, q)| RotationLog3 {
                    turns,
                    principal: quat_log(*q),
                    turns_from_previous: None,
                })
                .collect();
        if let Some((previous, _)) = previous {
            let turns = turns_from_previous(previous, rotations, adjacency, edge_weight, seeds);
            for (log, c) in logs.iter_mut().zip(turns) {
                log.turns_from_previous = Some(c);
            }
        }
        logs
    }

    fn add_turns(log: &RotationLog3, turns: i32) -> RotationLog3 {
        let axis = AxisAngle::new(log.principal).axis;
        RotationLog3 {
            turns: add(
                log.turns,
                axis.map(|x| x * std::f64::consts::TAU * turns as f64),
            ),
            principal: log.principal,
            turns_from_previous: log.turns_from_previous,
        }
    }

    /// The whole-turn vectors are shared by value: a patch's triangles
    /// (numbered near one another in most meshes) refer to one entry.
    fn segments(
        from: (&[Quat], &[RotationLog3]),
        to: (&[Quat], &[RotationLog3]),
        whole_turns: bool,
    ) -> (Vec<SegmentRotation>, SegmentTurns) {
        let parts: Vec<(Quat, [f64; 3], [f64; 3])> = (0..from.0.len())
            .into_par_iter()
            .map(|t| segment((&from.0[t], &from.1[t]), (&to.0[t], &to.1[t]), whole_turns))
            .collect();
        let mut shared: Vec<AxisAngle> = Vec::new();
        let mut index: HashMap<[u64; 3], u32> = HashMap::new();
        let mut last: Option<([f64; 3], u32)> = None;
        let segments = parts
            .into_iter()
            .map(|(base, e, c)| {
                let turns = if c == [0.0; 3] {
                    NO_TURNS
                } else if let Some((_, i)) =
                    last.filter(|(l, _)| l.map(f64::to_bits) == c.map(f64::to_bits))
                {
                    i
                } else {
                    let i = *index.entry(c.map(f64::to_bits)).or_insert_with(|| {
                        shared.push(AxisAngle::new(c));
                        (shared.len() - 1) as u32
                    });
                    last = Some((c, i));
                    i
                };
                SegmentRotation {
                    base,
                    principal: AxisAngle::new(e),
                    turns,
                }
            })
            .collect();
        (segments, SegmentTurns(shared))
    }

    fn turns_at(turns: &SegmentTurns, u: f64, out: &mut Vec<Quat>) {
        out.clear();
        out.extend(turns.0.iter().map(|c| c.quat_at(u)));
    }

    #[inline]
    fn segment_at(segment: &SegmentRotation, turns_at: &[Quat], u: f64, first: bool) -> Mat3 {
        segment.at(turns_at, u, !first)
    }

    fn segment_start(segment: &SegmentRotation) -> Mat3 {
        quat_to_matrix(segment.base)
    }

    #[inline(always)]
    fn turn_at<const L: usize>(
        segments: [&SegmentRotation; L],
        turns_at: [&[Quat]; L],
        u: Lanes<L>,
    ) -> [[Lanes<L>; 3]; 3] {
        matrix_of(turn_quats(segments, turns_at, u))
    }

    fn has_whole_turns(segment: &SegmentRotation) -> bool {
        segment.turns != NO_TURNS
    }

    #[inline]
    fn add_scaled(sum: &mut RotationLog3, w: f64, log: &RotationLog3) {
        for k in 0..3 {
            sum.turns[k] += w * log.turns[k];
            sum.principal[k] += w * log.principal[k];
        }
    }

    #[inline]
    fn exp(log: &RotationLog3) -> Mat3 {
        quat_to_matrix(quat_mul(quat_exp(log.turns), quat_exp(log.principal)))
    }

    fn stretch_powers(S: &Mat3) -> SymmetricEigen3 {
        SymmetricEigen3::new(*S)
    }

    #[inline]
    fn stretch_power(S: &SymmetricEigen3, t: f64, floor: f64) -> Mat3 {
        S.power(t, floor)
    }

    fn stretch_log(S: &Mat3, floor: f64) -> Mat3 {
        SymmetricEigen3::new(*S).map_values(|l| l.max(floor).ln())
    }

    #[inline]
    fn stretch_exp(L: &Mat3) -> Mat3 {
        SymmetricEigen3::new(*L).map_values(f64::exp)
    }
}
