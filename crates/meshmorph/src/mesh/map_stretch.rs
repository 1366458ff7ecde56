//! How far a planar triangle's map from one place to another is from a
//! rigid motion: the most it stretches or squeezes along any direction,
//! what a picture carried by the map shows as its texture's distortion.

/// `max(σ1, 1/σ2)` of the affine map taking triangle `from` onto `to`
/// (σ1 ≥ σ2 its singular values): 1 for a rigid motion, 1.1 for a map
/// that stretches or squeezes some direction by 10 %, infinite where `to`
/// is flat (NaN where `from` is). Whether the map turns the triangle over
/// does not count: the signs of the two areas tell.
pub fn map_stretch(from: [[f64; 2]; 3], to: [[f64; 2]; 3]) -> f64 {
    let sub = |p: [f64; 2], q: [f64; 2]| [p[0] - q[0], p[1] - q[1]];
    let (e1, e2) = (sub(from[1], from[0]), sub(from[2], from[0]));
    let (f1, f2) = (sub(to[1], to[0]), sub(to[2], to[0]));
    let det = e1[0] * e2[1] - e1[1] * e2[0];
    // J = [f1 f2] [e1 e2]⁻¹.
    let inverse = [[e2[1] / det, -e2[0] / det], [-e1[1] / det, e1[0] / det]];
    let j = |r: usize, c: usize| f1[r] * inverse[0][c] + f2[r] * inverse[1][c];
    let (a, b, c, d) = (j(0, 0), j(0, 1), j(1, 0), j(1, 1));
    // The singular values of a 2 × 2 matrix are q ± r (Blinn).
    let q = (0.5 * (a + d)).hypot(0.5 * (c - b));
    let r = (0.5 * (a - d)).hypot(0.5 * (c + b));
    (q + r).max(1.0 / (q - r).abs())
}
