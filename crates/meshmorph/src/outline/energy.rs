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

use crate::linalg::lanes::{array, Lanes, Real};
use crate::linalg::matrix::{det2, mul, Mat2};
use crate::mesh::signed_areas;

/// The inverse of the edge matrix of the equilateral triangle of unit
/// edge, `[1, ½; 0, √¾]⁻¹`.
const EQUILATERAL: Mat2 = [
    [1.0, -0.5 / SQRT_THREE_QUARTERS],
    [0.0, 1.0 / SQRT_THREE_QUARTERS],
];
const SQRT_THREE_QUARTERS: f64 = 0.866_025_403_784_438_6;

/// For each triangle a reference shape, the inverse of its edge matrix,
/// and its share of the energy. `theta` weighs the area term against the
/// shape term: 1/2 makes each triangle's term `½ (σ1 + 1/σ1)(σ2 + 1/σ2)`
/// of its map's singular values, least (2) for a rigid motion; 0 leaves
/// the shape term alone, `|J|² / det J`.
pub struct Energy<'a> {
    triangles: &'a [[u32; 3]],
    inverse: Vec<Mat2>,
    weight: Vec<f64>,
    theta: f64,
    /// Weight of each triangle's distortion from an equilateral one,
    /// added in the same pass ([`Energy::with_shape`]); 0 for none.
    shape: f64,
    /// Instead of the foldover-free term, each triangle's robust distance
    /// from a rigid motion with this knee ([`Energy::rigid`]).
    rigid: Option<f64>,
}

/// The regularised positive part of `d` (Garanzha et al.'s `χ`).
#[inline]
pub(super) fn chi(d: f64, eps: f64) -> f64 {
    0.5 * (d + (eps * eps + d * d).sqrt())
}

/// The edge matrix of triangle `tri` at `b`: its edges from the first
/// corner to the second and to the third, as columns.
#[inline]
fn edges(b: &[[f64; 2]], tri: [u32; 3]) -> Mat2 {
    let [i, j, k] = tri.map(|v| b[v as usize]);
    [[j[0] - i[0], k[0] - i[0]], [j[1] - i[1], k[1] - i[1]]]
}

/// Triangles evaluated side by side in a pass of [`Energy::evaluate`].
const TRIANGLES_PER_STEP: usize = 4;

/// A 2 x 2 matrix of lanes (one per triangle), row by row.
type LaneMat<const L: usize> = [[Lanes<L>; 2]; 2];

#[inline(always)]
fn mul_lanes<const L: usize>(a: &LaneMat<L>, b: &LaneMat<L>) -> LaneMat<L> {
    array(|i| array(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j]))
}

/// `a bᵀ`.
#[inline(always)]
fn mul_nt_lanes<const L: usize>(a: &LaneMat<L>, b: &LaneMat<L>) -> LaneMat<L> {
    array(|i| array(|j| a[i][0] * b[j][0] + a[i][1] * b[j][1]))
}

#[inline(always)]
fn det_lanes<const L: usize>(a: &LaneMat<L>) -> Lanes<L> {
    a[0][0] * a[1][1] - a[0][1] * a[1][0]
}

/// The triangles' terms at Jacobians `j`, weighed by `w`, and their
/// derivatives with respect to `j` when `with_gradient`.
#[inline(always)]
fn term<const L: usize>(
    j: LaneMat<L>,
    w: Lanes<L>,
    theta: f64,
    eps: f64,
    with_gradient: bool,
) -> (Lanes<L>, LaneMat<L>) {
    let det = det_lanes(&j);
    let tr = j[0][0] * j[0][0] + j[0][1] * j[0][1] + j[1][0] * j[1][0] + j[1][1] * j[1][1];
    let root = (Lanes::splat(eps * eps) + det * det).map(f64::sqrt);
    let c = Lanes::splat(0.5) * (det + root);
    let inv_c = c.map(|c| 1.0 / c);
    let num =
        Lanes::splat(1.0 - theta) * tr + Lanes::splat(theta) * (Lanes::splat(1.0) + det * det);
    let energy = w * num * inv_c;
    if !with_gradient {
        return (energy, [[Lanes::splat(0.0); 2]; 2]);
    }
    // dc/d(det) = c / root, so num dc / c² = num / (c root).
    let a = w * Lanes::splat(2.0 * (1.0 - theta)) * inv_c;
    let q = w * inv_c * (Lanes::splat(2.0 * theta) * det - num.zip(root, |n, r| n / r));
    // dE/dJ = a J + q cof(J), cof(J) = [j11, -j10; -j01, j00].
    (
        energy,
        [
            [a * j[0][0] + q * j[1][1], a * j[0][1] - q * j[1][0]],
            [a * j[1][0] - q * j[0][1], a * j[1][1] + q * j[0][0]],
        ],
    )
}

