//! Triangle correspondence between a source and a target mesh from a few
//! marker pairs of surface points (Sumner and Popović 2004, section 5).
//!
//! 0. Unless [`CorrespondOptions::align`] is off, the source reference is
//!    first brought onto the target reference by the similarity (rotation,
//!    uniform scale, translation) that best fits the marker pairs
//!    ([`Similarity::fit`]): moving, turning or scaling the source changes
//!    nothing. The similarity is kept in the [`Correspondence`], and
//!    [`Transfer`](crate::Transfer) applies it to every pose.
//! 1. The source reference is deformed onto the target reference by
//!    minimising `w_S E_S + w_I E_I + w_C E_C` over its vertices and fourth
//!    vertices, markers held at their target points (a vertex pinned, a
//!    point inside a triangle by a stiff term): `E_S` asks
//!    neighbouring triangles to deform alike, `E_I` asks every triangle to
//!    keep its shape (its deformation gradient near a similarity: a turn and
//!    a uniform scale) and `E_C` pulls every vertex to the closest compatible
//!    point of the target (on a triangle facing within 25° of the vertex's
//!    normal). A first round runs without `E_C`; then `w_C`
//!    grows round by round, closest points found afresh.
//! 2. Triangles of the deformed source and of the target are paired with the
//!    closest compatible triangle of the other mesh (centroids within a
//!    threshold, normals less than 60° apart), in both directions.
//! 3. The transfer's own turn is fitted to the normals of the matched pairs
//!    (the markers' fit reads every difference of shape as a turn), and
//!    keeps the two planes of symmetry together when both meshes are their
//!    own mirror images.
#![allow(non_snake_case)]

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::gradient::solve::{FactorKind, SymmetricBuilder, SymmetricMatrix};
use crate::gradient::weights::{normalise_by_mean, normalised_by_mean, vertex_weights};
use crate::gradient::{FactoredSystem, GradientOperators, Pins};
use crate::linalg::matrix::{identity, mul_vec, Mat3};
use crate::linalg::similarity::{
    closest_rotation, fit_robust, residuals, robust_rotation, Similarity,
};
use crate::linalg::vector::{add, centroid, dot, least_turn, scale, sub};
use crate::mesh::closest::{unit_normal, vertex_normals, Angle, CentroidIndex, SurfaceIndex};
use crate::mesh::topology::{connected_components, edges, Components, Edge};
use crate::mesh::{used_vertices, Mesh3};
use crate::transfer::correspondence::Correspondence;
use crate::transfer::fit_report::FitReport;
use crate::transfer::markers::{key, Key, Markers, HOLD_STIFFNESS};
use crate::transfer::mirror_plane::{mirror_plane, MirrorPlane};
use crate::transfer::partner_parts::Partners;

/// Options of [`correspond`]; the defaults follow the paper.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct CorrespondOptions {
    /// `w_S`, weight of the smoothness term. Default 1.
    pub smoothness_weight: f64,
    /// `w_I`, weight of the identity term. Default 0.3 (the paper's is
    /// 0.001).
    ///
    /// The term asks the source to keep its own shape where the markers and
    /// closest points would pull it into another (eyelids and lips into
    /// each other, a body bent where only a few markers sit). The paper
    /// asks every deformation gradient `T` to stay near the identity, which
    /// also counts every turn and change of size as a change of shape: its
    /// sources did not overlap their targets, and the term had to be faint.
    /// Here it asks `T` to stay near the similarity `s R` nearest to it
    /// (`R` the rotation of its polar decomposition, `s` the scale that fits
    /// best), taken from the previous round's solution (the identity in the
    /// first), as as-rigid-as-possible energies do with rotations: the term
    /// sees only changes of shape, whatever turn or size the source needs
    /// (a neck that stands higher, the scale left by the alignment), and
    /// the matrix stays the same (only the right-hand side moves). Stronger,
    /// it also keeps the markers from reshaping a source whose proportions
    /// differ from the target's: 0.3 still lets them make a tube twice too
    /// thin as thick as its target (`tests/library/real_meshes.rs`; from 0.7 on
    /// they no longer do).
    pub identity_weight: f64,
    /// `w_C` of each closest-point round, in order (a first round without
    /// closest points always runs before them). Default `[1, 1667.33,
    /// 3333.67, 5000]`: from 1 to 5000 in four steps.
    ///
    /// The closest-point term measures distances in units of the target's
    /// bounding-box diagonal (the paper's meshes are about that size), as
    /// the other two terms compare dimensionless gradients: the same
    /// weights then mean the same whatever unit the meshes were modelled
    /// in, and scaling both references scales the result and changes
    /// nothing else.
    pub closest_weights: Vec<f64>,
    /// Largest distance to a closest point, as a fraction of the target's
    /// bounding-box diagonal; farther vertices are not pulled. Default 0.02.
    pub closest_cutoff: f64,
    /// Largest angle, in degrees, between a source vertex's normal and the
    /// normal of the target triangle its closest point lies on; points on
    /// triangles turned farther are not taken. Default 25.
    ///
    /// A closest point whose surface faces another way is most often on
    /// another feature: the far side of a thin part, a neighbouring leg, the
    /// inside of a lip. Pulled there, the source folds onto the wrong
    /// surface, and with few markers nothing pulls it back. Measured on
    /// horse → camel (BENCHMARKS.md, "Correspondence from few markers"),
    /// 25° instead of 90° (with matched pairs within 60°) takes the mean
    /// pose error with 16 markers from 0.0170 to 0.0142, with 27 from
    /// 0.0187 to 0.0171 and with 9 from 0.0218 to 0.0206; with all 107 from
    /// 0.0145 to 0.0144; face → head stays at 0.0084.
    pub closest_normal_angle: f64,
    /// Largest centroid distance of a matched triangle pair, as a fraction of
    /// the target's bounding-box diagonal, but never less than the mean edge
    /// length of either mesh. Default 0.01: pairs farther apart
    /// than that are more often wrong than right, and a target triangle left
    /// without a pair takes its neighbours' deformation in the transfer.
    pub match_threshold: f64,
    /// Largest angle, in degrees, between the normals of a matched triangle
    /// pair. Default 60: a deformed source lies on its target, and a
    /// partner turned by more is on another side of the surface (90° let
    /// through pairs across creases and thin parts).
    pub match_normal_angle: f64,
    /// Bring the source onto the target by the similarity that best fits
    /// the markers before anything else, and transfer the deformations in
    /// the orientation the matched surface agrees on (with the planes of
    /// symmetry together when both meshes have one). Default `true`; off,
    /// the two references must already overlap, and nothing is turned.
    pub align: bool,
}

