//! Similarity transforms (rotation, uniform scale, translation) and their
//! least-squares fit to point pairs.
//!
//! The fit is Horn's ("Closed-form solution of absolute orientation using
//! unit quaternions", JOSA A 1987): the rotation is the unit quaternion of
//! the largest eigenvalue of a symmetric 4 × 4 matrix built from the
//! cross-covariance of the centred points, so it is always a proper
//! rotation (never a reflection, the case Umeyama 1991 guards against with a
//! sign in the SVD); the scale is Umeyama's `Σ yᵢ·R xᵢ / Σ |xᵢ|²`.
#![allow(non_snake_case)]

use crate::error::{Error, Result};
use crate::linalg::matrix::{det3, inverse3};
use crate::linalg::vector::{add, dot, mean_of, norm, scale, sub};

/// `x ↦ s R x + t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Similarity {
    /// The rotation `R`, row-major.
    pub rotation: [[f64; 3]; 3],
    /// The uniform scale `s > 0`.
    pub scale: f64,
    /// The translation `t`.
    pub translation: [f64; 3],
}

impl Default for Similarity {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Similarity {
    /// The identity.
    pub const IDENTITY: Similarity = Similarity {
        rotation: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        scale: 1.0,
        translation: [0.0; 3],
    };

    /// Whether this is exactly the identity.
    pub fn is_identity(&self) -> bool {
        *self == Self::IDENTITY
    }

    /// `s R p + t`.
    #[inline]
    pub fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        add(scale(self.rotate(p), self.scale), self.translation)
    }

    /// `R v` (no scale, no translation).
    #[inline]
    pub fn rotate(&self, v: [f64; 3]) -> [f64; 3] {
        let R = &self.rotation;
        [dot(R[0], v), dot(R[1], v), dot(R[2], v)]
    }

    /// The similarity that undoes this one: `Rᵀ (p − t) / s`.
    pub fn inverse(&self) -> Similarity {
        let rotation: [[f64; 3]; 3] =
            std::array::from_fn(|i| std::array::from_fn(|j| self.rotation[j][i]));
        let back = Similarity {
            rotation,
            scale: 1.0 / self.scale,
            translation: [0.0; 3],
        };
        Similarity {
            translation: scale(back.apply(self.translation), -1.0),
            ..back
        }
    }

