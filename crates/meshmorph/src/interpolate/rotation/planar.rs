//! Rotations of the plane: angles.
//!
//! A triangle's rotation along the segment from key `j` to `j + 1` is the
//! rotation by `θ_j + u (θ_{j+1} − θ_j)`, the angles with their branches;
//! from key 0 (`θ_0 = 0`) this is `R(u θ)`, as in Alexa et al. 2000.
#![allow(non_snake_case)]

use std::f64::consts::TAU;

use super::{make_consistent, Rotations, Space};
use crate::linalg::lanes::{array, Lanes};
use crate::linalg::matrix::Mat2;
use crate::linalg::polar::{polar_decomposition, rotation, SymmetricEigen2};
use crate::linalg::trig::sin_cos_lanes;
use crate::mesh::topology::TriangleAdjacency;

/// `angle + 2πk` for the integer `k` that brings it nearest to `reference`.
#[inline]
pub fn nearest_branch(angle: f64, reference: f64) -> f64 {
    angle + TAU * ((reference - angle) / TAU).round()
}

/// One triangle's rotation along one segment: the angle at its start and
/// the angle it turns through.
#[derive(Clone, Copy, Debug)]
pub struct AngleSegment {
    start: f64,
    turn: f64,
}

/// The rotation from the angle `from` to `to`: through their difference
/// with `whole_turns`, else the shortest way.
pub fn segment(from: f64, to: f64, whole_turns: bool) -> AngleSegment {
    let turn = to - from;
    AngleSegment {
        start: from,
        turn: if whole_turns {
            turn
        } else {
            nearest_branch(turn, 0.0)
        },
    }
}

impl Rotations<2> for Space<2> {
    /// Radians, counter-clockwise, in (−π, π].
    type Principal = f64;
    /// Radians, counter-clockwise.
    type Log = f64;
    type Segment = AngleSegment;
    type SegmentTurns = ();
    type StretchPowers = SymmetricEigen2;

    const IDENTITY: f64 = 0.0;

    fn polar(A: &Mat2) -> (f64, Mat2) {
        let p = polar_decomposition(*A);
        (p.angle, p.stretch)
    }

    fn angle(angle: &f64) -> f64 {
        angle.abs()
    }

    fn principal_log(angle: &f64) -> f64 {
        *angle
    }

    /// The walk over the adjacency (Baxter et al. 2008): each triangle
    /// takes the branch nearest to the one of the triangle it is reached
    /// from; each seed keeps its principal angle, or takes the branch
    /// nearest to its previous angle.
    fn choose_branches(
        angles: &[f64],
        adjacency: &TriangleAdjacency,
        _edge_weight: &dyn Fn(usize, usize) -> f64,
        seeds: &[usize],
        previous: Option<(&[f64], &[f64])>,
    ) -> Vec<f64> {
        let mut logs = angles.to_vec();
        if let Some((previous, _)) = previous {
            for &s in seeds {
                logs[s] = nearest_branch(logs[s], previous[s]);
            }
        }
        make_consistent(&mut logs, adjacency, seeds, |&a, &r| nearest_branch(a, r));
        logs
    }

    fn add_turns(angle: &f64, turns: i32) -> f64 {
        angle + TAU * turns as f64
    }

    /// With `whole_turns`, from one angle to the other; without, the
    /// shortest way.
    fn segments(
        (_, from): (&[f64], &[f64]),
        (_, to): (&[f64], &[f64]),
        whole_turns: bool,
    ) -> (Vec<AngleSegment>, ()) {
        let segments = from
            .iter()
            .zip(to)
            .map(|(&from, &to)| segment(from, to, whole_turns))
            .collect();
        (segments, ())
    }

    fn turns_at(_: &(), _: f64, out: &mut Vec<[f64; 4]>) {
        out.clear();
    }

    #[inline]
    fn segment_at(segment: &AngleSegment, _: &[[f64; 4]], u: f64, _first: bool) -> Mat2 {
        rotation(segment.start + u * segment.turn)
    }

    fn segment_start(segment: &AngleSegment) -> Mat2 {
        rotation(segment.start)
    }

    #[inline(always)]
    fn turn_at<const L: usize>(
        segments: [&AngleSegment; L],
        _: [&[[f64; 4]]; L],
        u: Lanes<L>,
    ) -> [[Lanes<L>; 2]; 2] {
        let (s, c) = sin_cos_lanes(Lanes(array(|l| u.0[l] * segments[l].turn)));
        [[c, -s], [s, c]]
    }

    fn has_whole_turns(segment: &AngleSegment) -> bool {
        // Beyond half a turn (exactly half a turn is either way).
        segment.turn.abs() > std::f64::consts::PI
    }

    #[inline]
    fn add_scaled(sum: &mut f64, w: f64, angle: &f64) {
        *sum += w * angle;
    }

    #[inline]
    fn exp(angle: &f64) -> Mat2 {
        rotation(*angle)
    }

    fn stretch_powers(S: &Mat2) -> SymmetricEigen2 {
        SymmetricEigen2::new(*S)
    }

    #[inline]
    fn stretch_power(S: &SymmetricEigen2, t: f64, floor: f64) -> Mat2 {
        S.power(t, floor)
    }

    fn stretch_log(S: &Mat2, floor: f64) -> Mat2 {
        SymmetricEigen2::new(*S).map_values(|l| l.max(floor).ln())
    }

    #[inline]
    fn stretch_exp(L: &Mat2) -> Mat2 {
        SymmetricEigen2::new(*L).map_values(f64::exp)
    }
}