impl Default for CorrespondOptions {
    fn default() -> Self {
        Self {
            smoothness_weight: 1.0,
            identity_weight: 0.3,
            closest_weights: (0..4)
                .map(|k| 1.0 + (5000.0 - 1.0) * k as f64 / 3.0)
                .collect(),
            closest_cutoff: 0.02,
            closest_normal_angle: 25.0,
            match_threshold: 0.01,
            match_normal_angle: 60.0,
            align: true,
        }
    }
}

impl CorrespondOptions {
    /// The number of steps [`correspond_with_progress`] reports: each
    /// deformation round, then the matching.
    pub fn steps(&self) -> usize {
        self.closest_weights.len() + 2
    }

    /// Checks that every weight and fraction can make a solvable problem.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] naming the option.
    pub fn validate(&self) -> Result<()> {
        let bad = |name: &str, v: f64, what: &str| {
            Err(Error::InvalidArgument(format!(
                "{name} must be {what}, not {v}"
            )))
        };
        if !(self.identity_weight.is_finite() && self.identity_weight > 0.0) {
            // Without it, an affine motion that keeps the markers costs nothing.
            return bad(
                "the identity weight",
                self.identity_weight,
                "a positive number",
            );
        }
        for (name, v) in [
            ("the smoothness weight", self.smoothness_weight),
            ("the closest-point cut-off", self.closest_cutoff),
            ("the match threshold", self.match_threshold),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return bad(name, v, "a number of at least 0");
            }
        }
        for (name, v) in [
            (
                "the closest points' normal angle",
                self.closest_normal_angle,
            ),
            ("the matched pairs' normal angle", self.match_normal_angle),
        ] {
            if !(v.is_finite() && v > 0.0 && v <= 90.0) {
                return bad(name, v, "an angle in degrees above 0 and at most 90");
            }
        }
        if let Some(&w) = self
            .closest_weights
            .iter()
            .find(|w| !(w.is_finite() && **w > 0.0))
        {
            return bad("every closest-point weight", w, "a positive number");
        }
        Ok(())
    }

    /// Sets [`CorrespondOptions::closest_weights`].
    pub fn with_closest_weights(mut self, weights: Vec<f64>) -> Self {
        self.closest_weights = weights;
        self
    }
    /// Sets [`CorrespondOptions::closest_cutoff`].
    pub fn with_closest_cutoff(mut self, fraction: f64) -> Self {
        self.closest_cutoff = fraction;
        self
    }
    /// Sets [`CorrespondOptions::closest_normal_angle`] and
    /// [`CorrespondOptions::match_normal_angle`], in degrees.
    pub fn with_normal_angles(mut self, closest: f64, matched: f64) -> Self {
        self.closest_normal_angle = closest;
        self.match_normal_angle = matched;
        self
    }
    /// Sets [`CorrespondOptions::match_threshold`].
    pub fn with_match_threshold(mut self, fraction: f64) -> Self {
        self.match_threshold = fraction;
        self
    }
    /// Sets [`CorrespondOptions::align`].
    pub fn with_align(mut self, align: bool) -> Self {
        self.align = align;
        self
    }
    /// Sets the smoothness and identity weights.
    pub fn with_weights(mut self, smoothness: f64, identity: f64) -> Self {
        self.smoothness_weight = smoothness;
        self.identity_weight = identity;
        self
    }
}

/// What [`correspond`] found.
#[derive(Clone, Debug)]
pub struct CorrespondResult {
    /// The triangle map.
    pub correspondence: Correspondence,
    /// The similarity fitted to the markers, which brought the source
    /// reference onto the target reference before it was deformed onto it
    /// (the identity without alignment). The correspondence's own
    /// [`alignment`](Correspondence::alignment), which the transfer
    /// applies, has the same scale, turned to the orientation of the matched
    /// surface (and of the planes of symmetry, when both meshes have one).
    pub marker_fit: Similarity,
    /// The source reference (brought onto the target by
    /// [`CorrespondResult::marker_fit`]) deformed onto the target reference.
    pub deformed_source: Mesh3,
    /// The distance between each marker's target vertex and its source
    /// vertex brought onto the target by the alignment (in the order of the
    /// markers; the misfit of the similarity, in the target's units).
    pub marker_residuals: Vec<f64>,
    /// The planes of symmetry of the source (brought onto the target by
    /// [`CorrespondResult::marker_fit`]) and of the target, when both have
    /// one and the transfer's turn keeps them together ([`Mesh3::mirror_plane`]).
    pub mirror_planes: Option<[MirrorPlane; 2]>,
    /// How well [`CorrespondResult::deformed_source`] lies on the target:
    /// distances from the target to it, the target's area no source
    /// triangle covers, and the regions where the fit is poor (farther than
    /// the matching's threshold), with the markers nearest each.
    pub fit: FitReport,
}

