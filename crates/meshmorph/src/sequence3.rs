//! As-rigid-as-possible interpolation of surfaces in space, through any
//! number of keys.
//!
//! Each key `K_j` is a pose of the first key `K_0` (the same triangles).
//! Per triangle the 3×3 map from `K_0` to `K_j` (Sumner and Popović's
//! frames, with a fourth vertex off the triangle's plane) is split by the
//! polar decomposition `A_j = R_j S_j`, `R_j` a proper rotation. Within the
//! segment from key `j` to `j + 1`, at `u ∈ [0, 1]`:
//!
//! - the rotation is `exp(u c) exp(u e) R_j`, where `e` is the principal
//!   rotation vector of `R_{j+1} R_jᵀ` and `c` its whole turns (see
//!   [`crate::consistency3`]); in the first segment `R_0 = I`, so this is
//!   `R(t)` interpolated along its axis by angle, with whole turns where a
//!   part turns by more than half a turn;
//! - the stretch is `(1−u) S_j + u S_{j+1}` ([`StretchMode::Linear`], with
//!   `S_0 = I`: Alexa et al. 2000), or `exp((1−u) log S_j + u log S_{j+1})`
//!   ([`StretchMode::Log`]; `S_1ᵘ` in the first segment), which never
//!   collapses a triangle;
//! - the vertices are the least-squares fit of these maps
//!   ([`PreparedSurface`], factored once for every segment), each connected
//!   part placed with its area-weighted centroid on the straight line
//!   between the keys' centroids.
//!
//! Rotations are measured from `K_0` and continue across keys: each key's
//! whole turns are chosen by rotation consistency over the mesh, and the
//! seed's region of a later key takes the whole turns nearest to the
//! previous key's, so a part that keeps turning keeps turning the same way.
//! Key `j` is at time `s = j`.
#![allow(non_snake_case)]

use std::sync::Arc;

use rayon::prelude::*;

use crate::consistency3::{nearest_whole_turns, whole_turns_after};
use crate::error::{Error, Result};
use crate::geometry::{add, norm, sub};
use crate::interpolate::{FrameWorkspace, InterpolatorOptions, PreparedSurface, StretchMode};
use crate::matrix::{identity, lerp_from_identity, mul as mul3, Mat3};
use crate::mesh::Mesh3;
use crate::polar3::SymmetricEigen3;
use crate::pose3::{shared_edge_length, RestFrames};
use crate::rotation3::{quat_axis_angle, quat_log, quat_mul, quat_to_matrix, Quat};

/// Eigenvalues of stretches below this are raised to it before logarithms
/// and powers.
pub(crate) const LOG_FLOOR: f64 = 1e-12;