    /// `other ∘ self`: this similarity, then `other`.
    pub fn then(&self, other: &Similarity) -> Similarity {
        let R: [[f64; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                (0..3)
                    .map(|k| other.rotation[i][k] * self.rotation[k][j])
                    .sum()
            })
        });
        Similarity {
            rotation: R,
            scale: other.scale * self.scale,
            translation: other.apply(self.translation),
        }
    }

    /// The angle of the rotation, in radians.
    pub fn angle(&self) -> f64 {
        self.angle_to(&Similarity::IDENTITY)
    }

    /// The angle (radians) between this rotation and `other`'s: that of the
    /// turn taking one onto the other.
    pub fn angle_to(&self, other: &Similarity) -> f64 {
        let (A, B) = (&self.rotation, &other.rotation);
        let trace: f64 = (0..3)
            .map(|i| (0..3).map(|j| A[i][j] * B[i][j]).sum::<f64>())
            .sum();
        ((trace - 1.0) / 2.0).clamp(-1.0, 1.0).acos()
    }

    /// Every point mapped.
    pub fn apply_all(&self, points: &[[f64; 3]]) -> Vec<[f64; 3]> {
        points.iter().map(|&p| self.apply(p)).collect()
    }

    /// The similarity that best maps `from[i]` onto `to[i]` in the least
    /// squares sense (Horn 1987 for the rotation, Umeyama 1991 for the scale).
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] when the counts differ, there are fewer
    /// than three pairs, or either set lies on one line (then no rotation is
    /// fixed): the message says which.
    pub fn fit(from: &[[f64; 3]], to: &[[f64; 3]]) -> Result<Similarity> {
        if from.len() != to.len() {
            return Err(Error::InvalidArgument(format!(
                "{} points cannot be paired with {}",
                from.len(),
                to.len()
            )));
        }
        if from.len() < 3 {
            return Err(Error::InvalidArgument(format!(
                "{} marker pair{} cannot fix a rotation and scale: at least 3 not on one line are needed",
                from.len(),
                if from.len() == 1 { "" } else { "s" }
            )));
        }
        let (cx, cy) = (mean_of(from), mean_of(to));
        for (points, c, which) in [(from, cx, "source"), (to, cy, "target")] {
            if is_on_a_line(points, c) {
                return Err(Error::InvalidArgument(format!(
                    "the {which} markers lie on one line: they cannot fix a rotation (add markers off that line)"
                )));
            }
        }
        // Cross-covariance M = Σ (x - cx)(y - cy)ᵀ.
        let mut M = [[0.0; 3]; 3];
        let mut xx = 0.0;
        for (&x, &y) in from.iter().zip(to) {
            let (x, y) = (sub(x, cx), sub(y, cy));
            for i in 0..3 {
                for j in 0..3 {
                    M[i][j] += x[i] * y[j];
                }
            }
            xx += dot(x, x);
        }
        let rotation = best_rotation(&M);
        let fit = Similarity {
            rotation,
            scale: 1.0,
            translation: [0.0; 3],
        };
        let yrx: f64 = from
            .iter()
            .zip(to)
            .map(|(&x, &y)| dot(sub(y, cy), fit.rotate(sub(x, cx))))
            .sum();
        let s = yrx / xx;
        if !(s.is_finite() && s > 0.0) {
            return Err(Error::InvalidArgument(
                "the markers give no positive scale: the source markers cannot be turned onto the target's".into(),
            ));
        }
        let translation = sub(cy, scale(fit.rotate(cx), s));
        Ok(Similarity {
            rotation,
            scale: s,
            translation,
        })
    }
}

/// [`Similarity::fit`], then fitted again without the pairs whose residual
/// stands out ([`outliers`]), so that a wrong marker does not turn the
/// whole source; the outliers are returned with the fit (indices into the
/// pairs, increasing).
///
/// # Errors
/// As [`Similarity::fit`] (on all pairs).
pub fn fit_robust(from: &[[f64; 3]], to: &[[f64; 3]]) -> Result<(Similarity, Vec<usize>)> {
    let first = Similarity::fit(from, to)?;
    let bad = outliers(&residuals(&first, from, to));
    if bad.is_empty() {
        return Ok((first, bad));
    }
    let keep = |p: &[[f64; 3]]| -> Vec<[f64; 3]> {
        p.iter()
            .enumerate()
            .filter(|(i, _)| bad.binary_search(i).is_err())
            .map(|(_, q)| *q)
            .collect()
    };
    match Similarity::fit(&keep(from), &keep(to)) {
        Ok(fit) => Ok((fit, bad)),
        // The others alone cannot fix it: keep the fit of all.
        Err(_) => Ok((first, bad)),
    }
}

/// Whether the points lie (numerically) on one line through `c`: the second
/// largest eigenvalue of their scatter is below `1e-10` of the largest.
fn is_on_a_line(points: &[[f64; 3]], c: [f64; 3]) -> bool {
    let mut S = [[0.0; 4]; 4];
    for &p in points {
        let d = sub(p, c);
        for i in 0..3 {
            for j in 0..3 {
                S[i][j] += d[i] * d[j];
            }
        }
    }
    // Padded to 4 × 4 with a zero row and column: the extra eigenvalue is 0.
    let (mut values, _) = jacobi_eigen(S);
    values.sort_by(|a, b| b.total_cmp(a));
    !(values[0] > 0.0 && values[1] > 1e-10 * values[0])
}

