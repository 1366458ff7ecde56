//! Deformation transfer (Sumner and Popović, "Deformation transfer for
//! triangle meshes", SIGGRAPH 2004, section 4).
//!
//! For a source pose `S_k`, every source triangle's deformation gradient
//! `Q_s = Ṽ_s V_s⁻¹` (relative to the source reference) is copied to the
//! target triangles it is paired with: the target's vertices and fourth
//! vertices minimise `Σ_(s,t) ‖T_t(x) − Q_s‖²_F`. The normal matrix depends
//! only on the target reference and the pairs, so [`Transfer::new`] factors
//! it once and [`Transfer::apply`] is a right-hand side and a
//! back-substitution.
//!
//! Each target triangle counts in proportion to its area and takes the
//! area-weighted mean gradient of the source triangles paired with it, so
//! the energy approximates an integral over the surfaces and does not depend
//! on how finely either mesh is tessellated. (The paper sums over pairs,
//! which over-weights regions where a coarse source triangle is paired with
//! many small target triangles; on Sumner's horse-to-camel data the area
//! weights bring the mean error against his own results from 0.017 to 0.015
//! and the worst from 0.023 to 0.022.)
//!
//! Target triangles in no pair are gaps of the matching when the paired
//! surface encloses them (no source triangle on the source's boundary is
//! paired along their edge: the source covers them, as a horse's back
//! covers a camel's hump) or when they lie near a paired one (within
//! [`TransferOptions::gap_distance`]): they take the deformation of their
//! neighbours (a smoothness term across their edges). The others lie beyond
//! the edge of the source and have no partner (the back of a head under a
//! face mask, a neck): each keeps its rest shape, turned by a rotation spread
//! from the paired triangles ([`RotationField`]: harmonic interpolation of
//! the paired triangles' rotations, projected onto rotations). They join the
//! paired region smoothly, a rigid motion of the whole source still moves
//! the whole target rigidly, and a local deformation of the source leaves
//! them as they are. Separate parts with few pairs (eyes, teeth) are carried
//! rigidly by the surface around them ([`CarriedParts`]); separate parts
//! with partners of their own take their shape from them, and move by as
//! much as the main part around them stands off where its own pairs would
//! put it (the target's longer neck puts its head elsewhere than the
//! source's: its eyes stay in it).
//!
//! The energy does not see translations. Each connected part of the target
//! is placed so that the centroid of each paired target triangle sits where
//! the centroid of its source triangle went, plus their offset in the
//! references carried by that source triangle's deformation gradient: by
//! the shift most pairs agree on (the weighted geometric median of the
//! pairs' shifts), so that what stays still in the source stays still in
//! the target while another region deforms. The output does not drift, and a rigid
//! (or affine) motion of the whole source moves the target by the same
//! motion, wherever the target lies. A part without pairs stays where it is.
//! Pinned target vertices ([`TransferOptions::pins`]) replace that placement
//! for the parts they are in.
#![allow(non_snake_case)]

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::gradient::solve::{FactorKind, SymmetricBuilder};
use crate::gradient::spatial::{deformation_gradient, frame_inverses};
use crate::gradient::weights::{normalised_by_mean, vertex_weights};
use crate::gradient::{FactoredSystem, GradientOperators, Pins, Placement, SolveWorkspace};
use crate::linalg::matrix::{identity, Mat3};
use crate::linalg::similarity::Similarity;
use crate::linalg::similarity::{closest_rotation, geometric_median};
use crate::linalg::vector::{centroid, sub};
use crate::mesh::topology::{connected_components, edges, Components, Edge, TriangleAdjacency};
use crate::mesh::Mesh3;
use crate::transfer::carried_parts::CarriedParts;
use crate::transfer::correspondence::Correspondence;
use crate::transfer::rotation_field::{FieldWorkspace, RotationField};