impl CorrespondResult {
    /// The markers whose distance from their partners after the alignment
    /// stands out from the others' (a modified z-score above 3.5, Iglewicz
    /// and Hoaglin 1993): each is most likely on the wrong feature. Indices
    /// into the markers, in increasing order.
    pub fn far_markers(&self) -> Vec<usize> {
        crate::linalg::similarity::outliers(&self.marker_residuals)
    }
}

/// The fewest markers [`correspond`] accepts: fewer cannot fix an orientation.
pub const MIN_MARKERS: usize = 3;

/// Without markers, the similarity that brings the source onto a target
/// that stands alike (the same way up and facing the same way, as two
/// characters exported from one scene): no turn, the source's
/// area-weighted centroid onto the target's, and its area-weighted RMS
/// distance from it scaled to the target's. Moving or scaling the source
/// changes nothing; turning it does.
fn standing_alike(source: &Mesh3, target: &Mesh3) -> Similarity {
    let moments = |mesh: &Mesh3| {
        let areas = mesh.triangle_areas();
        let total: f64 = areas.iter().sum::<f64>().max(f64::MIN_POSITIVE);
        let c = area_centroid(mesh, &areas);
        let spread: f64 = (0..mesh.num_triangles())
            .zip(&areas)
            .map(|(t, a)| {
                let d = sub(centroid(mesh.corners(t)), c);
                a / total * dot(d, d)
            })
            .sum();
        (c, spread.sqrt())
    };
    let ((cs, rs), (ct, rt)) = (moments(source), moments(target));
    let s = if rs > 0.0 && rt > 0.0 { rt / rs } else { 1.0 };
    Similarity {
        rotation: identity(),
        scale: s,
        translation: sub(ct, scale(cs, s)),
    }
}

/// The largest share of the source's area a correspondence found without
/// markers may leave without a partner on the target. With their markers,
/// the shared pairs leave a few percent at most (face → head 0.2 % of the
/// triangles, horse → camel 3.7 %); without, horse → camel leaves 30 % of
/// the area (its poses then transfer with almost three times the error)
/// and face → head 80 %.
const MAX_UNPAIRED_WITHOUT_MARKERS: f64 = 0.1;

/// Refuses a correspondence found without markers that leaves more than
/// [`MAX_UNPAIRED_WITHOUT_MARKERS`] of the source's area without a partner.
fn check_unmarked_fit(source: &Mesh3, matched: &Correspondence) -> Result<()> {
    let areas = source.triangle_areas();
    let mut paired = vec![false; areas.len()];
    for p in matched.pairs() {
        paired[p[0] as usize] = true;
    }
    let total: f64 = areas.iter().sum();
    let unpaired: f64 = areas
        .iter()
        .zip(&paired)
        .filter(|(_, &p)| !p)
        .map(|(a, _)| a)
        .sum();
    let share = unpaired / total.max(f64::MIN_POSITIVE);
    if share > MAX_UNPAIRED_WITHOUT_MARKERS {
        return Err(Error::PoorFit(format!(
            "without markers, the source reached the target's surface poorly: {:.0} % of its area found no partner (at most {:.0} % is accepted); \
             the two shapes do not stand alike (the same way up, facing the same way, in proportion): give at least {MIN_MARKERS} markers",
            100.0 * share,
            100.0 * MAX_UNPAIRED_WITHOUT_MARKERS
        )));
    }
    Ok(())
}

/// The centroid of `mesh`'s surface: its triangles' centroids weighted by
/// their `areas`.
fn area_centroid(mesh: &Mesh3, areas: &[f64]) -> [f64; 3] {
    let mut centre = [0.0; 3];
    for (t, a) in areas.iter().enumerate() {
        centre = add(centre, scale(centroid(mesh.corners(t)), *a));
    }
    scale(centre, 1.0 / areas.iter().sum::<f64>())
}

/// How far the closest points reach in each closest-point round, in units
/// of [`CorrespondOptions::closest_cutoff`]: with markers, as far each
/// round; without, the first rounds reach five and two and a half times as
/// far, as nothing else draws the parts of the source towards their
/// partners.
fn reach(unmarked: bool, round: usize) -> f64 {
    match (unmarked, round) {
        (true, 0) => 5.0,
        (true, 1) => 2.5,
        _ => 1.0,
    }
}

/// Computes the triangle correspondence between `source` and `target` from
/// `markers` ([`correspond_with_progress`] to follow its steps).
///
/// # Errors
/// - [`Error::InvalidArgument`] for bad markers (out of range, repeated, a
///   source vertex with two targets, a vertex in no triangle) or fewer than
///   [`MIN_MARKERS`] (a part
///   of the source without a marker of its own is placed by the alignment
///   and drawn onto the target by the closest points);
/// - [`Error::DegenerateTriangles`] for zero-area triangles in either mesh;
/// - [`Error::Solver`] if a system cannot be factored.
pub fn correspond(
    source: &Mesh3,
    target: &Mesh3,
    markers: &Markers,
    options: &CorrespondOptions,
) -> Result<CorrespondResult> {
    correspond_with_progress(source, target, markers, options, &mut |_| {})
}

