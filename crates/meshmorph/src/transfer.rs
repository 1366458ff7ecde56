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
//! Target triangles in no pair take the deformation of their neighbours
//! (a smoothness term across their edges). Those that cannot reach a paired
//! triangle across edges also get a faint pull towards their rest shape, so
//! that a part with no pair at all keeps its shape; the pull is left out
//! elsewhere, where it would bias the result towards the rest pose.
//!
//! The energy does not see translations. Each connected part of the target
//! is placed so that, in the area-weighted mean over its pairs, the centroid
//! of each paired target triangle sits where the centroid of its source
//! triangle went, plus their offset in the references carried by that source
//! triangle's deformation gradient. The output does not drift, and a rigid
//! (or affine) motion of the whole source moves the target by the same
//! motion, wherever the target lies. A part without pairs stays where it is.
//! Pinned target vertices ([`TransferOptions::pins`]) replace that placement
//! for the parts they are in.
#![allow(non_snake_case)]

use rayon::prelude::*;

use crate::correspondence::Correspondence;
use crate::error::{Error, Result};
use crate::frames::{deformation_gradient, frame_inverses, GradientOperators, Mat3, IDENTITY};
use crate::geometry::centroid;
use crate::mesh::Mesh3;
use crate::similarity::Similarity;
use crate::solve::{FactorKind, PinnedSystem, SymmetricBuilder, Workspace};
use crate::topology::{connected_components, edges, TriangleAdjacency};

