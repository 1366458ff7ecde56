//! The untangling: a mesh placed in another drawing, some of its
//! triangles turned over, moved until every triangle is positive, each as
//! close to its shape in the reference as the foldover-free energy of
//! Garanzha, Kaporin, Kudryavtseva, Protais, Ray and Sokolov (2021,
//! "Foldover-free maps in 50 lines of code") makes it, in rounds of
//! L-BFGS with a decreasing regularisation.
//!
//! An untangling can be stopped and taken up again where it stopped
//! ([`Untangling::go`] with more patience): the rounds it runs are the
//! same either way, when each taking up lowers the regularisation at the
//! same pace ([`Patience::least_fall`]).

use std::sync::atomic::{AtomicBool, Ordering};

use super::energy::{chi, Energy};
use super::lbfgs::{gather, lbfgs, place, unknowns};
use super::mapped::area_from_boundary;

/// How long the untangling keeps going: at most `rounds` rounds of
/// L-BFGS with one regularisation each (counted from the untangling's
/// start, however often it was taken up), and it gives up once `stall`
/// rounds in a row have not made the turned-over triangles fewer, or
/// when `called_off` is set (another try has already given what this one
/// would be for). Each round lowers the regularisation's target by at
/// least `least_fall` (Garanzha et al.'s `σ`, `1 − E/E_prev` where the
/// energy fell by more): [`PAPER_FALL`] or [`BRISK_FALL`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct Patience<'a> {
    pub(crate) rounds: usize,
    pub(crate) stall: usize,
    /// The least fraction by which a round lowers the regularisation's
    /// target.
    pub(crate) least_fall: f64,
    pub(crate) called_off: Option<&'a AtomicBool>,
}

impl<'a> Patience<'a> {
    /// A first look, for untanglings that are taken up again with
    /// [`Patience::LONG`] when no other gives valid meshes: like drawings
    /// untangle in a round or two, and the rounds spent are not lost to
    /// the one taken up.
    pub(crate) const FIRST_LOOK: Patience<'static> = Patience {
        rounds: 12,
        stall: 6,
        least_fall: PAPER_FALL,
        called_off: None,
    };
    /// Enough for like drawings, and a quick give-up on hard pairs.
    pub(crate) const SHORT: Patience<'static> = Patience {
        rounds: 30,
        stall: 6,
        least_fall: PAPER_FALL,
        called_off: None,
    };
    /// For unlike drawings (a fat shape into a thin spiral band), whose
    /// untangling goes on shrinking the turned-over triangles for
    /// hundreds of rounds before the last one turns up.
    pub(crate) const LONG: Patience<'static> = Patience {
        rounds: 400,
        stall: 40,
        least_fall: PAPER_FALL,
        called_off: None,
    };

    /// The same patience with the regularisation lowered faster
    /// ([`BRISK_FALL`]).
    pub(crate) const fn brisk(self) -> Self {
        Patience {
            least_fall: BRISK_FALL,
            ..self
        }
    }

    /// The same patience, given up as soon as `flag` is set.
    pub(crate) fn unless<'b>(self, flag: &'b AtomicBool) -> Patience<'b> {
        Patience {
            rounds: self.rounds,
            stall: self.stall,
            least_fall: self.least_fall,
            called_off: Some(flag),
        }
    }

    fn called_off(&self) -> bool {
        self.called_off.is_some_and(|f| f.load(Ordering::Relaxed))
    }
}

/// L-BFGS steps in a round of the untangling. The regularisation's
/// schedule more than how far a round gets sets how many rounds it
/// takes: on the 500-point star into the curl (1,301 free points, as the
/// meshes were made on 2026-12-04), with the paper's floor of 0.1 on the
/// fall of the regularisation ([`PAPER_FALL`]), 150 steps a round
/// untangled in 62 rounds and 1.25 s, 60 in 64 and 0.74 s, 30 in 68 and
/// 0.40 s, and 10 gave up. Harder pairs need longer rounds:
/// of 16 random polygons into a thick curl, 150 and 60 steps mapped the
/// same 10 (the others go to the overlay), 30 only 6 (BENCHMARKS.md).
const STEPS_PER_ROUND: usize = 60;