/// [`correspond`], calling `progress` with the number of steps done out of
/// [`CorrespondOptions::steps`] (for a progress bar).
///
/// # Errors
/// As [`correspond`].
pub fn correspond_with_progress(
    source: &Mesh3,
    target: &Mesh3,
    markers: &Markers,
    options: &CorrespondOptions,
    progress: &mut dyn FnMut(usize),
) -> Result<CorrespondResult> {
    let Aligned {
        alignment,
        marker_residuals,
        source: aligned,
        components,
    } = align(source, target, markers, options)?;
    let source = aligned.as_ref().unwrap_or(source);
    let unmarked = markers.pairs().is_empty();
    // The mirror planes the turn keeps together are found beside the
    // deformation (which leaves a core idle between its factorizations).
    let mut mirror_planes = (None, None);
    let deformed = rayon::in_place_scope(|scope| {
        if options.align {
            scope.spawn(|_| {
                mirror_planes = rayon::join(|| mirror_plane(source), || mirror_plane(target));
            });
        }
        deform(
            source,
            target,
            None,
            &components,
            markers,
            options,
            progress,
        )
    })?;
    let deformed_source = source.with_positions(deformed)?;
    // Centroids of two differently tessellated surfaces lie up to about an
    // edge apart even where the surfaces coincide: never ask for less.
    let (source_edge, target_edge) = rayon::join(
        || mean_edge_length(&deformed_source),
        || mean_edge_length(target),
    );
    let threshold = (options.match_threshold * target.bounding_box_diagonal())
        .max(source_edge)
        .max(target_edge);
    let matched = match_triangles(
        &deformed_source,
        &components,
        target,
        threshold,
        Angle::degrees(options.match_normal_angle),
    );
    let fit = FitReport::new(
        &deformed_source,
        target,
        &matched,
        markers,
        threshold / target.bounding_box_diagonal(),
    );
    // The markers' fit reads every difference of shape between the two as a
    // turn of the whole source: the transfer works in the orientation the
    // matched surface agrees on instead.
    let (transfer_alignment, mirror_planes) = if options.align {
        let (turn, kept) = matched_orientation(source, target, &matched, mirror_planes);
        (alignment.then(&turn), kept)
    } else {
        (Similarity::IDENTITY, None)
    };
    if unmarked {
        check_unmarked_fit(&deformed_source, &matched)?;
    }
    let correspondence = matched.with_alignment(transfer_alignment);
    progress(options.steps());
    Ok(CorrespondResult {
        correspondence,
        marker_fit: alignment,
        deformed_source,
        marker_residuals,
        mirror_planes,
        fit,
    })
}

/// The source deformed onto the target (steps 0 and 1 of [`correspond`],
/// without the pairing of triangles that follows): the similarity fitted to
/// the markers, and the source brought onto the target by it and deformed
/// onto the target's surface. `target_index` is the target's
/// [`SurfaceIndex`], where the caller has one.
///
/// # Errors
/// As [`correspond`].
pub fn deform_onto(
    source: &Mesh3,
    target: &Mesh3,
    target_index: &SurfaceIndex,
    markers: &Markers,
    options: &CorrespondOptions,
) -> Result<(Similarity, Mesh3)> {
    let Aligned {
        alignment,
        source: aligned,
        components,
        ..
    } = align(source, target, markers, options)?;
    let source = aligned.as_ref().unwrap_or(source);
    let deformed = deform(
        source,
        target,
        Some(target_index),
        &components,
        markers,
        options,
        &mut |_| {},
    )?;
    Ok((alignment, source.with_positions(deformed)?))
}

/// The source brought onto the target by the markers (step 0).
struct Aligned {
    /// The similarity fitted to the markers (the identity without
    /// alignment).
    alignment: Similarity,
    /// Each marker's misfit after it.
    marker_residuals: Vec<f64>,
    /// The source moved by it; `None` where it moves nothing.
    source: Option<Mesh3>,
    /// The source's connected parts.
    components: Components,
}

/// Checks the options, markers and meshes, and brings the source onto the
/// target by the similarity that best fits the markers.
fn align(
    source: &Mesh3,
    target: &Mesh3,
    markers: &Markers,
    options: &CorrespondOptions,
) -> Result<Aligned> {
    options.validate()?;
    markers.validate(source, target)?;
    let unmarked = markers.pairs().is_empty();
    if !unmarked && markers.pairs().len() < MIN_MARKERS {
        return Err(Error::InvalidArgument(format!(
            "{} marker pair{} given: correspondence needs at least {MIN_MARKERS} (or none, for two shapes that stand alike)",
            markers.pairs().len(),
            if markers.pairs().len() == 1 { "" } else { "s" }
        )));
    }
    source.check_no_degenerate_triangles("source reference")?;
    target.check_no_degenerate_triangles("target reference")?;
    let components = connected_components(source.num_vertices(), source.triangles());

    let (from, to) = markers.positions(source, target);
    // Fitted in a fixed order of the pairs, so that the order of the
    // markers does not change the last bits.
    let mut order: Vec<usize> = (0..from.len()).collect();
    let keys: Vec<[Key; 2]> = markers
        .pairs()
        .iter()
        .map(|[s, t]| [key(s, source.triangles()), key(t, target.triangles())])
        .collect();
    order.sort_unstable_by_key(|&k| keys[k]);
    let sorted = |p: &[[f64; 3]]| -> Vec<[f64; 3]> { order.iter().map(|&k| p[k]).collect() };
    let alignment = if options.align && unmarked {
        standing_alike(source, target)
    } else if options.align {
        fit_robust(&sorted(&from), &sorted(&to))?.0
    } else {
        Similarity::IDENTITY
    };
    let marker_residuals = residuals(&alignment, &from, &to);
    let source = if alignment.is_identity() {
        None
    } else {
        Some(source.with_positions(alignment.apply_all(source.positions()))?)
    };
    Ok(Aligned {
        alignment,
        marker_residuals,
        source,
        components,
    })
}