/// A rotation vector as a unit axis and an angle (any axis for angle 0).
#[derive(Clone, Copy, Debug)]
pub(crate) struct AxisAngle {
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

/// One triangle's rotation along one segment: `exp(u c) exp(u e) R_j`.
#[derive(Clone, Copy, Debug)]
struct SegmentRotation {
    base: Quat,
    principal: AxisAngle,
    turns: AxisAngle,
}

impl SegmentRotation {
    #[inline]
    fn at(&self, u: f64, has_base: bool) -> Mat3 {
        let mut q = self.principal.quat_at(u);
        if self.turns.angle != 0.0 {
            q = quat_mul(self.turns.quat_at(u), q);
        }
        if has_base {
            q = quat_mul(q, self.base);
        }
        quat_to_matrix(q)
    }
}

#[derive(Debug)]
enum SegmentStretches {
    /// `S_1`, for `(1−u) I + u S_1` (first segment).
    FromIdentity(Vec<Mat3>),
    /// `(S_j, S_{j+1})`, interpolated linearly.
    Linear(Vec<(Mat3, Mat3)>),
    /// `S_1ᵘ` (first segment, log mode).
    Power(Vec<SymmetricEigen3>),
    /// `(log S_j, log S_{j+1})`, interpolated linearly, then exponentiated.
    LogLinear(Vec<(Mat3, Mat3)>),
}

#[derive(Debug)]
struct Segment {
    rotations: Vec<SegmentRotation>,
    stretches: SegmentStretches,
    has_base: bool,
}

/// A keyframe sequence of surfaces in space: as-rigid-as-possible frames
/// through every key (see the module documentation). Two keys make an
/// interpolation from the first (`s = 0`) to the second (`s = 1`).
///
/// Everything that does not depend on `s` is computed in
/// [`Sequence3::new`]; [`Sequence3::at`] cannot fail.
///
/// ```
/// use meshmorph::{shapes, InterpolatorOptions, Sequence3};
///
/// // A tube bent through 540 degrees: the frame halfway is bent through 270.
/// let tube = shapes::tube(10.0, 0.2, 81, 8);
/// let bent = shapes::bend(&tube, 10.0, 3.0 * std::f64::consts::PI);
/// let morph = Sequence3::new(&[tube, bent], &InterpolatorOptions::default())?;
/// let halfway = morph.at(0.5);
/// assert_eq!(morph.count_turned_over(&halfway), 0);
/// # Ok::<(), meshmorph::Error>(())
/// ```
#[derive(Debug)]
pub struct Sequence3 {
    surface: Arc<PreparedSurface>,
    frames: RestFrames,
    segments: Vec<Segment>,
    /// Centroid of each part in each key.
    centroids: Vec<Vec<[f64; 3]>>,
    /// Positions of the vertices no triangle uses, in each key.
    loose: Vec<Vec<[f64; 3]>>,
}

/// Per-thread scratch for [`Sequence3::at_into`] and [`crate::Blend3::at_into`].
#[derive(Debug)]
pub struct SequenceWorkspace {
    pub(crate) surface: FrameWorkspace<3>,
    pub(crate) centroids: Vec<[f64; 3]>,
}

impl Sequence3 {
    /// Prepares the sequence through `keys` (at least two), factoring the
    /// system of the first.
    ///
    /// # Errors
    /// - [`Error::InvalidArgument`] for fewer than two keys, or `turns` other
    ///   than 0 (whole extra turns need a common axis: planar meshes only);
    /// - [`Error::Mismatch`] naming the first key whose vertex or triangle
    ///   count differs from the first key's, [`Error::TriangleMismatch`] the
    ///   first key and triangle whose corners differ;
    /// - [`Error::DegenerateTriangles`] for zero-area triangles of the first key;
    /// - [`Error::ReflectedTriangles`] for triangles of a key turned over
    ///   relative to the first (unless [`InterpolatorOptions::allow_flips`]);
    /// - [`Error::Solver`] if the system cannot be factored.
    pub fn new(keys: &[Mesh3], options: &InterpolatorOptions) -> Result<Self> {
        let Some(first) = keys.first() else {
            return Err(Error::InvalidArgument(
                "a sequence needs at least two keys".into(),
            ));
        };
        first.check_no_degenerate_triangles("first key")?;
        let frames = RestFrames::new(first, "first key")?;
        check_poses(first, &frames, &keys[1..], "key", options)?;
        // The factorization and the per-triangle work are independent.
        let (surface, segments) = rayon::join(
            || PreparedSurface::named(first, "first key", options.factor),
            || segments(first, &frames, &keys[1..], options),
        );
        Self::build(Arc::new(surface?), frames, &keys[1..], segments?)
    }

    /// The sequence from the prepared surface's rest mesh (key 0) through
    /// `later_keys`: any number of sequences and blends can share one
    /// factorization.
    ///
    /// # Errors
    /// As [`Sequence3::new`].
    pub fn with_surface(
        surface: Arc<PreparedSurface>,
        later_keys: &[Mesh3],
        options: &InterpolatorOptions,
    ) -> Result<Self> {
        let frames = RestFrames::new(surface.source(), "first key")?;
        check_poses(surface.source(), &frames, later_keys, "key", options)?;
        let segments = segments(surface.source(), &frames, later_keys, options)?;
        Self::build(surface, frames, later_keys, segments)
    }

    fn build(
        surface: Arc<PreparedSurface>,
        frames: RestFrames,
        later: &[Mesh3],
        segments: Vec<Segment>,
    ) -> Result<Self> {
        let rest = surface.source();
        let loose_of = |p: &[[f64; 3]]| -> Vec<[f64; 3]> {
            surface
                .loose_vertices()
                .iter()
                .map(|&v| p[v as usize])
                .collect()
        };
        let mut centroids = vec![surface.centroids(rest.positions())];
        let mut loose = vec![loose_of(rest.positions())];
        for key in later {
            centroids.push(surface.centroids(key.positions()));
            loose.push(loose_of(key.positions()));
        }
        Ok(Self {
            surface,
            frames,
            segments,
            centroids,
            loose,
        })
    }

    /// The prepared rest surface, to share with other sequences and blends.
    pub fn surface(&self) -> &Arc<PreparedSurface> {
        &self.surface
    }