/// The rotation closest to `A` in the Frobenius norm (the rotation factor
/// of its polar decomposition when `det A > 0`; always a proper rotation).
///
/// # Performance
/// Well-conditioned `A` with `det A > 0` (every deformation gradient that
/// does not flip or flatten its triangle) take Higham's scaled Newton
/// iteration, a few 3 × 3 inverses; the others Horn's quaternion, a 4 × 4
/// eigen decomposition several times as costly.
pub fn closest_rotation(A: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    polar_rotation(A).unwrap_or_else(|| {
        // Σ y·R x = tr(R M) for M = Σ x yᵀ; tr(Rᵀ A) = tr(R Aᵀ).
        let At: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| A[j][i]));
        best_rotation(&At)
    })
}

/// The rotation factor of the polar decomposition of `A` by Higham's scaled
/// Newton iteration `X ← (γ X + X⁻ᵀ / γ) / 2`, `γ = (‖X⁻¹‖ / ‖X‖)^½`
/// (Higham, "Computing the polar decomposition, with applications", 1986),
/// which converges quadratically; `None` when `det A` is not clearly
/// positive (the nearest rotation is then not the polar factor, or the
/// iteration would divide by almost nothing) or the iteration does not
/// settle.
pub fn polar_rotation(A: &[[f64; 3]; 3]) -> Option<[[f64; 3]; 3]> {
    let frobenius = |M: &[[f64; 3]; 3]| M.iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
    let size = frobenius(A);
    if !(size.is_finite() && det3(*A) > 1e-9 * size * size * size) {
        return None;
    }
    let mut X = *A;
    for _ in 0..30 {
        let inverse = inverse3(X)?;
        let gamma = (frobenius(&inverse) / frobenius(&X)).sqrt();
        let next: [[f64; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| 0.5 * (gamma * X[i][j] + inverse[j][i] / gamma))
        });
        let step = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| (next[i][j] - X[i][j]).powi(2))
            .sum::<f64>();
        X = next;
        // Quadratic convergence: the step after one of 1e-9 is below rounding.
        if step < 1e-18 {
            return Some(X);
        }
    }
    None
}

/// The rotation `R` minimising `Σ wᵢ |R xᵢ − yᵢ|` (not squared: a robust,
/// L1 fit of directions), by iteratively reweighted least squares started
/// from the least-squares fit: each round is Horn's fit with the weights
/// `wᵢ / |R xᵢ − yᵢ|` of the previous rotation (Weiszfeld's iteration). A
/// minority of pairs far from the others' rotation does not pull it.
pub fn robust_rotation(from: &[[f64; 3]], to: &[[f64; 3]], weights: &[f64]) -> [[f64; 3]; 3] {
    let fit = |weight: &dyn Fn(usize) -> f64| {
        let mut M = [[0.0; 3]; 3];
        let mut total = 0.0;
        for (k, (x, y)) in from.iter().zip(to).enumerate() {
            let w = weight(k);
            total += w;
            for i in 0..3 {
                for j in 0..3 {
                    M[i][j] += w * x[i] * y[j];
                }
            }
        }
        // A tie between turns the directions leave free (all of them
        // parallel) goes to no turn at all.
        for (i, row) in M.iter_mut().enumerate() {
            row[i] += 1e-9 * total;
        }
        best_rotation(&M)
    };
    let mut R = fit(&|k| weights[k]);
    for _ in 0..100 {
        let at = Similarity {
            rotation: R,
            scale: 1.0,
            translation: [0.0; 3],
        };
        let next = fit(&|k| weights[k] / norm(sub(at.rotate(from[k]), to[k])).max(1e-9));
        let step: f64 = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| (next[i][j] - R[i][j]).powi(2))
            .sum();
        R = next;
        if step < 1e-24 {
            break;
        }
    }
    R
}

/// Over-relaxation of Weiszfeld's step (Ostresh 1978: any factor in
/// `[1, 2]` keeps every step a descent): 1.5 takes about half the
/// iterations of the plain step on the transfer's placements.
const MEDIAN_RELAXATION: f64 = 1.5;