/// The turn that best brings the source's triangles to face the same way as
/// their partners on the target, about the source's area-weighted centroid.
///
/// The markers fix the similarity that brings the source near the target,
/// but where the shapes differ (a camel's neck stands higher than a
/// horse's) their least-squares fit reads the difference as a turn of the
/// whole source, and every transferred deformation would be turned by as
/// much. Here the turn is fitted to the unit normals of all matched pairs
/// instead ([`robust_rotation`], each pair weighing the smaller of its two
/// areas): the whole surface takes part, no lever arm lets a long neck
/// dominate, and the L1 fit follows the orientation most of the surface
/// agrees on. When both surfaces are their own mirror images, the turn then
/// brings their planes of symmetry together ([`mirror_planes_together`]).
/// It depends only on the source brought onto the target and on the target,
/// so moving, turning or scaling the source still changes nothing. Where the
/// normals leave a turn free (a flat source), the markers' orientation
/// stands.
fn matched_orientation(
    source: &Mesh3,
    target: &Mesh3,
    matched: &Correspondence,
    mirror_planes: (Option<MirrorPlane>, Option<MirrorPlane>),
) -> (Similarity, Option<[MirrorPlane; 2]>) {
    let (source_areas, target_areas) = (source.triangle_areas(), target.triangle_areas());
    let n = matched.pairs().len();
    let (mut from, mut to, mut weights) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    for &[s, t] in matched.pairs() {
        from.push(unit_normal(source.corners(s as usize)));
        to.push(unit_normal(target.corners(t as usize)));
        weights.push(source_areas[s as usize].min(target_areas[t as usize]));
    }
    let (rotation, kept) =
        mirror_planes_together(robust_rotation(&from, &to, &weights), mirror_planes);
    let turn = Similarity {
        rotation,
        scale: 1.0,
        translation: [0.0; 3],
    };
    let centre = area_centroid(source, &source_areas);
    let turn = Similarity {
        translation: sub(centre, turn.rotate(centre)),
        ..turn
    };
    (turn, kept)
}

/// How far apart (degrees) the source's mirror plane, turned, and the
/// target's may stand for [`mirror_planes_together`] to bring them together:
/// the matched normals fix the turn to a degree or two, and planes farther
/// apart than this are not each other's.
const MIRROR_PLANES_APART: f64 = 10.0;

/// `turn`, corrected by the least rotation that brings the source's mirror
/// plane onto the target's, when both have one ([`mirror_plane`]) and the
/// turn already brings them within [`MIRROR_PLANES_APART`] (then with the
/// two planes).
///
/// The matched normals fix the turn to a degree or two in every direction:
/// a tail held to one side, a head turned a little, or a tessellation that
/// differs left and right tilts their fit. Where both characters are their
/// own mirror images (most animals and people, faces and heads), the planes
/// of symmetry fix two of the turn's three degrees of freedom exactly (no
/// yaw, no roll between the two), and the normals are left to fix the
/// third: the pitch, a turn about the planes' common normal.
pub fn mirror_planes_together(
    turn: Mat3,
    (from, to): (Option<MirrorPlane>, Option<MirrorPlane>),
) -> (Mat3, Option<[MirrorPlane; 2]>) {
    let (Some(from), Some(to)) = (from, to) else {
        return (turn, None);
    };
    let mut a = mul_vec(&turn, from.normal);
    let b = to.normal;
    if dot(a, b) < 0.0 {
        a = scale(a, -1.0);
    }
    let c = dot(a, b);
    if c < MIRROR_PLANES_APART.to_radians().cos() {
        return (turn, None);
    }
    // Each column of the turn turned by the least rotation taking a onto b.
    let columns: [[f64; 3]; 3] =
        std::array::from_fn(|j| least_turn([turn[0][j], turn[1][j], turn[2][j]], a, b));
    let corrected = std::array::from_fn(|i| std::array::from_fn(|j| columns[j][i]));
    (corrected, Some([from, to]))
}

/// Mean length of the edges of a mesh.
pub fn mean_edge_length(mesh: &Mesh3) -> f64 {
    mean_length(&edges(mesh.triangles()), mesh.positions())
}

/// Mean length of `edges` (of a mesh with vertex positions `p`).
pub(crate) fn mean_length(edges: &[Edge], p: &[[f64; 3]]) -> f64 {
    let total: f64 = edges
        .iter()
        .map(|e| {
            crate::linalg::vector::norm(crate::linalg::vector::sub(
                p[e.vertices[0] as usize],
                p[e.vertices[1] as usize],
            ))
        })
        .sum();
    total / edges.len().max(1) as f64
}