/// The triangles' robust distances from a rotation at Jacobians `j`,
/// weighed by `w` ([`Energy::rigid`]), and their derivatives. For
/// `J = [a b; c d]` the nearest rotation turns by `atan2(c − b, a + d)`
/// and `|J − R|² = |J|² − 2n + 2`, `n = |(a + d, c − b)|`, whose
/// derivative is `2 (J − R)`.
#[inline(always)]
fn rigid_term<const L: usize>(
    j: LaneMat<L>,
    w: Lanes<L>,
    knee: f64,
    with_gradient: bool,
) -> (Lanes<L>, LaneMat<L>) {
    let tr = j[0][0] * j[0][0] + j[0][1] * j[0][1] + j[1][0] * j[1][0] + j[1][1] * j[1][1];
    let (cs, sn) = (j[0][0] + j[1][1], j[1][0] - j[0][1]);
    let n = (cs * cs + sn * sn).map(f64::sqrt);
    let r2 = (tr - Lanes::splat(2.0) * n + Lanes::splat(2.0)).map(|x| x.max(0.0));
    let f = (Lanes::splat(knee * knee) + r2).map(f64::sqrt);
    let energy = w * f;
    if !with_gradient {
        return (energy, [[Lanes::splat(0.0); 2]; 2]);
    }
    let inv_n = n.map(|n| if n > 0.0 { 1.0 / n } else { 0.0 });
    let (c, s) = (cs * inv_n, sn * inv_n);
    let k = w * f.map(|f| 1.0 / f);
    (
        energy,
        [
            [k * (j[0][0] - c), k * (j[0][1] + s)],
            [k * (j[1][0] - s), k * (j[1][1] - c)],
        ],
    )
}

impl<'a> Energy<'a> {
    /// The energy of maps of `reference`'s triangles into a drawing of
    /// signed area `target_area`: each triangle's shape in `reference`
    /// scaled to that area, weighed by its share of the area.
    pub(super) fn against(
        reference: &[[f64; 2]],
        triangles: &'a [[u32; 3]],
        target_area: f64,
        theta: f64,
    ) -> Self {
        let area: f64 = signed_areas(reference, triangles).iter().sum();
        let scale = (target_area / area).abs().sqrt();
        let mut inverse = Vec::with_capacity(triangles.len());
        let mut weight = Vec::with_capacity(triangles.len());
        for &t in triangles {
            let d = edges(reference, t).map(|row| row.map(|x| scale * x));
            let det = det2(d);
            inverse.push([
                [d[1][1] / det, -d[0][1] / det],
                [-d[1][0] / det, d[0][0] / det],
            ]);
            weight.push(0.5 * det / target_area.abs());
        }
        Self {
            triangles,
            inverse,
            weight,
            theta,
            shape: 0.0,
            rigid: None,
        }
    }

    /// The conformal distortion of each triangle from an equilateral one
    /// (the MIPS energy of Hormann and Greiner 2000, `|J|² / det J`, the
    /// shape part of the foldover-free energy), each triangle weighed
    /// alike, the mean over them: 2 when all are equilateral, infinite
    /// for a flat one.
    pub(super) fn equilateral(triangles: &'a [[u32; 3]]) -> Self {
        Self {
            triangles,
            inverse: vec![EQUILATERAL; triangles.len()],
            weight: vec![1.0 / triangles.len() as f64; triangles.len()],
            theta: 0.0,
            shape: 0.0,
            rigid: None,
        }
    }