/// Options of [`Transfer::new`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct TransferOptions {
    /// Target vertices held at the given positions in every pose. The parts
    /// of the target that hold a pinned vertex are not moved by the centroid
    /// rule. Default: none.
    pub pins: Vec<(u32, [f64; 3])>,
    /// Which Cholesky variant factors the system. Default [`FactorKind::Auto`].
    pub factor: FactorKind,
    /// Unpaired target triangles whose centroid lies within this fraction
    /// of the target's bounding-box diagonal (and never less than its mean
    /// edge length) of a paired triangle's centroid are gaps of the
    /// matching and take their neighbours' deformation, as do those the
    /// paired surface encloses; farther ones beyond the edge of the source
    /// keep their rest shape, turned with the paired surface. Default 0.01, the
    /// default [`CorrespondOptions::match_threshold`](crate::CorrespondOptions::match_threshold):
    /// the distance within which the correspondence pairs triangles at all.
    pub gap_distance: f64,
}

impl Default for TransferOptions {
    fn default() -> Self {
        Self {
            pins: Vec::new(),
            factor: FactorKind::Auto,
            gap_distance: 0.01,
        }
    }
}

impl TransferOptions {
    /// Sets [`TransferOptions::factor`].
    pub fn with_factor(mut self, kind: FactorKind) -> Self {
        self.factor = kind;
        self
    }

    /// Sets [`TransferOptions::pins`].
    pub fn with_pins(mut self, pins: Vec<(u32, [f64; 3])>) -> Self {
        self.pins = pins;
        self
    }
}

/// Deformation transfer from one source reference to one target reference,
/// factored once: each pose is a right-hand side and a back-substitution
/// (Sumner and Popović 2004, section 4; the choices are described with
/// [`Transfer::new`] and [`TransferOptions`]).
#[derive(Debug)]
pub struct Transfer {
    /// What brings the source onto the target (applied to every pose).
    alignment: Similarity,
    /// The source reference, aligned (its connectivity checks poses).
    source_ref: Mesh3,
    /// `V⁻¹` of every source reference triangle.
    source_frames_inv: Vec<Mat3>,
    /// `G = D V⁻¹` of every target reference triangle.
    target_gradients: GradientOperators<3, 4>,
    pairs: PairsByTarget,
    /// The weight of each target triangle (its area over the mean).
    weights: Vec<f64>,
    /// Rotations for the unpaired triangles.
    field: RotationField,
    /// The unpaired triangles that are not gaps: held to their rest shape,
    /// turned.
    unpaired: Vec<u32>,
    /// How many unpaired triangles are gaps of the matching (deformed as
    /// their neighbours).
    gaps: usize,
    /// Separate parts carried by the surface around them.
    carried: CarriedParts,
    /// The target reference's positions (carried parts move them rigidly).
    target_rest: Vec<[f64; 3]>,
    system: FactoredSystem<3>,
    /// The target's parts not held by a pin.
    placement: Placement<3>,
    /// How each placed part follows the source, by placed part.
    anchors: Vec<PartAnchor>,
    /// The paired parts whose place follows the main part around them.
    following: Vec<FollowingAnchors>,
}

/// The source triangles paired with each target triangle, with their
/// weights: compressed rows `(source triangle, weight)`.
#[derive(Clone, Debug)]
struct PairsByTarget {
    ptr: Vec<usize>,
    pairs: Vec<(u32, f64)>,
}

impl PairsByTarget {
    /// Each target triangle counts in proportion to its weight (area over
    /// the mean area) and takes the area-weighted mean gradient of its
    /// partners: pair (s, t) weighs `weight_t · area_s / Σ area_partners`.
    fn new(correspondence: &Correspondence, source_areas: &[f64], target_weights: &[f64]) -> Self {
        let num_targets = target_weights.len();
        let mut ptr = vec![0usize; num_targets + 1];
        for p in correspondence.pairs() {
            ptr[p[1] as usize + 1] += 1;
        }
        for t in 0..num_targets {
            ptr[t + 1] += ptr[t];
        }
        let mut fill = ptr.clone();
        let mut pairs = vec![(0u32, 0.0); correspondence.pairs().len()];
        for p in correspondence.pairs() {
            pairs[fill[p[1] as usize]] = (p[0], source_areas[p[0] as usize]);
            fill[p[1] as usize] += 1;
        }
        for t in 0..num_targets {
            let partners = &mut pairs[ptr[t]..ptr[t + 1]];
            let total: f64 = partners.iter().map(|p| p.1).sum();
            partners
                .iter_mut()
                .for_each(|p| p.1 *= target_weights[t] / total);
        }
        Self { ptr, pairs }
    }

