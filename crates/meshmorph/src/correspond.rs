//! Triangle correspondence between a source and a target mesh from a few
//! marker vertex pairs (Sumner and Popović 2004, section 5).
//!
//! 0. Unless [`CorrespondOptions::align`] is off, the source reference is
//!    first brought onto the target reference by the similarity (rotation,
//!    uniform scale, translation) that best fits the marker pairs
//!    ([`Similarity::fit`]): moving, turning or scaling the source changes
//!    nothing. The similarity is kept in the [`Correspondence`], and
//!    [`Transfer`](crate::Transfer) applies it to every pose.
//! 1. The source reference is deformed onto the target reference by
//!    minimising `w_S E_S + w_I E_I + w_C E_C` over its vertices and fourth
//!    vertices, markers held at their target positions: `E_S` asks
//!    neighbouring triangles to deform alike, `E_I` asks every deformation
//!    gradient to stay near the identity and `E_C` pulls every vertex to the
//!    closest compatible point of the target. A first round runs without
//!    `E_C`; then `w_C` grows round by round, closest points found afresh.
//! 2. Triangles of the deformed source and of the target are paired with the
//!    closest compatible triangle of the other mesh (centroids within a
//!    threshold, normals less than 90° apart), in both directions.
#![allow(non_snake_case)]

use rayon::prelude::*;

use crate::closest::{unit_normal, vertex_normals, CentroidIndex, SurfaceIndex};
use crate::correspondence::Correspondence;
use crate::error::{Error, Result};
use crate::frames::{GradientOperators, IDENTITY};
use crate::geometry::centroid;
use crate::markers::Markers;
use crate::mesh::Mesh3;
use crate::similarity::{residuals, Similarity};
use crate::solve::{FactorKind, PinnedSystem, SymmetricBuilder};
use crate::topology::{connected_components, edges};

/// Options of [`correspond`]; the defaults follow the paper.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct CorrespondOptions {
    /// `w_S`, weight of the smoothness term. Default 1.
    pub smoothness_weight: f64,
    /// `w_I`, weight of the identity term. Default 0.001.
    pub identity_weight: f64,
    /// `w_C` of each closest-point round, in order (a first round without
    /// closest points always runs before them). Default `[1, 1667.33,
    /// 3333.67, 5000]`: from 1 to 5000 in four steps.
    pub closest_weights: Vec<f64>,
    /// Largest distance to a closest point, as a fraction of the target's
    /// bounding-box diagonal; farther vertices are not pulled. Default 0.02.
    pub closest_cutoff: f64,
    /// Largest centroid distance of a matched triangle pair, as a fraction of
    /// the target's bounding-box diagonal, but never less than the mean edge
    /// length of either mesh. Default 0.01: pairs farther apart
    /// than that are more often wrong than right, and a target triangle left
    /// without a pair takes its neighbours' deformation in the transfer.
    pub match_threshold: f64,
    /// Bring the source onto the target by the similarity that best fits
    /// the markers before anything else. Default `true`; off, the two
    /// references must already overlap.
    pub align: bool,
}

impl Default for CorrespondOptions {
    fn default() -> Self {
        Self {
            smoothness_weight: 1.0,
            identity_weight: 0.001,
            closest_weights: (0..4)
                .map(|k| 1.0 + (5000.0 - 1.0) * k as f64 / 3.0)
                .collect(),
            closest_cutoff: 0.02,
            match_threshold: 0.01,
            align: true,
        }
    }
}

impl CorrespondOptions {
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
    /// The source reference deformed onto the target reference.
    pub deformed_source: Mesh3,
    /// The distance between each marker's target vertex and its source
    /// vertex brought onto the target by the alignment (in the order of the
    /// markers; the misfit of the similarity, in the target's units).
    pub marker_residuals: Vec<f64>,
}

/// The fewest markers [`correspond`] accepts: fewer cannot fix an orientation.
pub const MIN_MARKERS: usize = 3;