    /// This energy plus, with `weight` times the same weight as a whole,
    /// the moving mesh's own distortion from equilateral triangles
    /// ([`Energy::equilateral`]), both in one pass.
    pub(super) fn with_shape(mut self, weight: f64) -> Self {
        self.shape = weight / self.triangles.len().max(1) as f64;
        self
    }

    /// This energy with each triangle's term its distance from the
    /// nearest rotation, `√(knee² + |J − R|²)`: like the distance's square
    /// below `knee`, like the distance itself above it, so that a map
    /// gains by keeping most triangles rigid and putting what must give
    /// on a few (a fold's squeeze at its corner) rather than sharing it
    /// out. Bounded where a triangle flattens: steps that keep every
    /// triangle positive ([`Energy::eval_positive`]) keep the map valid.
    pub(super) fn rigid(mut self, knee: f64) -> Self {
        self.rigid = Some(knee);
        self
    }

    /// Jacobian of triangle `t` at `b`.
    #[inline]
    fn jacobian(&self, b: &[[f64; 2]], t: usize) -> Mat2 {
        mul(edges(b, self.triangles[t]), self.inverse[t])
    }

    /// The smallest determinant of the triangles' maps at `b`: positive
    /// when every triangle is.
    pub(super) fn min_det(&self, b: &[[f64; 2]]) -> f64 {
        (0..self.triangles.len())
            .map(|t| det2(self.jacobian(b, t)))
            .fold(f64::INFINITY, f64::min)
    }

    /// How many triangles are not positive at `b`.
    pub(super) fn inverted(&self, b: &[[f64; 2]]) -> usize {
        (0..self.triangles.len())
            .filter(|&t| det2(self.jacobian(b, t)) <= 0.0)
            .count()
    }

    /// An estimate of the energy's second derivative at `b` along each
    /// vertex's x (and, alike, y) coordinate: for each triangle's term,
    /// twice its weight times the squared gradient of the Jacobian with
    /// respect to that coordinate, over the regularised determinant. The
    /// preconditioner of [`super::lbfgs::lbfgs_scaled`].
    pub(super) fn diagonal(&self, b: &[[f64; 2]]) -> Vec<f64> {
        let mut h = vec![0.0; b.len()];
        let mut add = |t: &[u32; 3], r: &Mat2, w: f64, det: f64| {
            let w = 2.0 * w / chi(det, 1e-12 * det.abs().max(1e-300));
            // The rows of R are the Jacobian's derivatives along the
            // second and third corners' coordinates; the first's is minus
            // their sum.
            let rows = [[-(r[0][0] + r[1][0]), -(r[0][1] + r[1][1])], r[0], r[1]];
            for (&v, row) in t.iter().zip(rows) {
                h[v as usize] += w * (row[0] * row[0] + row[1] * row[1]);
            }
        };
        for (t, &tri) in self.triangles.iter().enumerate() {
            let d = edges(b, tri);
            let r = &self.inverse[t];
            add(&tri, r, self.weight[t], det2(mul(d, *r)));
            if self.shape > 0.0 {
                add(&tri, &EQUILATERAL, self.shape, det2(mul(d, EQUILATERAL)));
            }
        }
        h
    }

    /// The energy at `b`, regularised by `eps` (0 for none), and, when
    /// `grad` is given, its gradient with respect to every vertex (the
    /// caller takes the free ones' and leaves the rest: a branch on each
    /// corner cost more than the sums).
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
    /// into `grad`: [`TRIANGLES_PER_STEP`] triangles side by side, with
    /// AVX2 (x86-64-v3) where the processor has it (chosen when the
    /// program runs).
    fn evaluate(&self, b: &[[f64; 2]], eps: f64, mut grad: Option<&mut [[f64; 2]]>) -> (f64, f64) {
        if let Some(g) = grad.as_deref_mut() {
            g.fill([0.0, 0.0]);
        }
        pulp::Arch::new().dispatch(Pass {
            energy: self,
            b,
            eps,
            grad,
        })
    }