/// Options of [`Transfer::new`].
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct TransferOptions {
    /// Target vertices held at the given positions in every pose. The parts
    /// of the target that hold a pinned vertex are not moved by the centroid
    /// rule. Default: none.
    pub pins: Vec<(u32, [f64; 3])>,
    /// Which Cholesky variant factors the system. Default [`FactorKind::Auto`].
    pub factor: FactorKind,
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

/// Weight pulling unpaired target triangles that reach no paired triangle
/// across edges towards their rest shape, relative to the weight 1 of a pair
/// and of a smoothness term.
const UNPAIRED_REST_WEIGHT: f64 = 1e-6;

/// Deformation transfer from one source reference to one target reference,
/// factored once; see the [module documentation](self).
#[derive(Debug)]
pub struct Transfer {
    /// What brings the source onto the target (applied to every pose).
    alignment: Similarity,
    /// The source reference, aligned (its connectivity checks poses).
    source_ref: Mesh3,
    /// `V⁻¹` of every source reference triangle.
    source_frames_inv: Vec<Mat3>,
    target_vertices: usize,
    target_triangles: Vec<[u32; 3]>,
    /// `G = D V⁻¹` of every target reference triangle.
    target_gradients: GradientOperators,
    /// `(source triangle, weight)` of the pairs of each target triangle,
    /// compressed rows.
    paired_ptr: Vec<usize>,
    paired: Vec<(u32, f64)>,
    /// Constant part of the right-hand side (rest pull of unpaired triangles).
    rhs_rest: Vec<f64>,
    system: PinnedSystem,
    /// Column-major `#pinned × 3` values.
    pinned_values: Vec<f64>,
    placements: Vec<Placement>,
    /// Part of each target vertex, `u32::MAX` if it is not moved by a placement.
    vertex_part: Vec<u32>,
    /// Area weight of each target vertex.
    vertex_weight: Vec<f64>,
}

/// How one connected part of the target is placed.
#[derive(Clone, Debug)]
struct Placement {
    /// The pairs `(source triangle, target triangle, weight)` in the part.
    pairs: Vec<(u32, u32, f64)>,
    /// For each pair, the offset from the centroid of its source triangle to
    /// the centroid of its target triangle in the references.
    offsets: Vec<[f64; 3]>,
    /// Sum of the pair weights.
    pair_weight: f64,
    /// The part's own area-weighted centroid in the target reference, where
    /// a part without pairs stays.
    target_rest: [f64; 3],
    total_weight: f64,
}

/// Per-thread scratch for [`Transfer::apply_into`].
#[derive(Debug)]
pub struct PoseWorkspace {
    solve: Workspace,
    /// The pose brought onto the target by the alignment.
    aligned: Vec<[f64; 3]>,
    gradients: Vec<Mat3>,
    rhs: Vec<f64>,
    x: Vec<f64>,
    /// One vector per placed part: its centroid, then its shift.
    parts: Vec<[f64; 3]>,
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
        let (n, tris) = (target_ref.num_vertices(), target_ref.triangles());
        let m = n + tris.len();
        let source_frames_inv = frame_inverses(source_ref, "source reference")?;
        let target_gradients = GradientOperators::new(target_ref, "target reference")?;
        let unknowns = |t: usize| target_gradients.unknowns(t);

        // Pairs grouped by target triangle.
        let mut paired_ptr = vec![0usize; tris.len() + 1];
        for p in correspondence.pairs() {
            paired_ptr[p[1] as usize + 1] += 1;
        }
        for t in 0..tris.len() {
            paired_ptr[t + 1] += paired_ptr[t];
        }
        let count = |t: usize| paired_ptr[t + 1] - paired_ptr[t];
        // Each target triangle counts in proportion to its area (normalised
        // by the mean area) and takes the area-weighted mean gradient of its
        // partners: pair (s, t) weighs weight_t · area_s / Σ area_partners.
        let target_areas: Vec<f64> = target_ref.triangle_areas();
        let mean_area = target_areas.iter().sum::<f64>() / target_areas.len() as f64;
        let weight: Vec<f64> = target_areas.iter().map(|a| a / mean_area).collect();
        let source_areas = source_ref.triangle_areas();
        let mut fill = paired_ptr.clone();
        let mut paired = vec![(0u32, 0.0); correspondence.pairs().len()];
        for p in correspondence.pairs() {
            paired[fill[p[1] as usize]] = (p[0], source_areas[p[0] as usize]);
            fill[p[1] as usize] += 1;
        }
        for t in 0..tris.len() {
            let partners = &mut paired[paired_ptr[t]..paired_ptr[t + 1]];
            let total: f64 = partners.iter().map(|p| p.1).sum();
            partners.iter_mut().for_each(|p| p.1 *= weight[t] / total);
        }

        // Unpaired triangles that reach a paired one across edges take its
        // deformation through the smoothness terms; only those that reach
        // none need the rest pull (which would bias the others towards the
        // identity: a rotated source would give a target not quite rotated).
        let tri_edges = edges(tris);
        let adjacency = TriangleAdjacency::from_edges(tris.len(), &tri_edges);
        let mut reached: Vec<bool> = (0..tris.len()).map(|t| count(t) > 0).collect();
        let mut stack: Vec<usize> = (0..tris.len()).filter(|&t| reached[t]).collect();
        while let Some(t) = stack.pop() {
            for &u in adjacency.of(t) {
                if !std::mem::replace(&mut reached[u as usize], true) {
                    stack.push(u as usize);
                }
            }
        }

        let mut builder = SymmetricBuilder::new(m, 12 * tris.len());
        let mut rhs_rest = vec![0.0; 3 * m];
        for t in 0..tris.len() {
            if count(t) > 0 {
                builder.add_gram(&unknowns(t), target_gradients.operator(t), weight[t]);
            } else if !reached[t] {
                let w = UNPAIRED_REST_WEIGHT * weight[t];
                target_gradients.add_target(&mut builder, &mut rhs_rest, t, &IDENTITY, w);
            }
        }
        for e in &tri_edges {
            for (k, &a) in e.triangles.iter().enumerate() {
                for &b in &e.triangles[k + 1..] {
                    let (a, b) = (a as usize, b as usize);
                    if count(a) == 0 || count(b) == 0 {
                        target_gradients.add_difference(
                            &mut builder,
                            a,
                            b,
                            0.5 * (weight[a] + weight[b]),
                        );
                    }
                }
            }
        }

        // Translation: pins, else one held vertex per part, moved afterwards.
        let components = connected_components(n, tris);
        let mut pinned: Vec<usize> = Vec::new();
        let mut values: Vec<[f64; 3]> = Vec::new();
        let mut pinned_part = vec![false; components.count];
        let mut is_pinned = vec![false; n];
        for &(v, p) in &options.pins {
            let v = v as usize;
            if v >= n || is_pinned[v] {
                return Err(Error::InvalidArgument(format!(
                    "pinned target vertex {v} is out of range (the target has {n} vertices) or repeated"
                )));
            }
            if p.iter().any(|c| !c.is_finite()) {
                return Err(Error::InvalidArgument(format!(
                    "pinned target vertex {v} has a non-finite position"
                )));
            }
            is_pinned[v] = true;
            pinned.push(v);
            values.push(p);
            if let Some(c) = components.of_vertex[v] {
                pinned_part[c as usize] = true;
            }
        }
        let mut anchored = pinned_part.clone();
        for (v, c) in components.of_vertex.iter().enumerate() {
            let hold = match c {
                Some(c) => !std::mem::replace(&mut anchored[*c as usize], true),
                None => !is_pinned[v],
            };
            if hold {
                pinned.push(v);
                values.push(target_ref.positions()[v]);
            }
        }
        let system = PinnedSystem::new(&builder.build(), &pinned, options.factor)?;
        let np = pinned.len();
        let mut pinned_values = vec![0.0; 3 * np];
        for (q, p) in values.iter().enumerate() {
            for i in 0..3 {
                pinned_values[i * np + q] = p[i];
            }
        }

        // Placement of each part not held by a pin.
        let mut vertex_weight = vec![0.0; n];
        for (tri, a) in tris.iter().zip(&target_areas) {
            for &v in tri {
                vertex_weight[v as usize] += a / 3.0;
            }
        }
        let mut placements: Vec<Placement> = Vec::new();
        let mut part_slot = vec![u32::MAX; components.count];
        for c in 0..components.count {
            if !pinned_part[c] {
                part_slot[c] = placements.len() as u32;
                placements.push(Placement {
                    pairs: Vec::new(),
                    offsets: Vec::new(),
                    pair_weight: 0.0,
                    target_rest: [0.0; 3],
                    total_weight: 0.0,
                });
            }
        }
        for (t, partners) in paired_ptr
            .windows(2)
            .map(|r| &paired[r[0]..r[1]])
            .enumerate()
        {
            let slot = part_slot[components.of_triangle[t] as usize];
            for &(s, w) in partners.iter().filter(|_| slot != u32::MAX) {
                let pl = &mut placements[slot as usize];
                let (cs, ct) = (
                    centroid(source_ref.corners(s as usize)),
                    centroid(target_ref.corners(t)),
                );
                pl.pairs.push((s, t as u32, w));
                pl.offsets.push(std::array::from_fn(|i| ct[i] - cs[i]));
                pl.pair_weight += w;
            }
        }
        let vertex_part: Vec<u32> = components
            .of_vertex
            .iter()
            .map(|c| c.map_or(u32::MAX, |c| part_slot[c as usize]))
            .collect();
        let mut weights = vec![0.0; placements.len()];
        for v in 0..n {
            if vertex_part[v] != u32::MAX {
                let pl = &mut placements[vertex_part[v] as usize];
                for i in 0..3 {
                    pl.target_rest[i] += vertex_weight[v] * target_ref.positions()[v][i];
                }
                weights[vertex_part[v] as usize] += vertex_weight[v];
            }
        }
        for (pl, w) in placements.iter_mut().zip(weights) {
            pl.total_weight = w;
            pl.target_rest = pl.target_rest.map(|x| x / w);
        }

        Ok(Self {
            alignment,
            source_ref: source_ref.clone(),
            source_frames_inv,
            target_vertices: n,
            target_triangles: tris.to_vec(),
            target_gradients,
            paired_ptr,
            paired,
            rhs_rest,
            system,
            pinned_values,
            placements,
            vertex_part,
            vertex_weight,
        })
    }

    /// The target's triangles, shared by every output.
    pub fn target_triangles(&self) -> &[[u32; 3]] {
        &self.target_triangles
    }

    /// Scratch for [`Transfer::apply_into`]; one per thread.
    pub fn workspace(&self) -> PoseWorkspace {
        let m = self.target_vertices + self.target_triangles.len();
        PoseWorkspace {
            solve: self.system.workspace(3),
            aligned: Vec::new(),
            gradients: vec![[[0.0; 3]; 3]; self.source_ref.num_triangles()],
            rhs: vec![0.0; 3 * m],
            x: vec![0.0; 3 * m],
            parts: vec![[0.0; 3]; self.placements.len()],
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
        let mut out = vec![[0.0; 3]; self.target_vertices];
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
                    let mut out = vec![[0.0; 3]; self.target_vertices];
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
            self.target_vertices,
            "output has the wrong number of vertices"
        );
        let n = self.target_vertices;
        let m = n + self.target_triangles.len();
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
        ws.rhs.copy_from_slice(&self.rhs_rest);
        for t in 0..self.target_triangles.len() {
            let sources = &self.paired[self.paired_ptr[t]..self.paired_ptr[t + 1]];
            if sources.is_empty() {
                continue;
            }
            let mut sum = [[0.0; 3]; 3];
            for &(s, w) in sources {
                let Q = &ws.gradients[s as usize];
                for i in 0..3 {
                    for j in 0..3 {
                        sum[i][j] += w * Q[i][j];
                    }
                }
            }
            self.target_gradients
                .add_target_rhs(&mut ws.rhs, t, &sum, 1.0);
        }
        self.system
            .solve(&ws.rhs, Some(&self.pinned_values), &mut ws.x, &mut ws.solve);
        for (v, o) in out.iter_mut().enumerate() {
            *o = [ws.x[v], ws.x[m + v], ws.x[2 * m + v]];
        }
        self.place(pose, &ws.gradients, out, &mut ws.parts);
        ws.aligned = aligned;
    }

    /// Moves each unpinned part so that its paired triangles' centroids
    /// follow those of their source triangles: each at its source triangle's
    /// centroid in `pose` plus the rest offset between the two mapped by the
    /// source triangle's deformation gradient, in the weighted mean over the
    /// pairs. A rigid (or affine) motion of the source thus moves the target
    /// by the same motion. A part without pairs stays where it is.
    fn place(
        &self,
        pose: &[[f64; 3]],
        gradients: &[Mat3],
        out: &mut [[f64; 3]],
        parts: &mut [[f64; 3]],
    ) {
        parts.fill([0.0; 3]);
        for (v, p) in out.iter().enumerate() {
            let c = self.vertex_part[v];
            if c != u32::MAX {
                for i in 0..3 {
                    parts[c as usize][i] += self.vertex_weight[v] * p[i];
                }
            }
        }
        for (pl, part) in self.placements.iter().zip(parts.iter_mut()) {
            if pl.pairs.is_empty() {
                *part = std::array::from_fn(|i| pl.target_rest[i] - part[i] / pl.total_weight);
                continue;
            }
            let mut shift = [0.0; 3];
            for (&(s, t, w), o) in pl.pairs.iter().zip(&pl.offsets) {
                let cs =
                    centroid(self.source_ref.triangles()[s as usize].map(|v| pose[v as usize]));
                let ct = centroid(self.target_triangles[t as usize].map(|v| out[v as usize]));
                let Q = &gradients[s as usize];
                for i in 0..3 {
                    let moved = Q[i][0] * o[0] + Q[i][1] * o[1] + Q[i][2] * o[2];
                    shift[i] += w * (cs[i] + moved - ct[i]);
                }
            }
            *part = shift.map(|x| x / pl.pair_weight);
        }
        for (v, p) in out.iter_mut().enumerate() {
            let c = self.vertex_part[v];
            if c != u32::MAX {
                for i in 0..3 {
                    p[i] += parts[c as usize][i];
                }
            }
        }
    }
}
