//! Options of the interpolation.

use crate::FactorKind;

/// How the symmetric stretch `S` of each triangle is interpolated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum StretchMode {
    /// `(1−t) I + t S`, as in Alexa et al. 2000. The default: it is the
    /// published method, so frames match other implementations of it, and
    /// for `t` in `[0, 1]` it never collapses a triangle (a convex
    /// combination of two positive definite matrices is positive definite).
    /// Beyond `[0, 1]` an eigenvalue `1 + t(λ − 1)` reaches zero at
    /// `t = 1/(1 − λ)` for a triangle shrunk by `λ < 1`, or at
    /// `t = −1/(λ − 1)` for one stretched by `λ > 1`.
    #[default]
    Linear,
    /// `Sᵗ = V diag(λᵗ) Vᵀ` through the eigen decomposition of `S`: positive
    /// definite for every real `t`, so extrapolation never collapses a
    /// triangle. Stretches then grow geometrically rather than linearly.
    /// (With [`InterpolatorOptions::allow_flips`], a reversed triangle has
    /// no positive definite stretch: its symmetric part is used with
    /// eigenvalues raised to a tiny positive floor, so the fit reaches the
    /// target only approximately at `t = 1`.)
    Log,
    /// Planar only: [`StretchMode::Linear`], but where a triangle's blended
    /// stretch would swell it above the straight blend of its two areas
    /// (stretched along one direction and squeezed along the other, as a
    /// fat drawing's part becoming a thin band is), its smaller principal
    /// stretch is shrunk until its area is that blend; the larger one, along
    /// the band and its outline, stays on its straight blend. Elsewhere the
    /// same as `Linear`. Each frame's area then stays near the straight
    /// blend of the keys' areas where `Linear` swells by a quarter or more
    /// on unlike drawings. Drawings and pictures use it.
    AreaBlend,
}

/// Options of [`Interpolator::new`](crate::Interpolator::new).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct InterpolatorOptions {
    /// Make rotation angles continuous across neighbouring triangles
    /// (Baxter et al. 2008). Default `true`; without it, any part that turns
    /// by more than half a turn tears.
    pub consistency: bool,
    /// Whole extra turns added to every triangle's rotation: `2π · turns`
    /// radians, counter-clockwise for positive values. Default 0.
    pub turns: i32,
    /// How stretches are interpolated. Default [`StretchMode::Linear`].
    pub stretch: StretchMode,
    /// Accept triangles whose orientation is reversed between source and
    /// target instead of failing. Default `false`.
    pub allow_flips: bool,
    /// Which Cholesky variant factors the system. Default [`FactorKind::Auto`].
    pub factor: FactorKind,
    /// Planar only, for [`Interpolator`](crate::Interpolator) and
    /// [`Sequence`](crate::Sequence) frames (not blends): a frame in which
    /// triangles turn over is mended where they are. For each group of
    /// them, the inner vertices within two rings (then four, eight,
    /// sixteen) are moved until every triangle around them is positive, by
    /// the untangling that makes compatible meshes (the foldover-free
    /// energy of Garanzha et al. 2021, against the first key's triangles);
    /// the rest of the frame, and its outline always, stay as the fit made
    /// them. Where the untangling stalls (a jagged stretch of outline bent
    /// so far that a triangle's one free corner has little room), the
    /// vertices within sixteen rings are moved in turn, each to where the
    /// smallest of its triangles is largest (Freitag and Plassmann 2000).
    /// A group neither mends (where the outline itself folds, or a
    /// triangle has its three corners on it, which compatible meshes made
    /// from drawings never have) is left as it is. A
    /// frame with nothing turned over is unchanged (one pass over its
    /// triangles tells); a frame with folds takes milliseconds to a good
    /// part of a second more. Default `false`: the published method's
    /// frames. Drawings and pictures turn it on: where a drawing's maps
    /// disagree a great deal (a round shape into a thin curl) the fit turns
    /// triangles over inside an outline that stays whole.
    pub mend_folds: bool,
    /// Untie each planar frame's outline where the fit crumples a short
    /// stretch of it into a knot that crosses itself (a few points, at
    /// most an eighth of their loop, gathered a fraction of an edge
    /// across): that stretch is laid straight between the points on either
    /// side, its points in order and spaced as the fit spaced them; the
    /// rest of the frame stays as the fit made it (then mended, with
    /// [`Self::mend_folds`]). Two far places of the outline that meet are
    /// left as they are. A frame whose outline is simple is unchanged (one
    /// sweep over its boundary edges tells, microseconds). Default
    /// `false`: the published method's frames. Drawings and pictures turn
    /// it on.
    pub untie_outlines: bool,
    /// Give each planar frame's outline the straight blend of its edges'
    /// lengths in the two keys around it, each edge in the direction the
    /// fit gives it, the loop closed by spreading the gap over its edges
    /// (Sederberg et al. 1993), and move the inside with it (the same fit
    /// with the outline held: one more back-substitution a frame). Where two
    /// drawings' maps disagree a great deal, the fit alone pulls the outline
    /// in, nearly every edge 10 to 17 % shorter than its blend at half-way.
    /// A rigid turn is unchanged. Done before [`Self::untie_outlines`] and
    /// [`Self::mend_folds`]. Default `false`: the published method's
    /// frames. Drawings turn it on; pictures do not (what a picture's
    /// frames show is its texture, and on the demo's turning arm its
    /// stretch grew from 1.55 to 1.63 with it).
    pub outline_lengths: bool,
    /// Put each planar frame's outline on the straight blend of its points'
    /// places in the two keys around it, and move the inside with it (the
    /// fit with the outline held, as [`Self::outline_lengths`] does; it
    /// takes that option's place when both are set). For pictures taken
    /// whole (photos), whose outline is the frames' rectangle in every
    /// key: the fit alone pulls the rectangle's sides and corners in where
    /// anchors inside move, and the frame's edge shows through. Default
    /// `false`. Photos turn it on.
    pub outline_straight: bool,
}