/// Deforms the source onto the target; returns the deformed vertex positions.
fn deform(
    source: &Mesh3,
    target: &Mesh3,
    target_index: Option<&SurfaceIndex>,
    components: &Components,
    markers: &Markers,
    options: &CorrespondOptions,
    progress: &mut dyn FnMut(usize),
) -> Result<Vec<[f64; 3]>> {
    let n = source.num_vertices();
    let size = target.bounding_box_diagonal();
    let cutoff = options.closest_cutoff * size;
    // `w_C Σ a_v ‖(x_v − c_v) / size‖²`: scale-free, as `E_S` and `E_I`.
    let per_square_size = 1.0 / (size * size);
    // The first round has no closest-point term: its matrix (with the
    // ordering and symbolic analysis every round shares) is factored while
    // the target's triangles are indexed for the closest points.
    let first = || -> Result<_> {
        let mut terms = DeformTerms::new(source, options)?;
        let pins = marker_pins(source, target, markers);
        let held = HeldPoints::new(source, target, markers, &terms.base);
        let first_weight = options.closest_weights.first().copied().unwrap_or(1.0);
        let anchors = part_anchors(
            &terms,
            components,
            &|v| pins.is_pinned(v) || held.holds(v),
            (first_weight, per_square_size),
        );
        terms.base.add_to_diagonal(&anchors);
        held.add_to(&mut terms.base);
        terms.anchors = anchors;
        // One factorization per round, each used once: the supernodal
        // factor is the faster one then.
        let system = FactoredSystem::new(&terms.base, &pins, FactorKind::Supernodal)?;
        Ok((terms, system, held))
    };
    let built;
    let (surface, first) = match target_index {
        Some(index) => (index, first()),
        None => {
            let (index, first) = rayon::join(
                || SurfaceIndex::new(target.positions(), target.triangles()),
                first,
            );
            built = index;
            (&built, first)
        }
    };
    let (terms, mut system, held) = first?;
    let DeformTerms {
        ops,
        weights,
        mut base,
        vertex_weight,
        anchors,
    } = terms;
    // Each round adds the closest-point term to the base's diagonal, and
    // sets it back.
    let base_diagonal = base.diagonal();
    let m = ops.num_unknowns();
    let mut positions: Vec<[f64; 3]> = source.positions().to_vec();
    let rounds = std::iter::once(0.0).chain(options.closest_weights.iter().copied());
    // The identity term's targets: the similarities nearest to the previous
    // round's deformation gradients (the identity at first).
    let mut shapes: Vec<Mat3> = vec![identity(); source.num_triangles()];
    for (round, w_c) in rounds.enumerate() {
        let mut rhs = identity_rhs(&ops, &weights, options.identity_weight, &shapes);
        held.add_to_rhs(&mut rhs, m);
        for (v, &a) in anchors.iter().enumerate() {
            if a > 0.0 {
                for i in 0..3 {
                    rhs[i * m + v] += a * source.positions()[v][i];
                }
            }
        }
        if w_c > 0.0 {
            let mut diagonal = vec![0.0; m];
            let within = (
                cutoff * reach(markers.pairs().is_empty(), round - 1),
                Angle::degrees(options.closest_normal_angle),
            );
            for (v, c) in closest_points(surface, &positions, source.triangles(), within)
                .iter()
                .enumerate()
            {
                if let Some(c) = c {
                    let w = w_c * per_square_size * vertex_weight[v];
                    diagonal[v] = w;
                    for i in 0..3 {
                        rhs[i * m + v] += w * c[i];
                    }
                }
            }
            base.add_to_diagonal(&diagonal);
            // The same pattern every round: the analysis is reused.
            let factored = system.refactor(&base);
            base.set_diagonal(&base_diagonal);
            factored?;
        }
        let mut ws = system.workspace();
        ws.rhs = rhs;
        system.solve(&mut ws);
        positions = (0..n).map(|v| system.position(&ws, v)).collect();
        if positions.iter().flatten().any(|c| !c.is_finite()) {
            return Err(Error::Solver(
                "the deformation produced non-finite positions".into(),
            ));
        }
        if round < options.closest_weights.len() {
            shapes = nearest_similarities(&ops, &ws.x);
        }
        progress(round + 1);
    }
    Ok(positions)
}

/// What every round of [`deform`] shares.
struct DeformTerms {
    ops: GradientOperators<3, 4>,
    /// Each triangle's area over the mean.
    weights: Vec<f64>,
    /// `w_S E_S + w_I E_I` ([`smooth_and_identity_terms`]).
    base: SymmetricMatrix,
    /// The closest-point term's weight of each vertex: its share of the
    /// area, normalised to a mean of 1 over the vertices.
    vertex_weight: Vec<f64>,
    /// The weight holding each vertex of a part without a marker near
    /// where the alignment put it ([`part_anchors`]; 0 elsewhere).
    anchors: Vec<f64>,
}

impl DeformTerms {
    fn new(source: &Mesh3, options: &CorrespondOptions) -> Result<Self> {
        let ops = GradientOperators::spatial(source, "source reference")?;
        let weights = normalised_by_mean(&source.triangle_areas());
        let base = smooth_and_identity_terms(
            &ops,
            &weights,
            options.smoothness_weight,
            options.identity_weight,
        );
        let mut vertex_weight = vertex_weights(source.num_vertices(), source.triangles(), &weights);
        normalise_by_mean(&mut vertex_weight);
        Ok(Self {
            ops,
            weights,
            base,
            vertex_weight,
            anchors: Vec::new(),
        })
    }
}

/// `w_S E_S + w_I E_I`: the normal matrix (with every diagonal entry stored,
/// for the closest-point term to add to). Every term counts in proportion to
/// the area it covers (normalised by the mean area), so the energy does not
/// depend on the tessellation.
fn smooth_and_identity_terms(
    ops: &GradientOperators<3, 4>,
    weights: &[f64],
    smoothness_weight: f64,
    identity_weight: f64,
) -> SymmetricMatrix {
    let (m, tris) = (ops.num_unknowns(), ops.triangles());
    let mut base = SymmetricBuilder::new(m, 40 * tris.len());
    for v in 0..m {
        base.add(v, v, 0.0);
    }
    ops.add_smoothness(
        &mut base,
        &edges(tris),
        weights,
        smoothness_weight,
        |_, _| true,
    );
    for (t, w) in weights.iter().enumerate() {
        ops.add_fit(&mut base, t, identity_weight * w);
    }
    base.build()
}

/// The right-hand side of `w_I E_I` with one target gradient per triangle:
/// `E_I = Σ_t a_t ‖T_t − shapes_t‖²_F`.
fn identity_rhs(
    ops: &GradientOperators<3, 4>,
    weights: &[f64],
    identity_weight: f64,
    shapes: &[Mat3],
) -> Vec<f64> {
    let mut rhs = vec![0.0; 3 * ops.num_unknowns()];
    for (t, (w, S)) in weights.iter().zip(shapes).enumerate() {
        ops.add_fit_rhs(&mut rhs, t, S, identity_weight * w);
    }
    rhs
}