    /// The partners of target triangle `t`.
    #[inline]
    fn of(&self, t: usize) -> &[(u32, f64)] {
        &self.pairs[self.ptr[t]..self.ptr[t + 1]]
    }

    fn is_paired(&self, t: usize) -> bool {
        self.ptr[t + 1] > self.ptr[t]
    }
}

/// How one connected part of the target follows the source.
#[derive(Clone, Debug, Default)]
struct PartAnchor {
    /// The pairs `(source triangle, target triangle, weight)` in the part.
    pairs: Vec<(u32, u32, f64)>,
    /// For each pair, the offset from the centroid of its source triangle to
    /// the centroid of its target triangle in the references.
    offsets: Vec<[f64; 3]>,
    /// The part's own area-weighted centroid in the target reference, where
    /// a part without pairs stays.
    target_rest: [f64; 3],
}

/// How a paired part next to the target's main part follows it (see
/// `carried_parts.rs`): where its anchors, the main part's vertices nearest
/// to it, would be if they followed their own pairs as a placed part does.
#[derive(Clone, Debug)]
struct FollowingAnchors {
    /// The placed part that follows.
    part: usize,
    /// `(source triangle, anchor vertex, weight)` for each pair of each
    /// triangle around each anchor.
    pairs: Vec<(u32, u32, f64)>,
    /// For each pair, the offset from the centroid of its source triangle to
    /// the anchor in the references.
    offsets: Vec<[f64; 3]>,
}

/// Scratch of [`Transfer::place`].
#[derive(Debug)]
struct PlaceWorkspace {
    /// One vector per placed part: its centroid, then its shift.
    parts: Vec<[f64; 3]>,
    /// The shift each pair of a part asks for, with the pair's weight.
    shifts: Vec<([f64; 3], f64)>,
}

/// Per-thread scratch for [`Transfer::apply_into`].
#[derive(Debug)]
pub struct PoseWorkspace {
    solve: SolveWorkspace,
    /// The pose brought onto the target by the alignment.
    aligned: Vec<[f64; 3]>,
    gradients: Vec<Mat3>,
    place: PlaceWorkspace,
    /// Rotation of each unpaired target triangle.
    rotations: Vec<Mat3>,
    field: FieldWorkspace,
}

