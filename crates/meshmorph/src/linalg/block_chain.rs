//! Symmetric positive definite systems whose unknowns are points of the
//! plane in a chain: each point coupled to the one before and the one
//! after by a 2 × 2 block (block tridiagonal), as the points of an open
//! polyline are. Factored by block elimination (the Thomas algorithm) and
//! solved in time linear in the number of points.

/// A 2 × 2 block, by rows.
pub type Block = [[f64; 2]; 2];

/// A factored chain: row `i` of the system is
/// `C_{i−1}ᵀ x_{i−1} + D_i x_i + C_i x_{i+1} = b_i`.
#[derive(Clone, Debug)]
pub struct PlanarChain {
    /// The inverse of each point's diagonal block once the points before it
    /// are eliminated.
    inverse: Vec<Block>,
    /// `C_i`, the block coupling point `i` to point `i + 1`.
    next: Vec<Block>,
}

impl PlanarChain {
    /// Factors the chain with diagonal blocks `diagonal` and couplings
    /// `next` (`next[i]` between points `i` and `i + 1`; one fewer than the
    /// points); none when the system is not positive definite (a block to
    /// invert is not, or is not finite).
    pub fn new(diagonal: &[Block], next: Vec<Block>) -> Option<Self> {
        debug_assert_eq!(next.len() + 1, diagonal.len().max(1));
        let mut inverse: Vec<Block> = Vec::with_capacity(diagonal.len());
        for (i, d) in diagonal.iter().enumerate() {
            let e = match i {
                0 => *d,
                _ => {
                    let c = &next[i - 1];
                    sub(d, &mul(&transpose(c), &mul(&inverse[i - 1], c)))
                }
            };
            inverse.push(inverse_spd(&e)?);
        }
        Some(Self { inverse, next })
    }

    /// Number of points.
    pub(crate) fn len(&self) -> usize {
        self.inverse.len()
    }

    /// Overwrites `rhs` (one right-hand side per point) with the solution.
    ///
    /// # Panics
    /// If `rhs` does not have one row per point.
    #[track_caller]
    pub fn solve(&self, rhs: &mut [[f64; 2]]) {
        assert_eq!(rhs.len(), self.len(), "one right-hand side per point");
        for i in 1..rhs.len() {
            let c = transpose(&self.next[i - 1]);
            let y = apply(&c, &apply(&self.inverse[i - 1], &rhs[i - 1]));
            rhs[i] = [rhs[i][0] - y[0], rhs[i][1] - y[1]];
        }
        for i in (0..rhs.len()).rev() {
            let mut y = rhs[i];
            if i + 1 < rhs.len() {
                let c = apply(&self.next[i], &rhs[i + 1]);
                y = [y[0] - c[0], y[1] - c[1]];
            }
            rhs[i] = apply(&self.inverse[i], &y);
        }
    }
}

fn mul(a: &Block, b: &Block) -> Block {
    std::array::from_fn(|i| std::array::from_fn(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j]))
}

pub fn transpose(a: &Block) -> Block {
    [[a[0][0], a[1][0]], [a[0][1], a[1][1]]]
}

fn sub(a: &Block, b: &Block) -> Block {
    std::array::from_fn(|i| std::array::from_fn(|j| a[i][j] - b[i][j]))
}

pub fn apply(a: &Block, x: &[f64; 2]) -> [f64; 2] {
    [
        a[0][0] * x[0] + a[0][1] * x[1],
        a[1][0] * x[0] + a[1][1] * x[1],
    ]
}

/// The inverse of a symmetric positive definite block; none otherwise.
fn inverse_spd(a: &Block) -> Option<Block> {
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    (a[0][0] > 0.0 && det > 0.0 && det.is_finite()).then(|| {
        [
            [a[1][1] / det, -a[0][1] / det],
            [-a[1][0] / det, a[0][0] / det],
        ]
    })
}
