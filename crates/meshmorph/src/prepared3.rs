//! The part of 3D gradient-domain animation that depends on the rest mesh
//! alone: per-triangle gradient operators, the factored normal matrix, and
//! the placement of each connected part. Built once, shared (for example
//! behind an `Arc`) by interpolations, sequences and blends of that rest
//! mesh.
//!
//! A frame is given by one 3×3 map `A_T` per triangle (the map from the rest
//! triangle to the frame's triangle, as in Alexa et al. 2000 for the plane);
//! its vertices minimise `Σ_T area_T ‖J_T(x) − A_T P_T‖²_F`, where `J_T(x)`
//! is the surface gradient of the piecewise-linear map that sends the rest
//! mesh to `x` and `P_T` projects onto the rest triangle's plane. The normal
//! matrix is the cotangent Laplacian of the rest mesh, the same for x, y and
//! z and for every frame: one factorization, three right-hand sides.
#![allow(non_snake_case)]

use crate::error::Result;
use crate::geometry::{cross, norm, scale, sub};
use crate::matrix::Mat3;
use crate::mesh::Mesh3;
use crate::solve::{FactorKind, PinnedSystem, SymmetricBuilder, Workspace};
use crate::topology::connected_components;

/// A rest mesh prepared for frames (see the module documentation).
#[derive(Debug)]
pub struct PreparedSurface {
    rest: Mesh3,
    /// `area_T ∇φ_k` for the three corners of each rest triangle (vectors in
    /// the triangle's plane).
    weighted_gradients: Vec<[[f64; 3]; 3]>,
    system: PinnedSystem,
    /// Connected part of each vertex, `u32::MAX` for vertices no triangle uses.
    vertex_component: Vec<u32>,
    /// Area weight of each vertex in its part's centroid.
    vertex_weight: Vec<f64>,
    /// Total weight of each part.
    component_weight: Vec<f64>,
    /// Vertices no triangle uses.
    loose: Vec<u32>,
}

/// Per-thread scratch for [`PreparedSurface::solve_into`].
#[derive(Debug)]
pub struct SurfaceWorkspace {
    solve: Workspace,
    rhs: Vec<f64>,
    x: Vec<f64>,
    sums: Vec<[f64; 3]>,
}

impl PreparedSurface {
    /// Prepares `rest` (whose triangles must all have a non-zero area).
    ///
    /// # Errors
    /// [`Error::DegenerateTriangles`](crate::Error::DegenerateTriangles) naming
    /// zero-area triangles of `rest` (called `name` in the message), or
    /// [`Error::Solver`](crate::Error::Solver) if the system cannot be
    /// factored.
    ///
    /// # Performance
    /// Linear in the number of triangles apart from one sparse Cholesky
    /// factorization of a `#V × #V` matrix.
    pub fn new(rest: &Mesh3, name: &str, factor: FactorKind) -> Result<Self> {
        rest.check_no_degenerate_triangles(name)?;
        let n = rest.num_vertices();
        let triangles = rest.triangles();
        // area ∇φ_i = n̂ × (p_{i+2} − p_{i+1}) / 2 with n̂ the unit normal.
        let weighted_gradients: Vec<[[f64; 3]; 3]> = (0..triangles.len())
            .map(|t| {
                let p = rest.corners(t);
                let nrm = cross(sub(p[1], p[0]), sub(p[2], p[0]));
                let unit = scale(nrm, 1.0 / norm(nrm));
                std::array::from_fn(|i| {
                    scale(cross(unit, sub(p[(i + 2) % 3], p[(i + 1) % 3])), 0.5)
                })
            })
            .collect();
        let areas = rest.triangle_areas();
        let mut builder = SymmetricBuilder::new(n, 6 * triangles.len());
        for (tri, (g, &area)) in triangles.iter().zip(weighted_gradients.iter().zip(&areas)) {
            let inv = 1.0 / area;
            for i in 0..3 {
                for j in i..3 {
                    let v = (g[i][0] * g[j][0] + g[i][1] * g[j][1] + g[i][2] * g[j][2]) * inv;
                    builder.add(tri[i] as usize, tri[j] as usize, v);
                }
            }
        }
        // Translation is free in each part: pin one vertex of each (the
        // result is moved afterwards), and every vertex no triangle uses.
        let components = connected_components(n, triangles);
        let mut vertex_component = vec![u32::MAX; n];
        let mut pinned = Vec::with_capacity(components.count);
        let mut seen = vec![false; components.count];
        let mut loose = Vec::new();
        for (v, c) in components.of_vertex.iter().enumerate() {
            match c {
                Some(c) => {
                    vertex_component[v] = *c;
                    if !std::mem::replace(&mut seen[*c as usize], true) {
                        pinned.push(v);
                    }
                }
                None => {
                    pinned.push(v);
                    loose.push(v as u32);
                }
            }
        }
        let system = PinnedSystem::new(&builder.build(), &pinned, factor)?;
        let mut vertex_weight = vec![0.0; n];
        for (tri, area) in triangles.iter().zip(&areas) {
            for &v in tri {
                vertex_weight[v as usize] += area / 3.0;
            }
        }
        let mut component_weight = vec![0.0; components.count];
        for v in 0..n {
            if let Some(c) = components.of_vertex[v] {
                component_weight[c as usize] += vertex_weight[v];
            }
        }
        Ok(Self {
            rest: rest.clone(),
            weighted_gradients,
            system,
            vertex_component,
            vertex_weight,
            component_weight,
            loose,
        })
    }