impl Transfer {
    /// Prepares the transfer from poses of `source_ref` to `target_ref`
    /// through `correspondence`.
    ///
    /// # Errors
    /// - [`Error::Mismatch`] if the correspondence was made for other meshes;
    /// - [`Error::DegenerateTriangles`] for zero-area triangles in either mesh;
    /// - [`Error::InvalidArgument`] for a pin out of range or repeated;
    /// - [`Error::Solver`] if the system cannot be factored.
    pub fn new(
        source_ref: &Mesh3,
        target_ref: &Mesh3,
        correspondence: &Correspondence,
        options: &TransferOptions,
    ) -> Result<Self> {
        correspondence.check_fits(source_ref, target_ref)?;
        let alignment = *correspondence.alignment();
        let aligned;
        let source_ref = if alignment.is_identity() {
            source_ref
        } else {
            aligned = source_ref.with_positions(alignment.apply_all(source_ref.positions()))?;
            &aligned
        };
        source_ref.check_no_degenerate_triangles("source reference")?;
        target_ref.check_no_degenerate_triangles("target reference")?;
        let source_frames_inv = frame_inverses(source_ref, "source reference")?;
        let (target_gradients, (tri_edges, adjacency)) = rayon::join(
            || GradientOperators::spatial(target_ref, "target reference"),
            || {
                let tri_edges: Vec<Edge> = edges(target_ref.triangles());
                let adjacency =
                    TriangleAdjacency::from_edges(target_ref.num_triangles(), &tri_edges);
                (tri_edges, adjacency)
            },
        );
        let target_gradients = target_gradients?;
        let target_areas = target_ref.triangle_areas();
        let weights = normalised_by_mean(&target_areas);
        let pairs = PairsByTarget::new(correspondence, &source_ref.triangle_areas(), &weights);
        let paired: Vec<bool> = (0..target_ref.num_triangles())
            .map(|t| pairs.is_paired(t))
            .collect();
        let gap_distance = (options.gap_distance * target_ref.bounding_box_diagonal()).max(
            crate::transfer::matching::mean_length(&tri_edges, target_ref.positions()),
        );
        let (beyond, near) = rayon::join(
            || beyond_the_source(target_ref, source_ref, &pairs, &adjacency, &paired),
            || gaps(target_ref, &paired, gap_distance),
        );
        let is_gap: Vec<bool> = near
            .into_iter()
            .zip(&paired)
            .zip(&beyond)
            .map(|((near, &p), &b)| !p && (near || !b))
            .collect();
        let unpaired: Vec<u32> = (0..target_ref.num_triangles() as u32)
            .filter(|&t| !paired[t as usize] && !is_gap[t as usize])
            .collect();
        let gaps = is_gap.iter().filter(|&&g| g).count();
        let matrix = normal_equations(&target_gradients, &tri_edges, &is_gap, &weights);
        let components = connected_components(target_ref.num_vertices(), target_ref.triangles());
        let mut pins = target_pins(&options.pins, target_ref.num_vertices())?;
        let held_by_pin = pins.hold_free_parts(&components, |v| target_ref.positions()[v]);
        // The factorization, most of the setup, runs while the rest is made.
        let (system, rest) = rayon::join(
            || FactoredSystem::new(&matrix, &pins, options.factor),
            || -> Result<_> {
                let field = RotationField::new(&adjacency, &paired, &weights)?;
                let carried = CarriedParts::new(
                    target_ref.positions(),
                    &components,
                    &paired,
                    &target_areas,
                    &held_by_pin,
                );
                let placement = Placement::new(
                    &components,
                    |c| !held_by_pin[c],
                    vertex_weights(
                        target_ref.num_vertices(),
                        target_ref.triangles(),
                        &target_areas,
                    ),
                );
                let anchors = part_anchors(&placement, &pairs, source_ref, target_ref);
                let following = following_anchors(
                    &carried,
                    &components,
                    &placement,
                    &pairs,
                    source_ref,
                    target_ref,
                );
                Ok((field, carried, placement, anchors, following))
            },
        );
        let (field, carried, placement, anchors, following) = rest?;
        let system = system?;
        Ok(Self {
            alignment,
            source_ref: source_ref.clone(),
            source_frames_inv,
            target_gradients,
            pairs,
            weights,
            field,
            unpaired,
            gaps,
            carried,
            target_rest: target_ref.positions().to_vec(),
            system,
            placement,
            anchors,
            following,
        })
    }

    /// The target's triangles, shared by every output.
    pub fn target_triangles(&self) -> &[[u32; 3]] {
        self.target_gradients.triangles()
    }

    /// The number of the target's vertices, as every output has.
    pub fn num_target_vertices(&self) -> usize {
        self.target_gradients.num_vertices()
    }

    /// Scratch for [`Transfer::apply_into`]; one per thread.
    pub fn workspace(&self) -> PoseWorkspace {
        PoseWorkspace {
            solve: self.system.workspace(),
            aligned: Vec::new(),
            gradients: vec![[[0.0; 3]; 3]; self.source_ref.num_triangles()],
            place: PlaceWorkspace {
                parts: vec![[0.0; 3]; self.placement.count()],
                shifts: Vec::new(),
            },
            rotations: vec![identity(); self.target_triangles().len()],
            field: self.field.workspace(),
        }
    }

    /// Checks that `pose` is a pose of the source reference.
    ///
    /// # Errors
    /// [`Error::Mismatch`] naming what differs.
    pub fn check_pose(&self, pose: &Mesh3) -> Result<()> {
        pose.check_same_connectivity(&self.source_ref, ["the pose", "the source reference"])
    }

    /// The target's vertex positions in `pose`.
    ///
    /// # Errors
    /// [`Error::Mismatch`] if `pose` does not have the source's connectivity.
    pub fn apply(&self, pose: &Mesh3) -> Result<Vec<[f64; 3]>> {
        self.check_pose(pose)?;
        let mut out = vec![[0.0; 3]; self.num_target_vertices()];
        self.apply_into(pose.positions(), &mut out, &mut self.workspace());
        Ok(out)
    }

