//! Limited-memory BFGS, the minimiser of the outline wing's energies
//! (the untangling, the relaxation and the rigid settle), and the moves
//! between free points and its unknowns (each point's x, then its y).

/// The coordinates of `points` as unknowns: x, y of the first, then of
/// the next, ...
pub fn unknowns(points: &[[f64; 2]]) -> Vec<f64> {
    points.iter().flat_map(|p| [p[0], p[1]]).collect()
}

/// `points` placed at the unknowns `x` (two for each point).
pub fn place(x: &[f64], points: &mut [[f64; 2]]) {
    for (p, c) in points.iter_mut().zip(x.chunks_exact(2)) {
        *p = [c[0], c[1]];
    }
}

/// The gradient of each point, `grad`, as the unknowns' gradient `g`.
pub fn gather(grad: &[[f64; 2]], g: &mut [f64]) {
    for (c, q) in g.chunks_exact_mut(2).zip(grad) {
        c.copy_from_slice(q);
    }
}

/// Limited-memory BFGS (Nocedal 1980) with a backtracking line search on
/// the free coordinates `x`, at most `iterations` steps.
pub(super) fn lbfgs(
    x: &mut [f64],
    iterations: usize,
    f: impl FnMut(&[f64], &mut [f64]) -> f64,
) -> f64 {
    lbfgs_scaled(x, iterations, None, f)
}

/// [`lbfgs`] with a diagonal preconditioner: `scale` holds, for each
/// coordinate, the inverse of an estimate of the energy's second
/// derivative along it, which the two-loop recursion starts from in
/// place of a multiple of the identity (Nocedal and Wright 2006, 7.2).
/// On a graded mesh, whose small triangles are stiffer than its large
/// ones by the square of their size ratio, it evens out the steps.
///
/// The vector work runs with AVX2 (x86-64-v3) where the processor has it
/// (chosen when the program runs).
pub fn lbfgs_scaled(
    x: &mut [f64],
    iterations: usize,
    scale: Option<&[f64]>,
    f: impl FnMut(&[f64], &mut [f64]) -> f64,
) -> f64 {
    pulp::Arch::new().dispatch(Minimise {
        x,
        iterations,
        scale,
        f,
    })
}

/// A run of [`lbfgs_scaled`], for the dispatch on the processor's vector
/// instructions.
struct Minimise<'a, F> {
    x: &'a mut [f64],
    iterations: usize,
    scale: Option<&'a [f64]>,
    f: F,
}

impl<F: FnMut(&[f64], &mut [f64]) -> f64> pulp::WithSimd for Minimise<'_, F> {
    type Output = f64;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _: S) -> f64 {
        steps(self.x, self.iterations, self.scale, self.f)
    }
}

