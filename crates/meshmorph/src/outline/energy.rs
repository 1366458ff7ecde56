//! The foldover-free energy of Garanzha, Kaporin, Kudryavtseva, Protais,
//! Ray and Sokolov (2021, "Foldover-free maps in 50 lines of code") of a
//! map between two meshes with the same triangles, and its gradient:
//! what the untangling, the relaxation and the rigid settle minimise.
//! One pass over the triangles gives the energy, its gradient and
//! whether every triangle is positive.
//!
//! (Evaluating the triangles in pieces on both cores was slower: at a few
//! thousand triangles an evaluation takes a fraction of a millisecond,
//! less than waking another thread costs.)

use crate::mesh::signed_areas;

/// The inverse of the edge matrix of the equilateral triangle of unit
/// edge, `[1, ½; 0, √¾]⁻¹` (row-major).
const EQUILATERAL: [f64; 4] = [
    1.0,
    -0.5 / SQRT_THREE_QUARTERS,
    0.0,
    1.0 / SQRT_THREE_QUARTERS,
];
const SQRT_THREE_QUARTERS: f64 = 0.866_025_403_784_438_6;

/// For each triangle a reference shape, the inverse of its edge matrix,
/// and its share of the energy. `theta` weighs the area term against the
/// shape term: 1/2 makes each triangle's term `½ (σ1 + 1/σ1)(σ2 + 1/σ2)`
/// of its map's singular values, least (2) for a rigid motion; 0 leaves
/// the shape term alone, `|J|² / det J`.
pub(super) struct Energy<'a> {
    triangles: &'a [[u32; 3]],
    inverse: Vec<[f64; 4]>,
    weight: Vec<f64>,
    fixed: usize,
    theta: f64,
    /// Weight of each triangle's distortion from an equilateral one,
    /// added in the same pass ([`Energy::with_shape`]); 0 for none.
    shape: f64,
}

/// The regularised positive part of `d` (Garanzha et al.'s `χ`).
#[inline]
pub(super) fn chi(d: f64, eps: f64) -> f64 {
    0.5 * (d + (eps * eps + d * d).sqrt())
}

/// `a b` of two row-major 2x2 matrices.
#[inline]
fn product(a: [f64; 4], b: &[f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] + a[1] * b[2],
        a[0] * b[1] + a[1] * b[3],
        a[2] * b[0] + a[3] * b[2],
        a[2] * b[1] + a[3] * b[3],
    ]
}

/// `a bᵀ` of two row-major 2x2 matrices.
#[inline]
fn product_transposed(a: [f64; 4], b: &[f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] + a[1] * b[1],
        a[0] * b[2] + a[1] * b[3],
        a[2] * b[0] + a[3] * b[1],
        a[2] * b[2] + a[3] * b[3],
    ]
}

/// One triangle's term at Jacobian `j`, weighed by `w`, and its
/// derivative with respect to `j` when `with_gradient`.
#[inline]
fn term(j: [f64; 4], w: f64, theta: f64, eps: f64, with_gradient: bool) -> (f64, [f64; 4]) {
    let det = j[0] * j[3] - j[1] * j[2];
    let tr = j[0] * j[0] + j[1] * j[1] + j[2] * j[2] + j[3] * j[3];
    let root = (eps * eps + det * det).sqrt();
    let c = 0.5 * (det + root);
    let num = (1.0 - theta) * tr + theta * (1.0 + det * det);
    let energy = w * num / c;
    if !with_gradient {
        return (energy, [0.0; 4]);
    }
    let dc = c / root;
    let a = w * 2.0 * (1.0 - theta) / c;
    let q = w * (2.0 * theta * det / c - num * dc / (c * c));
    // dE/dJ = a J + q cof(J), cof(J) = [j3, -j2; -j1, j0].
    (
        energy,
        [
            a * j[0] + q * j[3],
            a * j[1] - q * j[2],
            a * j[2] - q * j[1],
            a * j[3] + q * j[0],
        ],
    )
}