    /// [`Transfer::apply`] on many poses, in parallel.
    ///
    /// # Errors
    /// [`Error::Mismatch`] naming the first pose (by index) that does not fit.
    pub fn apply_all(&self, poses: &[Mesh3]) -> Result<Vec<Vec<[f64; 3]>>> {
        for (k, p) in poses.iter().enumerate() {
            self.check_pose(p)
                .map_err(|e| Error::Mismatch(format!("pose {k}: {e}")))?;
        }
        Ok(poses
            .par_iter()
            .map_init(
                || self.workspace(),
                |ws, pose| {
                    let mut out = vec![[0.0; 3]; self.num_target_vertices()];
                    self.apply_into(pose.positions(), &mut out, ws);
                    out
                },
            )
            .collect())
    }

    /// The transfer of source pose vertex positions `pose` into `out`.
    ///
    /// # Panics
    /// If `pose` or `out` has the wrong length (use [`Transfer::check_pose`]
    /// on untrusted poses first).
    #[track_caller]
    pub fn apply_into(&self, pose: &[[f64; 3]], out: &mut [[f64; 3]], ws: &mut PoseWorkspace) {
        assert_eq!(
            pose.len(),
            self.source_ref.num_vertices(),
            "pose has the wrong number of vertices"
        );
        assert_eq!(
            out.len(),
            self.num_target_vertices(),
            "output has the wrong number of vertices"
        );
        let mut aligned = std::mem::take(&mut ws.aligned);
        let pose = if self.alignment.is_identity() {
            pose
        } else {
            aligned.clear();
            aligned.extend(pose.iter().map(|&p| self.alignment.apply(p)));
            &aligned[..]
        };
        for ((Q, tri), V_inv) in ws
            .gradients
            .iter_mut()
            .zip(self.source_ref.triangles())
            .zip(&self.source_frames_inv)
        {
            *Q = deformation_gradient(*V_inv, tri.map(|v| pose[v as usize]));
        }
        ws.solve.rhs.fill(0.0);
        for t in 0..self.target_triangles().len() {
            if let Some(sum) = self.partner_gradient(t, &ws.gradients) {
                self.target_gradients
                    .add_fit_rhs(&mut ws.solve.rhs, t, &sum, 1.0);
            }
        }
        if !self.unpaired.is_empty() {
            let gradients = &ws.gradients;
            self.field.fill(
                |t| closest_rotation(&self.partner_gradient(t, gradients).unwrap_or(identity())),
                &mut ws.rotations,
                &mut ws.field,
            );
            for &t in &self.unpaired {
                let t = t as usize;
                self.target_gradients.add_fit_rhs(
                    &mut ws.solve.rhs,
                    t,
                    &ws.rotations[t],
                    self.weights[t],
                );
            }
        }
        self.system.solve(&mut ws.solve);
        for (v, o) in out.iter_mut().enumerate() {
            *o = self.system.position(&ws.solve, v);
        }
        self.place(pose, &ws.gradients, out, &mut ws.place);
        self.carried.carry(&self.target_rest, out);
        ws.aligned = aligned;
    }

    /// Number of separate parts of the target carried rigidly by the
    /// surface around them (anchored to it by their nearest vertices).
    pub fn carried_parts(&self) -> usize {
        self.carried.len()
    }

    /// Number of separate parts of the target with partners of their own
    /// that are placed by the main part around them.
    pub fn following_parts(&self) -> usize {
        self.following.len()
    }

    /// Number of target triangles in no pair that lie beyond the source
    /// (not gaps of the matching: no partner nearby), held to their rest
    /// shape, turned by the spread rotation.
    pub fn unpaired_triangles(&self) -> usize {
        self.unpaired.len()
    }

    /// Number of target triangles in no pair that are gaps of the matching
    /// (enclosed by the paired surface, or near a paired triangle): they
    /// take their neighbours' deformation. With
    /// [`Transfer::unpaired_triangles`] they make up every target triangle
    /// in no pair.
    pub fn gap_triangles(&self) -> usize {
        self.gaps
    }