    /// Number of stored values of the Cholesky factor (for measuring a
    /// frame against the memory traffic of its back-substitution).
    pub fn factor_len(&self) -> usize {
        self.system.factor_len()
    }

    /// The rest mesh.
    pub fn rest(&self) -> &Mesh3 {
        &self.rest
    }

    /// Number of vertices of every frame.
    pub fn num_vertices(&self) -> usize {
        self.rest.num_vertices()
    }

    /// Number of connected parts (triangles sharing vertices).
    pub fn num_components(&self) -> usize {
        self.component_weight.len()
    }

    /// Vertices no triangle uses: frames place them themselves.
    pub fn loose_vertices(&self) -> &[u32] {
        &self.loose
    }

    /// The area-weighted centroid of each connected part of `positions`
    /// (positions of the rest mesh's vertices in some pose).
    pub fn centroids(&self, positions: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let mut sums = vec![[0.0; 3]; self.num_components()];
        for (v, p) in positions.iter().enumerate() {
            let c = self.vertex_component[v];
            if c != u32::MAX {
                for k in 0..3 {
                    sums[c as usize][k] += self.vertex_weight[v] * p[k];
                }
            }
        }
        for (s, w) in sums.iter_mut().zip(&self.component_weight) {
            *s = s.map(|x| x / w);
        }
        sums
    }

    /// Scratch for [`PreparedSurface::solve_into`]; one per thread.
    pub fn workspace(&self) -> SurfaceWorkspace {
        let n = self.num_vertices();
        SurfaceWorkspace {
            solve: self.system.workspace(3),
            rhs: vec![0.0; 3 * n],
            x: vec![0.0; 3 * n],
            sums: vec![[0.0; 3]; self.num_components()],
        }
    }

    /// The frame whose triangle `t` has the map `map(t)`, each part moved so
    /// that its centroid is `centroids[part]`. Vertices no triangle uses are
    /// left as they are in `out`.
    ///
    /// # Panics
    /// If `out` or `centroids` has the wrong length.
    #[track_caller]
    pub fn solve_into(
        &self,
        map: impl Fn(usize) -> Mat3,
        centroids: &[[f64; 3]],
        out: &mut [[f64; 3]],
        ws: &mut SurfaceWorkspace,
    ) {
        let n = self.num_vertices();
        assert_eq!(out.len(), n, "output has the wrong number of vertices");
        assert_eq!(
            centroids.len(),
            self.num_components(),
            "one centroid per part"
        );
        ws.rhs.fill(0.0);
        {
            let (bx, rest) = ws.rhs.split_at_mut(n);
            let (by, bz) = rest.split_at_mut(n);
            for (t, (tri, g)) in self
                .rest
                .triangles()
                .iter()
                .zip(&self.weighted_gradients)
                .enumerate()
            {
                let A = map(t);
                for k in 0..3 {
                    let v = tri[k] as usize;
                    let gk = g[k];
                    bx[v] += A[0][0] * gk[0] + A[0][1] * gk[1] + A[0][2] * gk[2];
                    by[v] += A[1][0] * gk[0] + A[1][1] * gk[1] + A[1][2] * gk[2];
                    bz[v] += A[2][0] * gk[0] + A[2][1] * gk[1] + A[2][2] * gk[2];
                }
            }
        }
        self.system.solve(&ws.rhs, None, &mut ws.x, &mut ws.solve);
        ws.sums.fill([0.0; 3]);
        for v in 0..n {
            let c = self.vertex_component[v];
            if c != u32::MAX {
                let s = &mut ws.sums[c as usize];
                for k in 0..3 {
                    s[k] += self.vertex_weight[v] * ws.x[k * n + v];
                }
            }
        }
        for ((s, w), target) in ws
            .sums
            .iter_mut()
            .zip(&self.component_weight)
            .zip(centroids)
        {
            for k in 0..3 {
                s[k] = target[k] - s[k] / w;
            }
        }
        for v in 0..n {
            let c = self.vertex_component[v];
            if c != u32::MAX {
                let s = ws.sums[c as usize];
                out[v] = std::array::from_fn(|k| ws.x[k * n + v] + s[k]);
            }
        }
    }
}