/// The similarity `s R` nearest to each triangle's deformation gradient
/// `T_t = X G_t` in the solution `x` (column-major `#unknowns × 3`): `R` the
/// rotation nearest to `T_t`, `s = tr(Rᵀ T_t) / 3` the scale that then
/// minimises `‖T_t − s R‖_F`.
pub fn nearest_similarities(ops: &GradientOperators<3, 4>, x: &[f64]) -> Vec<Mat3> {
    (0..ops.triangles().len())
        .into_par_iter()
        .map(|t| {
            let T = ops.gradient(x, t);
            let R = closest_rotation(&T);
            let s = (0..3)
                .map(|i| (0..3).map(|j| R[i][j] * T[i][j]).sum::<f64>())
                .sum::<f64>()
                / 3.0;
            R.map(|row| row.map(|r| s * r))
        })
        .collect()
}

/// Markers whose source point is a vertex (or a corner of its triangle),
/// held at their target points (in a fixed order: the solve sums the
/// pinned values' contributions in this order, and the last bits of the
/// result decide ties in matching); vertices no triangle uses (and no marker
/// names) have no term at all and stay where they are.
fn marker_pins(source: &Mesh3, target: &Mesh3, markers: &Markers) -> Pins<3> {
    let mut pairs: Vec<(u32, Key, [f64; 3])> = markers
        .pairs()
        .iter()
        .filter_map(|[s, t]| {
            let v = s.as_vertex(source.triangles())?;
            Some((v, key(t, target.triangles()), t.position(target)))
        })
        .collect();
    pairs.sort_unstable_by_key(|&(s, t, _)| (s, t));
    let mut pins = Pins::new(source.num_vertices());
    for (s, _, at) in pairs {
        let pinned = pins.pin(s as usize, at);
        debug_assert!(pinned, "markers are validated");
    }
    for (v, used) in used_vertices(source.num_vertices(), source.triangles())
        .into_iter()
        .enumerate()
    {
        if !used && !pins.is_pinned(v) {
            let pinned = pins.pin(v, source.positions()[v]);
            debug_assert!(pinned);
        }
    }
    pins
}

/// Markers whose source point lies inside a triangle or on an edge: each
/// holds its point near its target point `p` through a stiff term
/// `w ‖Σ_i b_i x_i − p‖²` over the point's vertices `x_i` and weights
/// `b_i`, added to the matrix of every round. The vertices of a triangle
/// are already coupled by the other terms, so the matrix keeps its
/// pattern; the term is continuous in the `b_i`, so moving the point along
/// its triangle moves the result continuously (a pin would jump from
/// vertex to vertex). `w` is [`HOLD_STIFFNESS`] times the matrix's
/// diagonal at the vertices, weighted by the `b_i`: stiff against the
/// local terms whatever the mesh's size and tessellation, so the point
/// lands within a small fraction of an edge of its target.
struct HeldPoints {
    /// In a fixed order (the markers' order does not change the last bits).
    points: Vec<HeldPoint>,
    holds: Vec<bool>,
}

/// A point held by [`HeldPoints`].
struct HeldPoint {
    /// The `(vertex, b_i)` terms.
    terms: Vec<(usize, f64)>,
    /// The target point.
    at: [f64; 3],
    weight: f64,
}

impl HeldPoints {
    fn new(source: &Mesh3, target: &Mesh3, markers: &Markers, base: &SymmetricMatrix) -> Self {
        let mut held: Vec<([Key; 2], HeldPoint)> = markers
            .pairs()
            .iter()
            .filter(|[s, _]| s.as_vertex(source.triangles()).is_none())
            .map(|[s, t]| {
                let terms = s.terms(source.triangles()).map(|(v, b)| (v as usize, b));
                let point = HeldPoint {
                    terms: terms.collect(),
                    at: t.position(target),
                    weight: 0.0,
                };
                (
                    [key(s, source.triangles()), key(t, target.triangles())],
                    point,
                )
            })
            .collect();
        held.sort_unstable_by_key(|h| h.0);
        let mut holds = vec![false; source.num_vertices()];
        let diagonal = if held.is_empty() {
            Vec::new()
        } else {
            base.diagonal()
        };
        let points = held
            .into_iter()
            .map(|(_, mut point)| {
                point.weight = HOLD_STIFFNESS
                    * point
                        .terms
                        .iter()
                        .map(|&(v, b)| b * diagonal[v])
                        .sum::<f64>();
                for &(v, _) in &point.terms {
                    holds[v] = true;
                }
                point
            })
            .collect();
        Self { points, holds }
    }

    /// Whether a point holds vertex `v`.
    fn holds(&self, v: usize) -> bool {
        self.holds[v]
    }

    /// `w bᵀb` of every point into the matrix.
    fn add_to(&self, base: &mut SymmetricMatrix) {
        for p in &self.points {
            base.add_row_outer(&p.terms, p.weight);
        }
    }

    /// `w b p` of every point into the right-hand side (`m` unknowns a
    /// column).
    fn add_to_rhs(&self, rhs: &mut [f64], m: usize) {
        for p in &self.points {
            for &(v, b) in &p.terms {
                for i in 0..3 {
                    rhs[i * m + v] += p.weight * b * p.at[i];
                }
            }
        }
    }
}