/// The least fraction by which a round lowers the regularisation's
/// target in Garanzha et al.'s schedule. A round of the untangling lowers
/// the energy by less than a tenth, so this floor, not the energy, sets
/// how many rounds an unlike pair takes.
const PAPER_FALL: f64 = 0.1;

/// A floor twice the paper's: the regularisation halves in three rounds, not
/// seven. On the 500-point star into the curl (its meshes of 2026-12-07)
/// 0.1 untangled in 73 rounds, 0.15 in 49, 0.2 in 37, 0.3 in 24, 0.4 in
/// 17. Of 270 random pairs (`outline_stress`, seeds 1 to 3) the same 12
/// went to the overlay with 0.1 and 0.2, one more with 0.3 and two more
/// with 0.5; but a spiky polygon into a thin spiral untangled with 0.1
/// and not with 0.2 or 0.3. So the compatible meshes try it first and
/// take up the paper's floor afresh where it gives up, and the mending
/// of frames tries its widest patch again at the paper's floor
/// (BENCHMARKS.md, "The untangling's regularisation lowered faster").
const BRISK_FALL: f64 = 0.2;

/// L-BFGS steps on the energy itself (unregularised, with a barrier)
/// once a round leaves every triangle positive, if that round may have
/// run to its cap: with its 60 they make the 150 a round had before, so
/// the shapes the improvement starts from are as even as they were then.
/// A like pair's single round stops on its own and goes no further.
/// (Going on with the last round's regularisation instead, kept when
/// still valid, mended the 500-point star to curl's frames in 35 to 39 ms
/// each against 21 to 26 ms, with 30 steps a round.)
const POLISH_STEPS: usize = 90;

/// An untangling under way: the vertices from `n` on of a mesh move so
/// that every triangle is positive (the first `n` stay where they are),
/// each as close to its shape in the reference as the foldover-free
/// energy makes it, in rounds of L-BFGS with a decreasing regularisation
/// ([`STEPS_PER_ROUND`] steps each); after the first round that leaves
/// every triangle positive, no further rounds, and [`POLISH_STEPS`] more
/// on the energy itself when that round may have run to its cap
/// ([`Untangling::finish`]). (Going on until the energy settles evens out
/// the shapes further, which the flips, splits, relaxation and rigid
/// settle that follow do anyway: on the picture benchmark at 4096 x 4096
/// it took the compatible meshes from 0.51 to 0.85 s and changed no
/// measure.)
pub(crate) struct Untangling<'a> {
    energy: Energy<'a>,
    positions: Vec<[f64; 2]>,
    fixed: usize,
    unknowns: Vec<f64>,
    gradient: Vec<[f64; 2]>,
    /// The smallest determinant of the triangles' maps: positive once
    /// every triangle is.
    mindet: f64,
    /// The regularisation of the next round, and the energy the last
    /// round ended at.
    eps: f64,
    energy_before: f64,
    /// The fewest turned-over triangles after a round so far, and the
    /// rounds since.
    fewest: usize,
    stalled: usize,
    rounds: usize,
    /// Evaluations of the energy in the last round (a step takes one or
    /// more): fewer than the cap on steps means it stopped before the
    /// cap, because the energy no longer fell.
    evaluations: usize,
}

impl<'a> Untangling<'a> {
    /// The untangling of `positions` (the first `fixed` of them held)
    /// towards the shapes of `reference`'s `triangles`, none of its
    /// rounds run yet.
    pub(crate) fn new(
        reference: &[[f64; 2]],
        triangles: &'a [[u32; 3]],
        positions: Vec<[f64; 2]>,
        fixed: usize,
    ) -> Self {
        let area = area_from_boundary(&positions, triangles, fixed);
        let energy = Energy::against(reference, triangles, area, 1.0 / 128.0);
        let unknowns = unknowns(&positions[fixed..]);
        let gradient = vec![[0.0; 2]; positions.len()];
        let mindet = energy.min_det(&positions);
        let eps = (1e-12 + 0.04 * mindet.min(0.0).powi(2)).sqrt();
        let energy_before = energy.eval(&positions, eps, None);
        Self {
            energy,
            positions,
            fixed,
            unknowns,
            gradient,
            mindet,
            eps,
            energy_before,
            fewest: usize::MAX,
            stalled: 0,
            rounds: 0,
            evaluations: 0,
        }
    }