    /// The weighted sum of the gradients of triangle `t`'s partners (its
    /// target, times its weight), `None` without partners.
    #[inline]
    fn partner_gradient(&self, t: usize, gradients: &[Mat3]) -> Option<Mat3> {
        let sources = self.pairs.of(t);
        if sources.is_empty() {
            return None;
        }
        let mut sum = [[0.0; 3]; 3];
        for &(s, w) in sources {
            let Q = &gradients[s as usize];
            for i in 0..3 {
                for j in 0..3 {
                    sum[i][j] += w * Q[i][j];
                }
            }
        }
        Some(sum)
    }

    /// Where source triangle `s` carries a point at `offset` from its
    /// centroid in the references: its centroid in `pose` plus the offset
    /// mapped by its deformation gradient.
    #[inline]
    fn carried_by(
        &self,
        s: u32,
        offset: &[f64; 3],
        pose: &[[f64; 3]],
        gradients: &[Mat3],
    ) -> [f64; 3] {
        let cs = centroid(self.source_ref.triangles()[s as usize].map(|v| pose[v as usize]));
        let Q = &gradients[s as usize];
        std::array::from_fn(|i| {
            cs[i] + Q[i][0] * offset[0] + Q[i][1] * offset[1] + Q[i][2] * offset[2]
        })
    }

    /// Moves each unpinned part so that its paired triangles' centroids
    /// follow those of their source triangles: each at its source triangle's
    /// centroid in `pose` plus the rest offset between the two mapped by the
    /// source triangle's deformation gradient. The part takes the shift most
    /// of its pairs agree on (their weighted geometric median), so a region
    /// that does not move in the source does not move in the target while
    /// another region deforms (a skull while the jaw opens). A rigid (or
    /// affine) motion of the source moves every pair alike, and the target
    /// by the same motion. A part without pairs stays where it is. Then each
    /// part that follows the main part (`carried_parts.rs`) moves by as much
    /// as the main part's vertices around it (its anchors) stand off where
    /// their own pairs would put them (the weighted geometric median).
    fn place(
        &self,
        pose: &[[f64; 3]],
        gradients: &[Mat3],
        out: &mut [[f64; 3]],
        ws: &mut PlaceWorkspace,
    ) {
        let PlaceWorkspace { parts, shifts } = ws;
        self.placement.centroids(out, parts);
        for (anchor, part) in self.anchors.iter().zip(parts.iter_mut()) {
            if anchor.pairs.is_empty() {
                *part = std::array::from_fn(|i| anchor.target_rest[i] - part[i]);
                continue;
            }
            shifts.clear();
            for (&(s, t, w), o) in anchor.pairs.iter().zip(&anchor.offsets) {
                let ct = centroid(self.target_triangles()[t as usize].map(|v| out[v as usize]));
                shifts.push((sub(self.carried_by(s, o, pose, gradients), ct), w));
            }
            *part = geometric_median(shifts);
        }
        self.placement.translate(out, parts);
        if self.following.is_empty() {
            return;
        }
        // A part next to the main one moves by as much as the main part
        // around it stands off where its own pairs would put it.
        parts.fill([0.0; 3]);
        for follower in &self.following {
            shifts.clear();
            for (&(s, a, w), o) in follower.pairs.iter().zip(&follower.offsets) {
                shifts.push((
                    sub(out[a as usize], self.carried_by(s, o, pose, gradients)),
                    w,
                ));
            }
            if !shifts.is_empty() {
                parts[follower.part] = geometric_median(shifts);
            }
        }
        self.placement.translate(out, parts);
    }
}

/// The normal matrix over the target's vertices and fourth vertices: every
/// triangle fitted to a target (its partners' gradient, or its rest shape
/// turned), except the gaps of the matching, which take their neighbours'
/// deformation through smoothness across their edges.
fn normal_equations(
    operators: &GradientOperators<3, 4>,
    tri_edges: &[Edge],
    is_gap: &[bool],
    weights: &[f64],
) -> crate::gradient::solve::SymmetricMatrix {
    let n = operators.triangles().len();
    let mut builder = SymmetricBuilder::new(operators.num_unknowns(), 12 * n);
    for t in 0..n {
        if !is_gap[t] {
            operators.add_fit(&mut builder, t, weights[t]);
        }
    }
    operators.add_smoothness(&mut builder, tri_edges, weights, 1.0, |a, b| {
        is_gap[a] || is_gap[b]
    });
    builder.build()
}