/// The weighted geometric median of `points` (each with its weight): the
/// point whose weighted sum of distances to them is least, by Weiszfeld's
/// iteration from the weighted mean (over-relaxed), distances floored at a
/// tiny fraction of the points' spread so that the iteration may land on a
/// point, until a step moves less than 1e-9 of that spread (or a few
/// units in the last place of the answer). Unlike
/// the mean it follows the majority: where most of the weight agrees on a
/// point, the median is that point, whatever the rest say.
///
/// # Panics
/// If `points` is empty or a weight is not positive.
pub fn geometric_median(points: &[([f64; 3], f64)]) -> [f64; 3] {
    let total: f64 = points.iter().map(|p| p.1).sum();
    assert!(total > 0.0, "a median needs points of positive weight");
    let mut x = points
        .iter()
        .fold([0.0; 3], |s, (p, w)| add(s, scale(*p, *w)))
        .map(|c| c / total);
    let spread = points
        .iter()
        .map(|(p, w)| w * norm(sub(*p, x)))
        .sum::<f64>()
        / total;
    if spread == 0.0 {
        return x;
    }
    // Below a few units in the last place of the answer a step is rounding
    // (pairs that agree to rounding would otherwise never stop).
    let ulps = 4.0 * f64::EPSILON * norm(x);
    let (floor, tolerance) = (1e-12 * spread, (1e-9 * spread).max(ulps));
    for _ in 0..200 {
        let (mut sum, mut weight) = ([0.0; 3], 0.0);
        for (p, w) in points {
            let k = w / norm(sub(*p, x)).max(floor);
            sum = add(sum, scale(*p, k));
            weight += k;
        }
        let next: [f64; 3] =
            std::array::from_fn(|i| x[i] + MEDIAN_RELAXATION * (sum[i] / weight - x[i]));
        let step = norm(sub(next, x));
        x = next;
        if step <= tolerance {
            break;
        }
    }
    x
}

/// The rigid motion that best takes the points `from(i)` to `to(i)`, `i`
/// in `indices`, in the least-squares sense, in the plane (`D = 2`) or in
/// space (`D = 3`): the centroids `(a, b)` of both sets and the rotation
/// `R`, so that `to(i) ≈ b + R (from(i) − a)`.
///
/// # Panics
/// If `indices` is empty, or `D` is neither 2 nor 3.
pub fn rigid_fit<const D: usize>(
    indices: &[u32],
    from: impl Fn(usize) -> [f64; D],
    to: impl Fn(usize) -> [f64; D],
) -> ([f64; D], [f64; D], [[f64; D]; D]) {
    assert!(!indices.is_empty(), "a rigid fit needs points");
    let k = indices.len() as f64;
    let mean = |p: &dyn Fn(usize) -> [f64; D]| {
        indices
            .iter()
            .fold([0.0; D], |s, &i| add(s, p(i as usize)))
            .map(|x| x / k)
    };
    let (a, b) = (mean(&from), mean(&to));
    let mut M = [[0.0; D]; D];
    for &i in indices {
        let (x, y) = (sub(from(i as usize), a), sub(to(i as usize), b));
        for r in 0..D {
            for c in 0..D {
                M[r][c] += x[r] * y[c];
            }
        }
    }
    let R: [[f64; D]; D] = match D {
        2 => {
            let angle = (M[0][1] - M[1][0]).atan2(M[0][0] + M[1][1]);
            let (s, c) = angle.sin_cos();
            let R2 = [[c, -s], [s, c]];
            std::array::from_fn(|r| std::array::from_fn(|c| R2[r][c]))
        }
        3 => {
            let R3 = best_rotation(&std::array::from_fn(|r| std::array::from_fn(|c| M[r][c])));
            std::array::from_fn(|r| std::array::from_fn(|c| R3[r][c]))
        }
        _ => panic!("rigid fits are in the plane or in space"),
    };
    (a, b, R)
}