    /// For each segment (key `j` to `j + 1`), how many triangles take whole
    /// turns beyond their principal rotation: 0 wherever no part turns by
    /// more than half a turn.
    pub fn triangles_with_whole_turns(&self) -> Vec<usize> {
        self.segments
            .iter()
            .map(|s| s.rotations.iter().filter(|r| r.turns.angle != 0.0).count())
            .collect()
    }

    /// Number of keys (the last one is at `s = num_keys() − 1`).
    pub fn num_keys(&self) -> usize {
        self.segments.len() + 1
    }

    /// Number of vertices of every frame.
    pub fn num_vertices(&self) -> usize {
        self.surface.num_vertices()
    }

    /// The triangles shared by every frame.
    pub fn triangles(&self) -> &[[u32; 3]] {
        self.surface.source().triangles()
    }

    /// Scratch for [`Sequence3::at_into`]; one per thread.
    pub fn workspace(&self) -> SequenceWorkspace {
        SequenceWorkspace {
            surface: self.surface.workspace(),
            centroids: vec![[0.0; 3]; self.surface.num_components()],
        }
    }

    /// Vertex positions at time `s`: key `j` at `s = j`; times before 0 or
    /// after the last key extrapolate the first or last segment.
    pub fn at(&self, s: f64) -> Vec<[f64; 3]> {
        let mut out = vec![[0.0; 3]; self.num_vertices()];
        self.at_into(s, &mut out, &mut self.workspace());
        out
    }

    /// Frames at each of `times`, computed in parallel.
    pub fn frames(&self, times: &[f64]) -> Vec<Vec<[f64; 3]>> {
        times
            .par_iter()
            .map_init(
                || self.workspace(),
                |ws, &s| {
                    let mut out = vec![[0.0; 3]; self.num_vertices()];
                    self.at_into(s, &mut out, ws);
                    out
                },
            )
            .collect()
    }

    /// [`Sequence3::at`] into a caller's buffer, with a caller's scratch.
    ///
    /// # Panics
    /// If `out.len()` is not the number of vertices.
    #[track_caller]
    pub fn at_into(&self, s: f64, out: &mut [[f64; 3]], ws: &mut SequenceWorkspace) {
        let last = self.segments.len() - 1;
        let j = if s.is_nan() {
            0
        } else {
            (s.floor().max(0.0) as usize).min(last)
        };
        let u = s - j as f64;
        let seg = &self.segments[j];
        let lerp = |a: [f64; 3], b: [f64; 3]| -> [f64; 3] {
            std::array::from_fn(|k| (1.0 - u) * a[k] + u * b[k])
        };
        for (c, (a, b)) in ws
            .centroids
            .iter_mut()
            .zip(self.centroids[j].iter().zip(&self.centroids[j + 1]))
        {
            *c = lerp(*a, *b);
        }
        let rot = |t: usize| seg.rotations[t].at(u, seg.has_base);
        let (surface, centroids) = (&mut ws.surface, &ws.centroids);
        match &seg.stretches {
            SegmentStretches::FromIdentity(v) => self.surface.solve_into(
                |t| mul3(rot(t), lerp_from_identity(&v[t], u)),
                centroids,
                out,
                surface,
            ),
            SegmentStretches::Linear(v) => self.surface.solve_into(
                |t| {
                    let (a, b) = &v[t];
                    let S: Mat3 = std::array::from_fn(|r| {
                        std::array::from_fn(|c| (1.0 - u) * a[r][c] + u * b[r][c])
                    });
                    mul3(rot(t), S)
                },
                centroids,
                out,
                surface,
            ),
            SegmentStretches::Power(v) => self.surface.solve_into(
                |t| mul3(rot(t), v[t].power(u, LOG_FLOOR)),
                centroids,
                out,
                surface,
            ),
            SegmentStretches::LogLinear(v) => self.surface.solve_into(
                |t| {
                    let (a, b) = &v[t];
                    let L: Mat3 = std::array::from_fn(|r| {
                        std::array::from_fn(|c| (1.0 - u) * a[r][c] + u * b[r][c])
                    });
                    mul3(rot(t), SymmetricEigen3::new(L).map_values(f64::exp))
                },
                centroids,
                out,
                surface,
            ),
        }
        for (k, &v) in self.surface.loose_vertices().iter().enumerate() {
            out[v as usize] = lerp(self.loose[j][k], self.loose[j + 1][k]);
        }
    }