/// Which unpaired triangles of `mesh` have their centroid within `distance`
/// of a paired triangle's centroid.
fn gaps(mesh: &Mesh3, paired: &[bool], distance: f64) -> Vec<bool> {
    use rstar::primitives::GeomWithData;
    let centroids: Vec<[f64; 3]> = (0..mesh.num_triangles())
        .map(|t| centroid(mesh.corners(t)))
        .collect();
    let items: Vec<GeomWithData<[f64; 3], ()>> = centroids
        .iter()
        .zip(paired)
        .filter(|(_, p)| **p)
        .map(|(c, _)| GeomWithData::new(*c, ()))
        .collect();
    let tree = rstar::RTree::bulk_load(items);
    let d2 = distance * distance;
    centroids
        .par_iter()
        .zip(paired)
        .map(|(c, &p)| {
            !p && tree
                .nearest_neighbor_iter_with_distance_2(*c)
                .next()
                .is_some_and(|(_, d)| d <= d2)
        })
        .collect()
}

/// Which unpaired target triangles lie beyond the source, by region (the
/// unpaired triangles connected through shared edges). A region lies beyond
/// the source when
/// - it borders a target triangle paired with a source triangle on the
///   source's boundary (one with a corner on a boundary edge): the edge of
///   an open source (a face mask) runs along it;
/// - or it reaches farther from the paired triangles around it than those
///   are wide (twice their largest distance from their own centre): it is
///   deeper than wide, and stands out of the paired surface (the far half of
///   a target under a source that covers half of it) rather than filling a
///   hole in it (an eye between its lids);
/// - or it borders no paired triangle at all.
///
/// The others are holes of the matching that the paired surface around
/// them spans (a camel's hump under a horse's back, lips whose shapes
/// differ): the source covers them, and they take their neighbours'
/// deformation, however wide.
fn beyond_the_source(
    target: &Mesh3,
    source: &Mesh3,
    pairs: &PairsByTarget,
    adjacency: &TriangleAdjacency,
    paired: &[bool],
) -> Vec<bool> {
    use crate::linalg::vector::{norm, sub};
    use rstar::primitives::GeomWithData;
    let mut on_rim = vec![false; source.num_vertices()];
    for e in edges(source.triangles()) {
        if e.triangles.len() == 1 {
            on_rim[e.vertices[0] as usize] = true;
            on_rim[e.vertices[1] as usize] = true;
        }
    }
    let rim_source = |s: u32| {
        source.triangles()[s as usize]
            .iter()
            .any(|&v| on_rim[v as usize])
    };
    let n = paired.len();
    let centroids: Vec<[f64; 3]> = (0..n).map(|t| centroid(target.corners(t))).collect();
    let mut beyond = vec![false; n];
    let mut seen = vec![false; n];
    let mut border_seen = vec![false; n];
    for start in 0..n {
        if paired[start] || seen[start] {
            continue;
        }
        seen[start] = true;
        let (mut region, mut border) = (vec![start], Vec::new());
        let mut k = 0;
        while k < region.len() {
            let t = region[k];
            k += 1;
            for &u in adjacency.of(t) {
                let u = u as usize;
                if paired[u] {
                    if !std::mem::replace(&mut border_seen[u], true) {
                        border.push(u);
                    }
                } else if !std::mem::replace(&mut seen[u], true) {
                    region.push(u);
                }
            }
        }
        for &u in &border {
            border_seen[u] = false;
        }
        let out = border.is_empty()
            || border
                .iter()
                .any(|&u| pairs.of(u).iter().any(|&(s, _)| rim_source(s)))
            || {
                let mut centre = [0.0; 3];
                for &u in &border {
                    centre = crate::linalg::vector::add(centre, centroids[u]);
                }
                let centre = centre.map(|x| x / border.len() as f64);
                // Half the width of the paired surface around the region.
                let span = border
                    .iter()
                    .map(|&u| norm(sub(centroids[u], centre)))
                    .fold(0.0, f64::max);
                let tree = rstar::RTree::bulk_load(
                    border
                        .iter()
                        .map(|&u| GeomWithData::new(centroids[u], ()))
                        .collect(),
                );
                region.iter().any(|&t| {
                    tree.nearest_neighbor_iter_with_distance_2(centroids[t])
                        .next()
                        .is_some_and(|(_, d2)| d2 > 4.0 * span * span)
                })
            };
        if out {
            for t in region {
                beyond[t] = true;
            }
        }
    }
    beyond
}