/// Computes the triangle correspondence between `source` and `target` from
/// `markers`. `progress` is called with the number of steps done out of
/// [`correspond_steps`].
///
/// # Errors
/// - [`Error::InvalidArgument`] for bad markers (out of range, repeated, a
///   source vertex with two targets), fewer than [`MIN_MARKERS`], or a
///   connected part of the source without a marker;
/// - [`Error::DegenerateTriangles`] for zero-area triangles in either mesh;
/// - [`Error::Solver`] if a system cannot be factored.
pub fn correspond(
    source: &Mesh3,
    target: &Mesh3,
    markers: &Markers,
    options: &CorrespondOptions,
    progress: &mut dyn FnMut(usize),
) -> Result<CorrespondResult> {
    options.validate()?;
    markers.validate(source.num_vertices(), target.num_vertices())?;
    if markers.pairs().len() < MIN_MARKERS {
        return Err(Error::InvalidArgument(format!(
            "{} marker pair{} given: correspondence needs at least {MIN_MARKERS}",
            markers.pairs().len(),
            if markers.pairs().len() == 1 { "" } else { "s" }
        )));
    }
    source.check_no_degenerate_triangles("source reference")?;
    target.check_no_degenerate_triangles("target reference")?;
    let components = connected_components(source.num_vertices(), source.triangles());
    let mut held = vec![false; components.count];
    for &[s, _] in markers.pairs() {
        if let Some(c) = components.of_vertex[s as usize] {
            held[c as usize] = true;
        }
    }
    if let Some(c) = held.iter().position(|h| !h) {
        let t = components
            .of_triangle
            .iter()
            .position(|&x| x as usize == c)
            .unwrap_or(0);
        return Err(Error::InvalidArgument(format!(
            "part {c} of the source reference (the connected triangles around triangle {t}) has no \
             marker: every connected part needs at least one"
        )));
    }

    let marker_points = |mesh: &Mesh3, k: usize| -> Vec<[f64; 3]> {
        markers
            .pairs()
            .iter()
            .map(|p| mesh.positions()[p[k] as usize])
            .collect()
    };
    let (from, to) = (marker_points(source, 0), marker_points(target, 1));
    let alignment = if options.align {
        Similarity::fit(&from, &to)?
    } else {
        Similarity::IDENTITY
    };
    let marker_residuals = residuals(&alignment, &from, &to);
    let aligned;
    let source = if alignment.is_identity() {
        source
    } else {
        aligned = source.with_positions(alignment.apply_all(source.positions()))?;
        &aligned
    };
    let deformed = deform(source, target, markers, options, progress)?;
    let deformed_source = source.with_positions(deformed)?;
    // Centroids of two differently tessellated surfaces lie up to about an
    // edge apart even where the surfaces coincide: never ask for less.
    let threshold = (options.match_threshold * target.bounding_box_diagonal())
        .max(mean_edge_length(&deformed_source))
        .max(mean_edge_length(target));
    let correspondence =
        match_triangles(&deformed_source, target, threshold).with_alignment(alignment);
    progress(correspond_steps(options));
    Ok(CorrespondResult {
        correspondence,
        deformed_source,
        marker_residuals,
    })
}

/// Mean length of the edges of a mesh.
pub fn mean_edge_length(mesh: &Mesh3) -> f64 {
    let e = edges(mesh.triangles());
    let p = mesh.positions();
    let total: f64 = e
        .iter()
        .map(|e| {
            crate::geometry::norm(crate::geometry::sub(
                p[e.vertices[0] as usize],
                p[e.vertices[1] as usize],
            ))
        })
        .sum();
    total / e.len().max(1) as f64
}

/// Number of steps [`correspond`] reports: each deformation round, then matching.
pub fn correspond_steps(options: &CorrespondOptions) -> usize {
    options.closest_weights.len() + 2
}