/// A part of the source without a marker (an eye, a tooth, a strap) has
/// nothing to place it in the first round: each of its vertices is held
/// near where the alignment put it, in every round, with the first
/// closest-point weight (`weight`, on the closest-point term's scale), so
/// that it keeps its place and shape until the closest points, thousands of
/// times stronger in the later rounds, draw it onto the target. The weight of each
/// unknown (0 in parts with a marker, and for fourth vertices) is returned.
fn part_anchors(
    terms: &DeformTerms,
    components: &Components,
    is_marked: &dyn Fn(usize) -> bool,
    (weight, per_square_size): (f64, f64),
) -> Vec<f64> {
    let mut marked = vec![false; components.count];
    for (v, c) in components.of_vertex.iter().enumerate() {
        if let Some(c) = c {
            marked[*c as usize] |= is_marked(v);
        }
    }
    // Over every unknown: the vertices, then the fourth vertices (0).
    let mut anchors = vec![0.0; terms.ops.num_unknowns()];
    for (v, c) in components.of_vertex.iter().enumerate() {
        if matches!(c, Some(c) if !marked[*c as usize]) {
            anchors[v] = weight * per_square_size * terms.vertex_weight[v];
        }
    }
    anchors
}

/// The closest point of the target surface to each vertex on a triangle
/// whose normal is within `angle` of the vertex's, if one lies within
/// `cutoff`.
fn closest_points(
    surface: &SurfaceIndex,
    positions: &[[f64; 3]],
    triangles: &[[u32; 3]],
    (cutoff, angle): (f64, Angle),
) -> Vec<Option<[f64; 3]>> {
    let normals = vertex_normals(positions, triangles);
    (0..positions.len())
        .into_par_iter()
        .map(|v| {
            surface
                .closest_compatible(positions[v], normals[v], cutoff, angle)
                .map(|c| c.point)
        })
        .collect()
}

/// Pairs each triangle of `source` with the nearest compatible triangle of
/// `target` (centroids within `threshold`, normals less than `angle` apart) and
/// each triangle of `target` with the nearest compatible one of `source`.
/// The union of both, sorted, is the map. Where either mesh has separate
/// parts, a triangle whose nearest lies in another part than its own part's
/// partner looks again among its partner's triangles (a target's skin pairs
/// with the source's skin within reach, not with an eye just under it), and
/// pairs between parts neither of which is the other's partner are left out
/// (an eyeball and eyelid skin: see `partner_parts.rs`).
pub fn match_triangles(
    source: &Mesh3,
    source_parts: &Components,
    target: &Mesh3,
    threshold: f64,
    angle: Angle,
) -> Correspondence {
    let target_parts = connected_components(target.num_vertices(), target.triangles());
    let (source_index, target_index) = rayon::join(
        || {
            CentroidIndex::new(
                source.positions(),
                source.triangles(),
                &source_parts.of_triangle,
            )
        },
        || {
            CentroidIndex::new(
                target.positions(),
                target.triangles(),
                &target_parts.of_triangle,
            )
        },
    );
    let nearest = |from: &Mesh3, t: usize, index: &CentroidIndex, part: Option<u32>| {
        let p = from.corners(t);
        index.nearest_compatible(centroid(p), unit_normal(p), threshold, angle, part)
    };
    let query = |from: &Mesh3, index: &CentroidIndex| -> Vec<Option<u32>> {
        (0..from.num_triangles())
            .into_par_iter()
            .map(|t| nearest(from, t, index, None))
            .collect()
    };
    let (mut forward, mut backward) = rayon::join(
        || query(source, &target_index),
        || query(target, &source_index),
    );
    let union = |forward: &[Option<u32>], backward: &[Option<u32>]| {
        let mut pairs: Vec<[u32; 2]> = forward
            .iter()
            .enumerate()
            .filter_map(|(s, t)| t.map(|t| [s as u32, t]))
            .chain(
                backward
                    .iter()
                    .enumerate()
                    .filter_map(|(t, s)| s.map(|s| [s, t as u32])),
            )
            .collect();
        pairs.sort_unstable();
        pairs.dedup();
        pairs
    };
    let pairs = union(&forward, &backward);
    if source_parts.count <= 1 && target_parts.count <= 1 {
        return Correspondence::new(pairs, source, target);
    }
    let partners = Partners::new(&pairs, source, source_parts, target, &target_parts);
    // A triangle whose nearest lies in another part than its own part's
    // partner looks again among the partner's triangles, and keeps what it
    // found first when none is within reach.
    let look_again = |found: &mut [Option<u32>],
                      from: &Mesh3,
                      index: &CentroidIndex,
                      partner: &(dyn Fn(u32) -> Option<u32> + Sync),
                      stays: &(dyn Fn(u32, u32) -> bool + Sync)| {
        let redo: Vec<(usize, u32)> = found
            .iter()
            .enumerate()
            .filter_map(|(t, n)| {
                let p = partner(t as u32)?;
                (!stays(t as u32, (*n)?)).then_some((t, p))
            })
            .collect();
        let again: Vec<Option<u32>> = redo
            .par_iter()
            .map(|&(t, p)| nearest(from, t, index, Some(p)))
            .collect();
        for (&(t, _), n) in redo.iter().zip(again) {
            if n.is_some() {
                found[t] = n;
            }
        }
    };
    // A source triangle also keeps a nearest target part whose partner is
    // its own part: a hand cut off a one-piece arm at a seam.
    look_again(
        &mut forward,
        source,
        &target_index,
        &|s| partners.of_source_triangle(s),
        &|s, t| {
            Some(partners.target_part(t)) == partners.of_source_triangle(s)
                || partners.of_target_triangle(t) == Some(partners.source_part(s))
        },
    );
    look_again(
        &mut backward,
        target,
        &source_index,
        &|t| partners.of_target_triangle(t),
        &|t, s| Some(partners.source_part(s)) == partners.of_target_triangle(t),
    );
    Correspondence::new(partners.keep(union(&forward, &backward)), source, target)
}
