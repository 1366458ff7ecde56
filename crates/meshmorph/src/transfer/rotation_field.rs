//! A rotation for every triangle, spread from the triangles whose rotation
//! is known to the others.
//!
//! Deformation transfer knows the deformation of the target triangles that
//! have a source partner. Those without one (the back of a head under a face
//! mask, a neck) should keep their rest shape yet follow the motion: each is
//! held to its rest shape turned by a rotation taken from the known ones.
//! The rotations are spread by harmonic interpolation over the triangles'
//! adjacency (each unknown matrix the weighted mean of its neighbours', the
//! known ones held), then each matrix is projected onto the closest rotation.
//! The interpolation is linear: its system depends on which triangles are
//! known only, so it is factored once, and each pose is a back-substitution
//! with nine right-hand sides. A rigid motion of every known triangle (all
//! rotations equal) gives that rotation everywhere.

#![allow(non_snake_case)]

use crate::error::Result;
use crate::gradient::solve::{FactorKind, PinnedSystem, SymmetricBuilder, Workspace};
use crate::linalg::matrix::{identity, Mat3};
use crate::linalg::similarity::closest_rotation;
use crate::mesh::topology::TriangleAdjacency;

/// The factored interpolation of rotations from known triangles.
#[derive(Debug)]
pub struct RotationField {
    /// The system over every triangle, known ones (and those that reach no
    /// known one, which stay unrotated) pinned. `None` when nothing is
    /// unknown.
    system: Option<PinnedSystem>,
    /// Pinned triangles, in the system's order, and whether each is known
    /// (else it is held at the identity).
    pinned: Vec<(u32, bool)>,
    /// The triangles to fill.
    unknown: Vec<u32>,
    /// The known triangles next to an unknown one: the only known rotations
    /// the spread needs.
    boundary: Vec<u32>,
    /// Where each boundary triangle is among the pinned ones.
    boundary_slots: Vec<u32>,
    /// Pinned slots of the triangles that reach no known one.
    unreached: Vec<u32>,
    num_triangles: usize,
}

/// Per-thread scratch of [`RotationField::fill`].
#[derive(Debug)]
pub struct FieldWorkspace {
    solve: Option<Workspace>,
    pinned_values: Vec<f64>,
    rhs: Vec<f64>,
    x: Vec<f64>,
}

impl RotationField {
    /// Prepares the spread over `adjacency` from the triangles where
    /// `known[t]`; `weight[t]` is each triangle's weight (its area share),
    /// an edge weighing the mean of its two triangles'.
    ///
    /// # Errors
    /// [`crate::Error::Solver`] if the system cannot be factored.
    pub fn new(adjacency: &TriangleAdjacency, known: &[bool], weight: &[f64]) -> Result<Self> {
        let n = known.len();
        // Triangles that reach a known one through unknown ones.
        let mut reached = known.to_vec();
        let mut stack: Vec<usize> = (0..n).filter(|&t| known[t]).collect();
        while let Some(t) = stack.pop() {
            for &u in adjacency.of(t) {
                if !std::mem::replace(&mut reached[u as usize], true) {
                    stack.push(u as usize);
                }
            }
        }
        let unknown: Vec<u32> = (0..n as u32)
            .filter(|&t| !known[t as usize] && reached[t as usize])
            .collect();
        let pinned: Vec<(u32, bool)> = (0..n as u32)
            .filter(|&t| known[t as usize] || !reached[t as usize])
            .map(|t| (t, known[t as usize]))
            .collect();
        let boundary: Vec<u32> = (0..n as u32)
            .filter(|&t| {
                known[t as usize]
                    && adjacency
                        .of(t as usize)
                        .iter()
                        .any(|&u| !known[u as usize] && reached[u as usize])
            })
            .collect();
        if unknown.is_empty() {
            return Ok(Self {
                system: None,
                pinned,
                unknown,
                boundary,
                boundary_slots: Vec::new(),
                unreached: Vec::new(),
                num_triangles: n,
            });
        }
        let mut builder = SymmetricBuilder::new(n, 4 * adjacency.neighbors.len() + n);
        for t in 0..n {
            builder.add(t, t, 0.0);
            for &u in adjacency.of(t) {
                let u = u as usize;
                if u > t {
                    let w = 0.5 * (weight[t] + weight[u]);
                    builder.add_row_outer(&[(t, 1.0), (u, -1.0)], w);
                }
            }
        }
        let indices: Vec<usize> = pinned.iter().map(|p| p.0 as usize).collect();
        let system = PinnedSystem::new(&builder.build(), &indices, FactorKind::Auto)?;
        let mut slot = vec![u32::MAX; n];
        for (q, p) in pinned.iter().enumerate() {
            slot[p.0 as usize] = q as u32;
        }
        let boundary_slots = boundary.iter().map(|&t| slot[t as usize]).collect();
        let unreached = pinned
            .iter()
            .enumerate()
            .filter(|(_, p)| !p.1)
            .map(|(q, _)| q as u32)
            .collect();
        Ok(Self {
            system: Some(system),
            pinned,
            unknown,
            boundary,
            boundary_slots,
            unreached,
            num_triangles: n,
        })
    }

    /// Scratch for [`RotationField::fill`]; one per thread.
    pub fn workspace(&self) -> FieldWorkspace {
        let n = self.num_triangles;
        FieldWorkspace {
            solve: self.system.as_ref().map(|s| s.workspace(9)),
            pinned_values: vec![0.0; 9 * self.pinned.len()],
            rhs: vec![0.0; 9 * n],
            x: vec![0.0; 9 * n],
        }
    }

    /// Writes a rotation into `rotations[t]` for every triangle of
    /// [`RotationField::filled`], spread from the known rotations, which
    /// `known_rotation(t)` gives (it is asked only for known triangles next
    /// to unknown ones).
    pub fn fill(
        &self,
        known_rotation: impl Fn(usize) -> Mat3,
        rotations: &mut [Mat3],
        ws: &mut FieldWorkspace,
    ) {
        let Some(system) = &self.system else {
            return;
        };
        let np = self.pinned.len();
        let mut put = |q: usize, R: &Mat3| {
            for i in 0..3 {
                for j in 0..3 {
                    ws.pinned_values[(3 * i + j) * np + q] = R[i][j];
                }
            }
        };
        for (&t, &q) in self.boundary.iter().zip(&self.boundary_slots) {
            put(q as usize, &known_rotation(t as usize));
        }
        for &q in &self.unreached {
            put(q as usize, &identity());
        }
        let solve = ws.solve.as_mut().expect("a workspace of this field");
        system.solve(&ws.rhs, Some(&ws.pinned_values), &mut ws.x, solve);
        let n = self.num_triangles;
        for &t in &self.unknown {
            let t = t as usize;
            let M: Mat3 =
                std::array::from_fn(|i| std::array::from_fn(|j| ws.x[(3 * i + j) * n + t]));
            rotations[t] = closest_rotation(&M);
        }
    }
}