    /// Whether every triangle is positive (by the energy's measure; the
    /// caller checks with its own margin).
    pub(crate) fn untangled(&self) -> bool {
        self.mindet > 0.0 || self.positions.len() == self.fixed
    }

    /// Runs rounds until every triangle is positive or `patience` says
    /// stop; then whether every triangle is positive. Taken up again
    /// with more patience, it goes on from the round it stopped at.
    pub(crate) fn go(&mut self, patience: Patience<'_>) -> bool {
        while !self.untangled() && self.rounds < patience.rounds && self.stalled < patience.stall {
            if patience.called_off() {
                break;
            }
            self.round(patience.least_fall);
        }
        self.untangled()
    }

    /// One round of L-BFGS at the current regularisation, then the next
    /// regularisation from Garanzha et al.'s schedule.
    fn round(&mut self, least_fall: f64) {
        let n = self.fixed;
        self.rounds += 1;
        self.evaluations = 0;
        let e = {
            let (energy, eps) = (&self.energy, self.eps);
            let (b, grad, evaluations) = (
                &mut self.positions,
                &mut self.gradient,
                &mut self.evaluations,
            );
            lbfgs(&mut self.unknowns, STEPS_PER_ROUND, |x, g| {
                *evaluations += 1;
                place(x, &mut b[n..]);
                let e = energy.eval(b, eps, Some(grad));
                gather(&grad[n..], g);
                e
            })
        };
        place(&self.unknowns, &mut self.positions[n..]);
        self.mindet = self.energy.min_det(&self.positions);
        if self.mindet > 0.0 {
            return;
        }
        // Given up on (by `go`) when the turned-over triangles stop
        // getting fewer: the overlay will do.
        let inverted = self.energy.inverted(&self.positions);
        if inverted < self.fewest {
            self.fewest = inverted;
            self.stalled = 0;
        } else {
            self.stalled += 1;
        }
        let sigma = (1.0 - e / self.energy_before).max(least_fall);
        let mu = (1.0 - sigma) * chi(self.mindet, self.eps);
        self.eps = if self.mindet < mu {
            2.0 * (mu * (mu - self.mindet)).sqrt()
        } else {
            1e-13
        };
        self.energy_before = e;
    }

    /// The positions reached: when every triangle is positive and the
    /// last round may have run to its cap, after [`POLISH_STEPS`] more on
    /// the energy itself. They may still hold turned-over triangles; the
    /// caller checks.
    pub(crate) fn finish(mut self) -> Vec<[f64; 2]> {
        if self.positions.len() > self.fixed
            && self.mindet > 0.0
            && self.evaluations >= STEPS_PER_ROUND
        {
            descend_positive(&self.energy, &mut self.positions, self.fixed, POLISH_STEPS);
        }
        self.positions
    }
}

/// Moves the vertices from `n` on of `b` (the first `n` stay where they
/// are) so that every triangle is positive, each as close to its shape
/// in `a` as the foldover-free energy makes it ([`Untangling`], as
/// patient as `patience`). The result may still hold turned-over
/// triangles; the caller checks.
pub(crate) fn untangle(
    a: &[[f64; 2]],
    triangles: &[[u32; 3]],
    b: Vec<[f64; 2]>,
    n: usize,
    patience: Patience<'_>,
) -> Vec<[f64; 2]> {
    if b.len() == n {
        return b;
    }
    let mut untangling = Untangling::new(a, triangles, b, n);
    untangling.go(patience);
    untangling.finish()
}

/// Moves the vertices from `n` on of a valid mesh `b` (the first `n`
/// stay) to lower `energy` unregularised, with a barrier that keeps every
/// triangle positive: at most `steps` L-BFGS steps.
pub(super) fn descend_positive(energy: &Energy<'_>, b: &mut [[f64; 2]], n: usize, steps: usize) {
    let mut x = unknowns(&b[n..]);
    let mut work = b.to_vec();
    let mut grad = vec![[0.0; 2]; b.len()];
    lbfgs(&mut x, steps, |x, g| {
        place(x, &mut work[n..]);
        let e = energy.eval_positive(&work, Some(&mut grad));
        if e.is_finite() {
            gather(&grad[n..], g);
        }
        e
    });
    place(&x, &mut b[n..]);
}
