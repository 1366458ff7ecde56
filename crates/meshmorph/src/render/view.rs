//! [`View2d`]: the fixed map from the plane of a planar mesh to pixels.

/// An axis-aligned map from world coordinates (y up) to pixel coordinates
/// (y down, `(0, 0)` the top-left corner of the top-left pixel), with the
/// same scale on both axes.
///
/// One view fitted over every frame of an animation keeps the camera still
/// while the mesh moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View2d {
    /// Picture width in pixels.
    pub width: u32,
    /// Picture height in pixels.
    pub height: u32,
    /// Pixels per world unit.
    pub scale: f64,
    /// The world point drawn at the centre of the picture.
    pub center: [f64; 2],
}

/// Pictures are no taller than this many times their width when the height
/// is chosen from the aspect ratio...
const MAX_ASPECT: u32 = 2;
/// ...and no shorter than their width divided by this.
const MIN_ASPECT: u32 = 4;

impl View2d {
    /// The view of a `width` × `height` picture that shows every point of
    /// every frame, as large as possible with at least `margin_px` pixels
    /// of background on each side, centred.
    ///
    /// With `height` `None` the height follows the aspect ratio of the
    /// bounds (plus margins), clamped to between a quarter and twice the
    /// width and rounded up to an even number (video encoders want even
    /// sizes). Non-finite coordinates are ignored; with no points at all
    /// the view shows the unit square. Sizes of 0 count as 1.
    pub fn fitting<'a>(
        frames: impl IntoIterator<Item = &'a [[f64; 2]]>,
        width: u32,
        height: Option<u32>,
        margin_px: u32,
    ) -> Self {
        let [lo, hi] = Self::bounds(frames);
        Self::fitting_bounds(lo, hi, width, height, margin_px)
    }

    /// [`View2d::fitting`] with the longer side `side` pixels: wide bounds
    /// get a picture `side` pixels wide, tall ones `side` pixels high and
    /// as wide as holds them (at least a quarter of that).
    pub fn fitting_longest<'a>(
        frames: impl IntoIterator<Item = &'a [[f64; 2]]>,
        side: u32,
        margin_px: u32,
    ) -> Self {
        let [lo, hi] = Self::bounds(frames);
        let wide = Self::fitting_bounds(lo, hi, side, None, margin_px);
        if wide.height <= side {
            return wide;
        }
        let m = f64::from(margin_px.min(side.saturating_sub(1) / 2));
        let inner =
            (f64::from(side) - 2.0 * m) * (hi[0] / 2.0 - lo[0] / 2.0) / (hi[1] / 2.0 - lo[1] / 2.0);
        let width = if inner.is_finite() {
            ((inner + 2.0 * m).ceil() as u32).clamp(side / 4, side)
        } else {
            side
        };
        Self::fitting_bounds(lo, hi, width.max(1), Some(side), margin_px)
    }

    /// The lowest and highest coordinates of the finite points of
    /// `frames`; the unit square when there is none.
    pub fn bounds<'a>(frames: impl IntoIterator<Item = &'a [[f64; 2]]>) -> [[f64; 2]; 2] {
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for frame in frames {
            for p in frame {
                if p[0].is_finite() && p[1].is_finite() {
                    for k in 0..2 {
                        lo[k] = lo[k].min(p[k]);
                        hi[k] = hi[k].max(p[k]);
                    }
                }
            }
        }
        if lo[0] > hi[0] {
            return [[0.0; 2], [1.0; 2]];
        }
        [lo, hi]
    }

    /// [`View2d::fitting`] for the box from `lo` to `hi` (finite, `lo <= hi`).
    pub fn fitting_bounds(
        lo: [f64; 2],
        hi: [f64; 2],
        width: u32,
        height: Option<u32>,
        margin_px: u32,
    ) -> Self {
        let width = width.max(1);
        // Halves, so that neither the extent nor the centre overflows.
        let half = [hi[0] / 2.0 - lo[0] / 2.0, hi[1] / 2.0 - lo[1] / 2.0];
        let center = [lo[0] / 2.0 + hi[0] / 2.0, lo[1] / 2.0 + hi[1] / 2.0];
        let height = match height {
            Some(h) => h.max(1),
            None => {
                let m = effective_margin(width, margin_px);
                let inner_w = f64::from(width - 2 * m);
                let inner_h = if half[0] > 0.0 {
                    inner_w * (half[1] / half[0])
                } else if half[1] > 0.0 {
                    f64::INFINITY
                } else {
                    inner_w
                };
                let lo_lim = (width / MIN_ASPECT).max(2 * margin_px + 2);
                let hi_lim = width.saturating_mul(MAX_ASPECT).max(lo_lim);
                let h = (inner_h + f64::from(2 * m))
                    .ceil()
                    .clamp(f64::from(lo_lim), f64::from(hi_lim)) as u32;
                h.saturating_add(h % 2)
            }
        };
        let mx = effective_margin(width, margin_px);
        let my = effective_margin(height, margin_px);
        let avail = [
            f64::from(width - 2 * mx) / 2.0,
            f64::from(height - 2 * my) / 2.0,
        ];
        let mut scale = f64::INFINITY;
        for k in 0..2 {
            if half[k] > 0.0 {
                scale = scale.min(avail[k] / half[k]);
            }
        }
        if !scale.is_finite() || scale <= 0.0 {
            // A single point (or bounds so small that the scale overflows).
            scale = if half[0] > 0.0 || half[1] > 0.0 {
                f64::MAX
            } else {
                1.0
            };
        }
        View2d {
            width,
            height,
            scale,
            center,
        }
    }

    /// Pixel coordinates of world point `p`.
    #[inline]
    pub fn to_pixel(&self, p: [f64; 2]) -> [f64; 2] {
        [
            f64::from(self.width) * 0.5 + (p[0] - self.center[0]) * self.scale,
            f64::from(self.height) * 0.5 - (p[1] - self.center[1]) * self.scale,
        ]
    }

    /// World coordinates of pixel point `q` (inverse of [`View2d::to_pixel`]).
    #[inline]
    pub fn to_world(&self, q: [f64; 2]) -> [f64; 2] {
        [
            self.center[0] + (q[0] - f64::from(self.width) * 0.5) / self.scale,
            self.center[1] - (q[1] - f64::from(self.height) * 0.5) / self.scale,
        ]
    }
}

/// The margin actually kept: at most what leaves one pixel in the middle.
fn effective_margin(size: u32, margin: u32) -> u32 {
    margin.min(size.saturating_sub(1) / 2)
}