/// Horn's rotation from the cross-covariance `M = Σ x yᵀ` of centred
/// points: the unit quaternion maximising `Σ y·R x`.
pub fn best_rotation(M: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let (sxx, sxy, sxz) = (M[0][0], M[0][1], M[0][2]);
    let (syx, syy, syz) = (M[1][0], M[1][1], M[1][2]);
    let (szx, szy, szz) = (M[2][0], M[2][1], M[2][2]);
    let N = [
        [sxx + syy + szz, syz - szy, szx - sxz, sxy - syx],
        [syz - szy, sxx - syy - szz, sxy + syx, szx + sxz],
        [szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy],
        [sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz],
    ];
    let (values, vectors) = jacobi_eigen(N);
    let k = (0..4)
        .max_by(|&a, &b| values[a].total_cmp(&values[b]))
        .unwrap_or(0);
    let q: [f64; 4] = std::array::from_fn(|i| vectors[i][k]);
    let len = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    let [w, x, y, z] = q.map(|c| c / len);
    [
        [
            w * w + x * x - y * y - z * z,
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            w * w - x * x + y * y - z * z,
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            w * w - x * x - y * y + z * z,
        ],
    ]
}

/// Eigenvalues and eigenvectors (columns) of a symmetric 4 × 4 matrix by
/// cyclic Jacobi rotations.
fn jacobi_eigen(mut A: [[f64; 4]; 4]) -> ([f64; 4], [[f64; 4]; 4]) {
    let mut V = [[0.0; 4]; 4];
    for i in 0..4 {
        V[i][i] = 1.0;
    }
    for _sweep in 0..50 {
        let off: f64 = (0..4)
            .flat_map(|i| (0..4).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| A[i][j] * A[i][j])
            .sum();
        let total: f64 = A.iter().flatten().map(|x| x * x).sum();
        if off <= 1e-30 * total || off == 0.0 {
            break;
        }
        for p in 0..4 {
            for q in p + 1..4 {
                if A[p][q] == 0.0 {
                    continue;
                }
                let theta = (A[q][q] - A[p][p]) / (2.0 * A[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..4 {
                    let (akp, akq) = (A[k][p], A[k][q]);
                    A[k][p] = c * akp - s * akq;
                    A[k][q] = s * akp + c * akq;
                }
                for k in 0..4 {
                    let (apk, aqk) = (A[p][k], A[q][k]);
                    A[p][k] = c * apk - s * aqk;
                    A[q][k] = s * apk + c * aqk;
                }
                for k in 0..4 {
                    let (vkp, vkq) = (V[k][p], V[k][q]);
                    V[k][p] = c * vkp - s * vkq;
                    V[k][q] = s * vkp + c * vkq;
                }
            }
        }
    }
    ([A[0][0], A[1][1], A[2][2], A[3][3]], V)
}

/// The residual `|s R xᵢ + t − yᵢ|` of each pair.
pub fn residuals(fit: &Similarity, from: &[[f64; 3]], to: &[[f64; 3]]) -> Vec<f64> {
    from.iter()
        .zip(to)
        .map(|(&x, &y)| norm(sub(fit.apply(x), y)))
        .collect()
}

/// Pairs whose residual stands out: a modified z-score above 3.5 (Iglewicz
/// and Hoaglin 1993), `0.6745 (rᵢ − median) / MAD`, where MAD is the median
/// absolute deviation of the residuals from their median. Markers on two
/// different characters never fit exactly; one whose residual is far beyond
/// the spread of the others is most likely placed on the wrong feature.
/// Indices in increasing order.
pub fn outliers(residuals: &[f64]) -> Vec<usize> {
    if residuals.len() < 4 {
        return Vec::new();
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        let n = v.len();
        if n % 2 == 1 {
            v[n / 2]
        } else {
            0.5 * (v[n / 2 - 1] + v[n / 2])
        }
    };
    let m = median(&mut residuals.to_vec());
    let mad = median(&mut residuals.iter().map(|r| (r - m).abs()).collect());
    if mad.is_nan() || mad <= 0.0 {
        return Vec::new();
    }
    (0..residuals.len())
        .filter(|&i| 0.6745 * (residuals[i] - m) / mad > 3.5)
        .collect()
}