/// Deforms the source onto the target; returns the deformed vertex positions.
fn deform(
    source: &Mesh3,
    target: &Mesh3,
    markers: &Markers,
    options: &CorrespondOptions,
    progress: &mut dyn FnMut(usize),
) -> Result<Vec<[f64; 3]>> {
    let (n, tris) = (source.num_vertices(), source.triangles());
    let m = n + tris.len();
    let ops = GradientOperators::new(source, "source reference")?;
    // Every term counts in proportion to the area it covers (normalised by
    // the mean area), so the energy does not depend on the tessellation.
    let areas = source.triangle_areas();
    let mean_area = areas.iter().sum::<f64>() / areas.len() as f64;
    let aw = |t: usize| areas[t] / mean_area;
    // The closest-point term weighs each vertex by its share of the area,
    // normalised to a mean of 1 over the vertices.
    let mut vertex_weight = vec![0.0; n];
    for (t, tri) in tris.iter().enumerate() {
        for &v in tri {
            vertex_weight[v as usize] += aw(t) / 3.0;
        }
    }
    let mean_weight = vertex_weight.iter().sum::<f64>() / n as f64;
    vertex_weight.iter_mut().for_each(|w| *w /= mean_weight);
    let mut base = SymmetricBuilder::new(m, 40 * tris.len());
    for v in 0..m {
        base.add(v, v, 0.0);
    }
    let mut rhs_identity = vec![0.0; 3 * m];
    for e in edges(tris) {
        for (k, &a) in e.triangles.iter().enumerate() {
            for &b in &e.triangles[k + 1..] {
                let (a, b) = (a as usize, b as usize);
                ops.add_difference(
                    &mut base,
                    a,
                    b,
                    options.smoothness_weight * 0.5 * (aw(a) + aw(b)),
                );
            }
        }
    }
    for t in 0..tris.len() {
        ops.add_target(
            &mut base,
            &mut rhs_identity,
            t,
            &IDENTITY,
            options.identity_weight * aw(t),
        );
    }
    let base = base.build();

    // In a fixed order: the solve sums the pinned values' contributions in
    // this order, and the last bits of the result decide ties in matching.
    let mut pairs = markers.pairs().to_vec();
    pairs.sort_unstable();
    // Markers are held at their targets; vertices no triangle uses (and no
    // marker names) have no term at all and stay where they are.
    let mut held: Vec<(usize, [f64; 3])> = pairs
        .iter()
        .map(|&[s, t]| (s as usize, target.positions()[t as usize]))
        .collect();
    let mut is_marker = vec![false; n];
    pairs.iter().for_each(|p| is_marker[p[0] as usize] = true);
    let mut used = vec![false; n];
    tris.iter().flatten().for_each(|&v| used[v as usize] = true);
    held.extend(
        (0..n)
            .filter(|&v| !used[v] && !is_marker[v])
            .map(|v| (v, source.positions()[v])),
    );
    let pinned: Vec<usize> = held.iter().map(|h| h.0).collect();
    let np = pinned.len();
    let mut pinned_values = vec![0.0; 3 * np];
    for (q, (_, p)) in held.iter().enumerate() {
        for i in 0..3 {
            pinned_values[i * np + q] = p[i];
        }
    }

    let surface = SurfaceIndex::new(target.positions(), target.triangles());
    let cutoff = options.closest_cutoff * target.bounding_box_diagonal();
    let mut x = vec![0.0; 3 * m];
    let mut positions: Vec<[f64; 3]> = source.positions().to_vec();
    let rounds = std::iter::once(0.0).chain(options.closest_weights.iter().copied());
    let mut system: Option<PinnedSystem> = None;
    for (round, w_c) in rounds.enumerate() {
        let mut rhs = rhs_identity.clone();
        let matrix = if w_c > 0.0 {
            let normals = vertex_normals(&positions, tris);
            let targets: Vec<Option<[f64; 3]>> = (0..n)
                .into_par_iter()
                .map(|v| {
                    surface
                        .closest_compatible(positions[v], normals[v], cutoff)
                        .map(|c| c.point)
                })
                .collect();
            let mut diagonal = vec![0.0; m];
            for (v, c) in targets.iter().enumerate() {
                if let Some(c) = c {
                    let w = w_c * vertex_weight[v];
                    diagonal[v] = w;
                    for i in 0..3 {
                        rhs[i * m + v] += w * c[i];
                    }
                }
            }
            let mut matrix = base.clone();
            matrix.add_to_diagonal(&diagonal);
            matrix
        } else {
            base.clone()
        };
        // One factorization per round, each used once: the supernodal factor
        // is the faster one then, and the symbolic analysis is shared.
        let system = match &mut system {
            Some(system) => {
                system.refactor(&matrix)?;
                system
            }
            None => system.insert(PinnedSystem::new(&matrix, &pinned, FactorKind::Supernodal)?),
        };
        let mut ws = system.workspace(3);
        system.solve(&rhs, Some(&pinned_values), &mut x, &mut ws);
        positions = (0..n).map(|v| [x[v], x[m + v], x[2 * m + v]]).collect();
        if positions.iter().flatten().any(|c| !c.is_finite()) {
            return Err(Error::Solver(
                "the deformation produced non-finite positions".into(),
            ));
        }
        progress(round + 1);
    }
    Ok(positions)
}

/// Pairs each triangle of `source` with the nearest compatible triangle of
/// `target` (centroids within `threshold`, normals less than 90° apart) and
/// each triangle of `target` with the nearest compatible one of `source`.
/// The union of both, sorted, is the map.
pub fn match_triangles(source: &Mesh3, target: &Mesh3, threshold: f64) -> Correspondence {
    let query = |from: &Mesh3, to: &Mesh3| -> Vec<Option<u32>> {
        let index = CentroidIndex::new(to.positions(), to.triangles());
        (0..from.num_triangles())
            .into_par_iter()
            .map(|t| {
                let p = from.corners(t);
                index.nearest_compatible(centroid(p), unit_normal(p), threshold)
            })
            .collect()
    };
    let forward = query(source, target);
    let backward = query(target, source);
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
    Correspondence::new(pairs, source, target)
}