impl<'a> Energy<'a> {
    /// The energy of maps of `reference`'s triangles into a drawing of
    /// signed area `target_area`: each triangle's shape in `reference`
    /// scaled to that area, weighed by its share of the area. Vertices
    /// below `fixed` get no gradient.
    pub(super) fn against(
        reference: &[[f64; 2]],
        triangles: &'a [[u32; 3]],
        target_area: f64,
        fixed: usize,
        theta: f64,
    ) -> Self {
        let area: f64 = signed_areas(reference, triangles).iter().sum();
        let scale = (target_area / area).abs().sqrt();
        let mut inverse = Vec::with_capacity(triangles.len());
        let mut weight = Vec::with_capacity(triangles.len());
        for t in triangles {
            let [i, j, k] = t.map(|v| reference[v as usize]);
            let d = [
                scale * (j[0] - i[0]),
                scale * (k[0] - i[0]),
                scale * (j[1] - i[1]),
                scale * (k[1] - i[1]),
            ];
            let det = d[0] * d[3] - d[1] * d[2];
            inverse.push([d[3] / det, -d[1] / det, -d[2] / det, d[0] / det]);
            weight.push(0.5 * det / target_area.abs());
        }
        Self {
            triangles,
            inverse,
            weight,
            fixed,
            theta,
            shape: 0.0,
        }
    }

    /// The conformal distortion of each triangle from an equilateral one
    /// (the MIPS energy of Hormann and Greiner 2000, `|J|² / det J`, the
    /// shape part of the foldover-free energy), each triangle weighed
    /// alike, the mean over them: 2 when all are equilateral, infinite
    /// for a flat one. Vertices below `fixed` get no gradient.
    pub(super) fn equilateral(triangles: &'a [[u32; 3]], fixed: usize) -> Self {
        Self {
            triangles,
            inverse: vec![EQUILATERAL; triangles.len()],
            weight: vec![1.0 / triangles.len() as f64; triangles.len()],
            fixed,
            theta: 0.0,
            shape: 0.0,
        }
    }

    /// This energy plus, with the same weight as a whole, the moving
    /// mesh's own distortion from equilateral triangles
    /// ([`Energy::equilateral`]), both in one pass.
    pub(super) fn with_shape(mut self) -> Self {
        self.shape = 1.0 / self.triangles.len().max(1) as f64;
        self
    }

    /// Jacobian of triangle `t` at `b`.
    #[inline]
    fn jacobian(&self, b: &[[f64; 2]], t: usize) -> [f64; 4] {
        let [i, j, k] = self.triangles[t].map(|v| b[v as usize]);
        product(
            [j[0] - i[0], k[0] - i[0], j[1] - i[1], k[1] - i[1]],
            &self.inverse[t],
        )
    }