    /// Triangles `first..first + L`'s terms at `b` added to `sums` (the
    /// energy, and the smallest determinant so far) and their gradient
    /// into `grad`.
    #[inline(always)]
    fn step<const L: usize>(
        &self,
        b: &[[f64; 2]],
        first: usize,
        eps: f64,
        sums: &mut (f64, f64),
        grad: Option<&mut [[f64; 2]]>,
    ) {
        let with_gradient = grad.is_some();
        let tris: [[u32; 3]; L] = array(|l| self.triangles[first + l]);
        let corner = |k: usize, c: usize| Lanes::<L>(array(|l| b[tris[l][k] as usize][c]));
        // Edge matrices: the edges from the first corner to the second and
        // to the third, as columns.
        let (x0, y0) = (corner(0, 0), corner(0, 1));
        let d: LaneMat<L> = [
            [corner(1, 0) - x0, corner(2, 0) - x0],
            [corner(1, 1) - y0, corner(2, 1) - y0],
        ];
        let r: LaneMat<L> = array(|i| array(|j| Lanes(array(|l| self.inverse[first + l][i][j]))));
        let jac = mul_lanes(&d, &r);
        let det = det_lanes(&jac);
        let w = Lanes(array(|l| self.weight[first + l]));
        let (e, gj) = match self.rigid {
            Some(knee) => rigid_term(jac, w, knee, with_gradient),
            None => term(jac, w, self.theta, eps, with_gradient),
        };
        // dE/dD = dE/dJ Rᵀ.
        let mut gd = mul_nt_lanes(&gj, &r);
        let mut energy = e;
        if self.shape > 0.0 {
            let equilateral: LaneMat<L> = EQUILATERAL.map(|row| row.map(Lanes::splat));
            let (e, gj) = term(
                mul_lanes(&d, &equilateral),
                Lanes::splat(self.shape),
                0.0,
                0.0,
                with_gradient,
            );
            energy = energy + e;
            let g = mul_nt_lanes(&gj, &equilateral);
            gd = array(|i| array(|j| gd[i][j] + g[i][j]));
        }
        for l in 0..L {
            sums.0 += energy.0[l];
            sums.1 = sums.1.min(det.0[l]);
        }
        let Some(g) = grad else {
            return;
        };
        for (l, tri) in tris.iter().enumerate() {
            // The second corner moves the first column of D, the third the
            // second, the first both against.
            let corners = [
                [
                    -(gd[0][0].0[l] + gd[0][1].0[l]),
                    -(gd[1][0].0[l] + gd[1][1].0[l]),
                ],
                [gd[0][0].0[l], gd[1][0].0[l]],
                [gd[0][1].0[l], gd[1][1].0[l]],
            ];
            for (&v, c) in tri.iter().zip(corners) {
                let g = &mut g[v as usize];
                g[0] += c[0];
                g[1] += c[1];
            }
        }
    }
}

/// A pass of [`Energy::evaluate`] over every triangle.
struct Pass<'a, 'e> {
    energy: &'a Energy<'e>,
    b: &'a [[f64; 2]],
    eps: f64,
    grad: Option<&'a mut [[f64; 2]]>,
}

impl pulp::WithSimd for Pass<'_, '_> {
    type Output = (f64, f64);

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(mut self, _: S) -> (f64, f64) {
        let mut sums = (0.0, f64::INFINITY);
        let count = self.energy.triangles.len();
        let whole = count - count % TRIANGLES_PER_STEP;
        for first in (0..whole).step_by(TRIANGLES_PER_STEP) {
            self.energy.step::<TRIANGLES_PER_STEP>(
                self.b,
                first,
                self.eps,
                &mut sums,
                self.grad.as_deref_mut(),
            );
        }
        for first in whole..count {
            self.energy
                .step::<1>(self.b, first, self.eps, &mut sums, self.grad.as_deref_mut());
        }
        sums
    }
}