impl Default for InterpolatorOptions {
    fn default() -> Self {
        Self {
            consistency: true,
            turns: 0,
            stretch: StretchMode::Linear,
            allow_flips: false,
            factor: FactorKind::Auto,
            mend_folds: false,
            untie_outlines: false,
            outline_lengths: false,
            outline_straight: false,
        }
    }
}

impl InterpolatorOptions {
    /// Sets [`InterpolatorOptions::consistency`].
    pub fn with_consistency(mut self, on: bool) -> Self {
        self.consistency = on;
        self
    }
    /// Sets [`InterpolatorOptions::turns`].
    pub fn with_turns(mut self, turns: i32) -> Self {
        self.turns = turns;
        self
    }
    /// Sets [`InterpolatorOptions::stretch`].
    pub fn with_stretch(mut self, mode: StretchMode) -> Self {
        self.stretch = mode;
        self
    }
    /// Sets [`InterpolatorOptions::allow_flips`].
    pub fn with_allow_flips(mut self, allow: bool) -> Self {
        self.allow_flips = allow;
        self
    }
    /// Sets [`InterpolatorOptions::factor`].
    pub fn with_factor(mut self, kind: FactorKind) -> Self {
        self.factor = kind;
        self
    }
    /// Sets [`InterpolatorOptions::mend_folds`].
    pub fn with_mend_folds(mut self, on: bool) -> Self {
        self.mend_folds = on;
        self
    }
    /// Sets [`InterpolatorOptions::outline_lengths`].
    pub fn with_outline_lengths(mut self, on: bool) -> Self {
        self.outline_lengths = on;
        self
    }

    /// Sets [`InterpolatorOptions::outline_straight`].
    pub fn with_outline_straight(mut self, on: bool) -> Self {
        self.outline_straight = on;
        self
    }

    /// Sets [`InterpolatorOptions::untie_outlines`].
    pub fn with_untie_outlines(mut self, on: bool) -> Self {
        self.untie_outlines = on;
        self
    }
}