/// The user's pins, checked.
fn target_pins(pins: &[(u32, [f64; 3])], n: usize) -> Result<Pins<3>> {
    let mut out = Pins::new(n);
    for &(v, p) in pins {
        let v = v as usize;
        if v >= n || out.is_pinned(v) {
            return Err(Error::InvalidArgument(format!(
                "pinned target vertex {v} is out of range (the target has {n} vertices) or repeated"
            )));
        }
        if p.iter().any(|c| !c.is_finite()) {
            return Err(Error::InvalidArgument(format!(
                "pinned target vertex {v} has a non-finite position"
            )));
        }
        let pinned = out.pin(v, p);
        debug_assert!(pinned);
    }
    Ok(out)
}

/// For each paired part that follows the main part (and is not held by a
/// pin): the pairs of the triangles around its anchors, with the anchors'
/// rest offsets from their source triangles.
fn following_anchors(
    carried: &CarriedParts,
    components: &Components,
    placement: &Placement<3>,
    pairs: &PairsByTarget,
    source_ref: &Mesh3,
    target_ref: &Mesh3,
) -> Vec<FollowingAnchors> {
    if carried.following().is_empty() {
        return Vec::new();
    }
    let mut placed_part = vec![None; components.count];
    for (v, c) in components.of_vertex.iter().enumerate() {
        if let Some(c) = c {
            placed_part[*c as usize] = placement.part_of_vertex(v);
        }
    }
    let mut out = Vec::new();
    let mut followers_of = vec![Vec::new(); target_ref.num_vertices()];
    for f in carried.following() {
        let Some(part) = placed_part[f.component as usize] else {
            continue;
        };
        for &a in &f.anchors {
            followers_of[a as usize].push(out.len());
        }
        out.push(FollowingAnchors {
            part,
            pairs: Vec::new(),
            offsets: Vec::new(),
        });
    }
    for (t, tri) in target_ref.triangles().iter().enumerate() {
        for &a in tri {
            for &f in &followers_of[a as usize] {
                for &(s, w) in pairs.of(t) {
                    let cs = centroid(source_ref.corners(s as usize));
                    let p = target_ref.positions()[a as usize];
                    out[f].pairs.push((s, a, w));
                    out[f].offsets.push(std::array::from_fn(|i| p[i] - cs[i]));
                }
            }
        }
    }
    out
}

/// For each placed part: its pairs with their rest offsets, and its rest
/// centroid.
fn part_anchors(
    placement: &Placement<3>,
    pairs: &PairsByTarget,
    source_ref: &Mesh3,
    target_ref: &Mesh3,
) -> Vec<PartAnchor> {
    let mut anchors = vec![PartAnchor::default(); placement.count()];
    for (t, tri) in target_ref.triangles().iter().enumerate() {
        let Some(part) = placement.part_of_vertex(tri[0] as usize) else {
            continue;
        };
        let anchor = &mut anchors[part];
        for &(s, w) in pairs.of(t) {
            let (cs, ct) = (
                centroid(source_ref.corners(s as usize)),
                centroid(target_ref.corners(t)),
            );
            anchor.pairs.push((s, t as u32, w));
            anchor.offsets.push(std::array::from_fn(|i| ct[i] - cs[i]));
        }
    }
    let mut rest = vec![[0.0; 3]; placement.count()];
    placement.centroids(target_ref.positions(), &mut rest);
    for (anchor, c) in anchors.iter_mut().zip(rest) {
        anchor.target_rest = c;
    }
    anchors
}