/// The steps of [`lbfgs_scaled`].
#[inline(always)]
fn steps(
    x: &mut [f64],
    iterations: usize,
    scale: Option<&[f64]>,
    mut f: impl FnMut(&[f64], &mut [f64]) -> f64,
) -> f64 {
    let scaled = |i: usize| scale.map_or(1.0, |m| m[i]);
    const MEMORY: usize = 8;
    let len = x.len();
    let mut g = vec![0.0; len];
    let mut fx = f(x, &mut g);
    let mut s_hist: Vec<Vec<f64>> = Vec::with_capacity(MEMORY);
    let mut y_hist: Vec<Vec<f64>> = Vec::with_capacity(MEMORY);
    let mut rho: Vec<f64> = Vec::with_capacity(MEMORY);
    let mut d = vec![0.0; len];
    let mut x_new = vec![0.0; len];
    let mut g_new = vec![0.0; len];
    let (mut s_new, mut y_new) = (vec![0.0; len], vec![0.0; len]);
    let mut alpha_hist = [0.0; MEMORY];
    for it in 0..iterations {
        let gnorm = dot(&g, &g).sqrt();
        if gnorm == 0.0 || !gnorm.is_finite() {
            break;
        }
        // Two-loop recursion.
        d.copy_from_slice(&g);
        for k in (0..s_hist.len()).rev() {
            let a = rho[k] * dot(&s_hist[k], &d);
            alpha_hist[k] = a;
            for (di, yi) in d.iter_mut().zip(&y_hist[k]) {
                *di -= a * yi;
            }
        }
        let gamma = match s_hist.len() {
            0 => {
                1.0 / match scale {
                    None => dot(&d, &d),
                    Some(m) => weighted_dot(&d, m, &d),
                }
                .sqrt()
            }
            k => {
                let y = &y_hist[k - 1];
                dot(&s_hist[k - 1], y)
                    / match scale {
                        None => dot(y, y),
                        Some(m) => weighted_dot(y, m, y),
                    }
            }
        };
        for (i, di) in d.iter_mut().enumerate() {
            *di *= gamma * scaled(i);
        }
        for k in 0..s_hist.len() {
            let beta = rho[k] * dot(&y_hist[k], &d);
            for (di, si) in d.iter_mut().zip(&s_hist[k]) {
                *di += (alpha_hist[k] - beta) * si;
            }
        }
        for di in d.iter_mut() {
            *di = -*di;
        }
        let mut slope = dot(&g, &d);
        if slope >= 0.0 {
            // Not a descent direction: restart along the gradient.
            s_hist.clear();
            y_hist.clear();
            rho.clear();
            for (di, gi) in d.iter_mut().zip(&g) {
                *di = -gi / gnorm;
            }
            slope = -gnorm;
        }
        let mut step = 1.0;
        let mut accepted = false;
        for _ in 0..30 {
            for ((xn, xi), di) in x_new.iter_mut().zip(x.iter()).zip(&d) {
                *xn = xi + step * di;
            }
            let fn_ = f(&x_new, &mut g_new);
            if fn_.is_finite() && fn_ <= fx + 1e-4 * step * slope {
                accepted = true;
                for ((si, a), b) in s_new.iter_mut().zip(&x_new).zip(x.iter()) {
                    *si = a - b;
                }
                for ((yi, a), b) in y_new.iter_mut().zip(&g_new).zip(&g) {
                    *yi = a - b;
                }
                let sy = dot(&s_new, &y_new);
                if sy > 1e-12 * dot(&s_new, &s_new).sqrt() * dot(&y_new, &y_new).sqrt() {
                    // Once the memory is full, the oldest pair's buffers
                    // hold the next step's.
                    let (s, y) = if s_hist.len() == MEMORY {
                        rho.remove(0);
                        (s_hist.remove(0), y_hist.remove(0))
                    } else {
                        (vec![0.0; len], vec![0.0; len])
                    };
                    s_hist.push(std::mem::replace(&mut s_new, s));
                    y_hist.push(std::mem::replace(&mut y_new, y));
                    rho.push(1.0 / sy);
                }
                let decrease = fx - fn_;
                x.copy_from_slice(&x_new);
                g.copy_from_slice(&g_new);
                fx = fn_;
                if decrease <= 1e-12 * fx.abs().max(1e-300) && it > 0 {
                    return fx;
                }
                break;
            }
            step *= 0.5;
        }
        if !accepted {
            break;
        }
    }
    fx
}

/// The dot product of `u` and `v`, summed in four lanes (one running sum
/// waits on each addition; four keep the adder busy).
#[inline(always)]
fn dot(u: &[f64], v: &[f64]) -> f64 {
    let mut lanes = [0.0; 4];
    let (uc, vc) = (u.chunks_exact(4), v.chunks_exact(4));
    let tail: f64 = uc
        .remainder()
        .iter()
        .zip(vc.remainder())
        .map(|(a, b)| a * b)
        .sum();
    for (a, b) in uc.zip(vc) {
        for k in 0..4 {
            lanes[k] += a[k] * b[k];
        }
    }
    (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]) + tail
}

/// The sum of `u[i] w[i] v[i]`, in four lanes as [`dot`].
#[inline(always)]
fn weighted_dot(u: &[f64], w: &[f64], v: &[f64]) -> f64 {
    let mut lanes = [0.0; 4];
    let (uc, wc, vc) = (u.chunks_exact(4), w.chunks_exact(4), v.chunks_exact(4));
    let tail: f64 = uc
        .remainder()
        .iter()
        .zip(wc.remainder())
        .zip(vc.remainder())
        .map(|((a, m), b)| a * m * b)
        .sum();
    for ((a, m), b) in uc.zip(wc).zip(vc) {
        for k in 0..4 {
            lanes[k] += a[k] * m[k] * b[k];
        }
    }
    (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]) + tail
}