    /// Number of triangles of `positions` turned over relative to the first
    /// key (folded back onto their neighbours, or collapsed).
    pub fn count_turned_over(&self, positions: &[[f64; 3]]) -> usize {
        self.frames
            .turned_over(self.surface.source(), positions)
            .len()
    }
}

/// The segments between consecutive keys (see the module documentation).
fn segments(
    rest: &Mesh3,
    frames: &RestFrames,
    later: &[Mesh3],
    options: &InterpolatorOptions,
) -> Result<Vec<Segment>> {
    if later.is_empty() {
        return Err(Error::InvalidArgument(
            "a sequence needs at least two keys".into(),
        ));
    }
    if options.turns != 0 {
        return Err(Error::InvalidArgument(
            "whole extra turns need a common axis of rotation: they apply to planar meshes only"
                .into(),
        ));
    }
    let num_triangles = rest.num_triangles();
    let areas = rest.triangle_areas();
    let mut previous_quats: Vec<Quat> = vec![[1.0, 0.0, 0.0, 0.0]; num_triangles];
    let mut previous_lifted = vec![[0.0; 3]; num_triangles];
    let mut previous_stretch = vec![identity::<3>(); num_triangles];
    let mut segments = Vec::with_capacity(later.len());
    for (j, key) in later.iter().enumerate() {
        let maps = frames.decompose(rest, key, &format!("key {}", j + 1))?;
        let turns = if !options.consistency {
            vec![[0.0; 3]; num_triangles]
        } else {
            let seeds = frames.seeds(rest, &maps.rotations);
            whole_turns_after(
                &maps.rotations,
                &frames.adjacency,
                |a, b| shared_edge_length(rest, a, b),
                &seeds,
                (j > 0).then_some((previous_lifted.as_slice(), areas.as_slice())),
            )
        };
        let lifted: Vec<[f64; 3]> = turns
            .iter()
            .zip(&maps.rotations)
            .map(|(&c, &q)| add(c, quat_log(q)))
            .collect();
        let rotations: Vec<SegmentRotation> = (0..num_triangles)
            .into_par_iter()
            .map(|t| {
                let base = previous_quats[t];
                let conj = [base[0], -base[1], -base[2], -base[3]];
                let e = quat_log(quat_mul(maps.rotations[t], conj));
                let c = if options.consistency {
                    nearest_whole_turns(sub(sub(lifted[t], previous_lifted[t]), e))
                } else {
                    [0.0; 3]
                };
                SegmentRotation {
                    base,
                    principal: AxisAngle::new(e),
                    turns: AxisAngle::new(c),
                }
            })
            .collect();
        let log = |S: &Mat3| SymmetricEigen3::new(*S).map_values(|l| l.max(LOG_FLOOR).ln());
        let stretches = match options.stretch {
            StretchMode::Log if j == 0 => SegmentStretches::Power(
                maps.stretches
                    .par_iter()
                    .map(|S| SymmetricEigen3::new(*S))
                    .collect(),
            ),
            StretchMode::Log => SegmentStretches::LogLinear(
                previous_stretch
                    .par_iter()
                    .zip(&maps.stretches)
                    .map(|(a, b)| (log(a), log(b)))
                    .collect(),
            ),
            StretchMode::Linear if j == 0 => SegmentStretches::FromIdentity(maps.stretches.clone()),
            StretchMode::Linear => SegmentStretches::Linear(
                previous_stretch
                    .iter()
                    .copied()
                    .zip(maps.stretches.iter().copied())
                    .collect(),
            ),
        };
        segments.push(Segment {
            rotations,
            stretches,
            has_base: j > 0,
        });
        previous_quats = maps.rotations;
        previous_lifted = lifted;
        previous_stretch = maps.stretches;
    }
    Ok(segments)
}

/// Checks that each of `poses` has the rest's connectivity and no triangle
/// turned over (unless allowed); `role` names them ("key", "blend shape"),
/// numbered from 1.
pub(crate) fn check_poses(
    rest: &Mesh3,
    frames: &RestFrames,
    poses: &[Mesh3],
    role: &str,
    options: &InterpolatorOptions,
) -> Result<()> {
    for (k, pose) in poses.iter().enumerate() {
        let name = format!("{role} {}", k + 1);
        rest.check_same_connectivity(pose, ["the first mesh", &name])?;
        pose.check_no_overflow(&name)?;
        if !options.allow_flips {
            frames.check_pose(rest, pose, &name)?;
        }
    }
    Ok(())
}