    /// The smallest determinant of the triangles' maps at `b`: positive
    /// when every triangle is.
    pub(super) fn min_det(&self, b: &[[f64; 2]]) -> f64 {
        (0..self.triangles.len())
            .map(|t| {
                let j = self.jacobian(b, t);
                j[0] * j[3] - j[1] * j[2]
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// How many triangles are not positive at `b`.
    pub(super) fn inverted(&self, b: &[[f64; 2]]) -> usize {
        (0..self.triangles.len())
            .filter(|&t| {
                let j = self.jacobian(b, t);
                j[0] * j[3] - j[1] * j[2] <= 0.0
            })
            .count()
    }

    /// An estimate of the energy's second derivative at `b` along each
    /// vertex's x (and, alike, y) coordinate: for each triangle's term,
    /// twice its weight times the squared gradient of the Jacobian with
    /// respect to that coordinate, over the regularised determinant. The
    /// preconditioner of [`super::lbfgs::lbfgs_scaled`].
    pub(super) fn diagonal(&self, b: &[[f64; 2]]) -> Vec<f64> {
        let mut h = vec![0.0; b.len()];
        let mut add = |t: &[u32; 3], r: &[f64; 4], w: f64, det: f64| {
            let w = 2.0 * w / chi(det, 1e-12 * det.abs().max(1e-300));
            // The rows of R are the Jacobian's derivatives along the
            // second and third corners' coordinates; the first's is minus
            // their sum.
            let rows = [[-(r[0] + r[2]), -(r[1] + r[3])], [r[0], r[1]], [r[2], r[3]]];
            for (&v, row) in t.iter().zip(rows) {
                h[v as usize] += w * (row[0] * row[0] + row[1] * row[1]);
            }
        };
        for (t, tri) in self.triangles.iter().enumerate() {
            let [i, j, l] = tri.map(|v| b[v as usize]);
            let d = [j[0] - i[0], l[0] - i[0], j[1] - i[1], l[1] - i[1]];
            let jac = product(d, &self.inverse[t]);
            add(
                tri,
                &self.inverse[t],
                self.weight[t],
                jac[0] * jac[3] - jac[1] * jac[2],
            );
            if self.shape > 0.0 {
                let own = product(d, &EQUILATERAL);
                add(
                    tri,
                    &EQUILATERAL,
                    self.shape,
                    own[0] * own[3] - own[1] * own[2],
                );
            }
        }
        h
    }

    /// The energy at `b`, regularised by `eps` (0 for none), and, when
    /// `grad` is given, its gradient with respect to every vertex (the
    /// fixed ones' left at zero).
    pub(super) fn eval(&self, b: &[[f64; 2]], eps: f64, grad: Option<&mut [[f64; 2]]>) -> f64 {
        self.evaluate(b, eps, grad).0
    }

    /// As [`Energy::eval`] without regularisation, but infinite when a
    /// triangle is not positive at `b` (a barrier for steps that must
    /// keep every triangle positive).
    pub(super) fn eval_positive(&self, b: &[[f64; 2]], grad: Option<&mut [[f64; 2]]>) -> f64 {
        match self.evaluate(b, 0.0, grad) {
            (_, least) if least <= 0.0 || least.is_nan() => f64::INFINITY,
            (e, _) => e,
        }
    }

    /// The energy and the smallest determinant at `b`, and the gradient
    /// into `grad`.
    fn evaluate(&self, b: &[[f64; 2]], eps: f64, mut grad: Option<&mut [[f64; 2]]>) -> (f64, f64) {
        let with_gradient = grad.is_some();
        if let Some(g) = grad.as_deref_mut() {
            g.fill([0.0, 0.0]);
        }
        let (mut total, mut least) = (0.0, f64::INFINITY);
        for (t, tri) in self.triangles.iter().enumerate() {
            let [i, j, l] = tri.map(|v| b[v as usize]);
            let d = [j[0] - i[0], l[0] - i[0], j[1] - i[1], l[1] - i[1]];
            let r = &self.inverse[t];
            let jac = product(d, r);
            least = least.min(jac[0] * jac[3] - jac[1] * jac[2]);
            let (e, gj) = term(jac, self.weight[t], self.theta, eps, with_gradient);
            total += e;
            // dE/dD = dE/dJ Rᵀ.
            let mut gd = product_transposed(gj, r);
            if self.shape > 0.0 {
                let own = product(d, &EQUILATERAL);
                let (e, gj) = term(own, self.shape, 0.0, 0.0, with_gradient);
                total += e;
                let g = product_transposed(gj, &EQUILATERAL);
                for (a, b) in gd.iter_mut().zip(g) {
                    *a += b;
                }
            }
            let Some(g) = grad.as_deref_mut() else {
                continue;
            };
            let corners = [
                [-(gd[0] + gd[1]), -(gd[2] + gd[3])],
                [gd[0], gd[2]],
                [gd[1], gd[3]],
            ];
            for (&v, c) in tri.iter().zip(corners) {
                if v as usize >= self.fixed {
                    let g = &mut g[v as usize];
                    g[0] += c[0];
                    g[1] += c[1];
                }
            }
        }
        (total, least)
    }
}
