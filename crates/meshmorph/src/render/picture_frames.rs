//! A whole morph of one picture into another, set up once: both pictures'
//! drawings (traced sprites or photo rectangles), their compatible meshes,
//! the interpolator between them and the textured frames, so that a frame
//! at any moment is one call that cannot fail. Front ends (the command
//! line, Python) read the pictures and write the frames; the rest is here.

use super::PictureMorph;
use crate::error::{Error, Result};
use crate::interpolate::{Interpolator, InterpolatorOptions, StretchMode};
use crate::io::picture::{
    picture_drawing, picture_meshes, Picture, PictureDrawing, PictureMeshes, PictureShape,
};
use crate::outline::OutlineOptions;

/// The largest side of a frame, pixels.
pub const MAX_FRAME_SIDE: u32 = 16384;

/// The largest tracing tolerance, pixels.
pub const MAX_TRACE_TOLERANCE: f64 = 16.0;

/// How a morph of two pictures is made.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct PictureMorphOptions {
    /// Morph the whole rectangles (photos), even where the pictures have
    /// transparency. Default `false`: a picture with transparency is
    /// traced (a sprite), an opaque one is its rectangle.
    pub frame_only: bool,
    /// How far a sprite's traced outline may stray from where its alpha
    /// crosses one half, pixels, in `(0, 16]`. Default 0.5.
    pub trace_tolerance: f64,
    /// Opaque regions and holes smaller than this, square pixels, are
    /// specks and ignored. Default 16.
    pub min_area: f64,
    /// The frames' width and height, pixels (each side 1 to 16384); the
    /// pictures are stretched onto it. Default `None`: the first
    /// picture's size.
    pub frame_size: Option<(u32, u32)>,
    /// The moments of the morph (fractions from 0 to 1) between which the
    /// blend goes from the first picture to the second. Default `None`:
    /// over the whole morph.
    pub dissolve: Option<[f64; 2]>,
    /// The interpolation of the meshes. Default: its own defaults with
    /// the area-kept stretch, [`InterpolatorOptions::untie_outlines`] and
    /// [`InterpolatorOptions::mend_folds`] on (a knotted outline or a
    /// triangle turned over would draw its piece of picture twice). Photos
    /// have [`InterpolatorOptions::outline_straight`] on whatever this says.
    pub interpolation: InterpolatorOptions,
    /// How the compatible meshes are made. Default:
    /// [`OutlineOptions::for_pictures`] (the maps kept rigid in parts).
    /// Photos have no rigid parts whatever this says: a photo's rectangle
    /// has no parts, and kept rigid in most places its anchors' warp
    /// gathers in creases (an eye moved by a quarter of the picture shows
    /// twice); shared out smoothly, it moves the neighbourhood with it.
    pub outline: OutlineOptions,
}

impl Default for PictureMorphOptions {
    fn default() -> Self {
        Self {
            frame_only: false,
            trace_tolerance: 0.5,
            min_area: 16.0,
            frame_size: None,
            dissolve: None,
            interpolation: InterpolatorOptions::default()
                .with_stretch(StretchMode::AreaBlend)
                .with_untie_outlines(true)
                .with_mend_folds(true),
            outline: OutlineOptions::for_pictures(),
        }
    }
}

impl PictureMorphOptions {
    /// With [`PictureMorphOptions::frame_only`].
    pub fn with_frame_only(mut self, on: bool) -> Self {
        self.frame_only = on;
        self
    }

    /// With [`PictureMorphOptions::trace_tolerance`].
    pub fn with_trace_tolerance(mut self, pixels: f64) -> Self {
        self.trace_tolerance = pixels;
        self
    }

    /// With [`PictureMorphOptions::frame_size`].
    pub fn with_frame_size(mut self, size: Option<(u32, u32)>) -> Self {
        self.frame_size = size;
        self
    }

    /// With [`PictureMorphOptions::dissolve`].
    pub fn with_dissolve(mut self, span: Option<[f64; 2]>) -> Self {
        self.dissolve = span;
        self
    }

    /// With [`PictureMorphOptions::interpolation`].
    pub fn with_interpolation(mut self, options: InterpolatorOptions) -> Self {
        self.interpolation = options;
        self
    }

    /// Every option in its range.
    fn check(&self) -> Result<()> {
        let t = self.trace_tolerance;
        if !(t > 0.0 && t <= MAX_TRACE_TOLERANCE) {
            return Err(Error::InvalidArgument(format!(
                "a tracing tolerance of {t} pixels: give one from 0 (excluded) to {MAX_TRACE_TOLERANCE}, such as 0.5"
            )));
        }
        if let Some((w, h)) = self.frame_size {
            if !(1..=MAX_FRAME_SIDE).contains(&w) || !(1..=MAX_FRAME_SIDE).contains(&h) {
                return Err(Error::InvalidArgument(format!(
                    "frames of {w} × {h} pixels: each side from 1 to {MAX_FRAME_SIDE}"
                )));
            }
        }
        if let Some(d) = self.dissolve {
            if let Some(x) = d.iter().find(|x| !(0.0..=1.0).contains(*x)) {
                return Err(Error::InvalidArgument(format!(
                    "a dissolve from {} to {}: {x} is not a fraction of the morph from 0 to 1",
                    d[0], d[1]
                )));
            }
            if d[1] < d[0] {
                return Err(Error::InvalidArgument(format!(
                    "a dissolve from {} to {}: it ends before it starts (give the start first; the same fraction twice cuts from one picture to the other there)",
                    d[0], d[1]
                )));
            }
        }
        Ok(())
    }
}

/// The weight of the second picture at moment `t` of the morph: `t`
/// itself, or with `dissolve` `[start, end]` 0 before `start`, 1 after
/// `end` and straight between (a step at `start` when `end` is `start`).
pub fn dissolve_blend(t: f64, dissolve: Option<[f64; 2]>) -> f64 {
    match dissolve {
        Some(d) if d[1] > d[0] => ((t - d[0]) / (d[1] - d[0])).clamp(0.0, 1.0),
        Some(d) => {
            if t < d[0] {
                0.0
            } else {
                1.0
            }
        }
        None => t,
    }
}

/// `count` moments evenly from 0 to 1, both ends included (one frame:
/// the start).
pub fn frame_times(count: usize) -> Vec<f64> {
    if count == 1 {
        vec![0.0]
    } else {
        (0..count).map(|k| k as f64 / (count - 1) as f64).collect()
    }
}

/// A morph of one picture into another, set up: frame 0 is the first
/// picture (stretched onto the frame size), the last the second.
pub struct PictureFrames<'a> {
    /// Each picture's drawing: how it was traced, what was left out.
    pub drawings: [PictureDrawing; 2],
    /// The compatible meshes in frame pixels and in each picture's.
    pub meshes: PictureMeshes,
    interpolator: Interpolator<2>,
    morph: PictureMorph<'a>,
    dissolve: Option<[f64; 2]>,
}

impl<'a> PictureFrames<'a> {
    /// The morph of `a` into `b`: each picture's drawing
    /// ([`picture_drawing`]), their compatible meshes with `anchors` (one
    /// point a picture each, in that picture's pixels, x right and y down
    /// from its top-left corner; see [`picture_meshes`]), the
    /// interpolator, and the textured frames ([`PictureMorph`], drawn a
    /// fringe of the tracing's tolerance and 1.5 pixels past the outline).
    /// `names` name the pictures in messages.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] for an option out of its range, a sprite
    /// morphed with a photo (one has transparency, the other none),
    /// a fully transparent picture or one of specks only, or an anchor
    /// outside its picture; the errors of the compatible meshes and of
    /// [`Interpolator::new`].
    pub fn new(
        [a, b]: [&'a Picture; 2],
        anchors: &[Vec<[f64; 2]>],
        options: &PictureMorphOptions,
        names: &[String; 2],
    ) -> Result<Self> {
        options.check()?;
        let drawing = |p: &Picture, name: &str| {
            picture_drawing(
                p,
                options.frame_only,
                options.trace_tolerance,
                options.min_area,
                name,
            )
        };
        let drawings = [drawing(a, &names[0])?, drawing(b, &names[1])?];
        if drawings[0].shape != drawings[1].shape {
            let (sprite, photo) = if drawings[0].shape == PictureShape::Sprite {
                (0, 1)
            } else {
                (1, 0)
            };
            return Err(Error::InvalidArgument(format!(
                "{} has transparency (a sprite, traced) but {} is opaque (a photo, its whole rectangle): give two sprites or two photos, or morph both as rectangles (--frame-only on the command line, frame_only=True in Python)",
                names[sprite], names[photo]
            )));
        }
        let (width, height) = options.frame_size.unwrap_or((a.width, a.height));
        // A photo's rectangle has no parts: its anchors' warp is shared out
        // smoothly, as a photo morph's is.
        let outline = OutlineOptions {
            rigid_parts: options.outline.rigid_parts && drawings[0].shape == PictureShape::Sprite,
            ..options.outline.clone()
        };
        let meshes = picture_meshes(
            &[a, b],
            &[&drawings[0], &drawings[1]],
            anchors,
            (width, height),
            &outline,
            names,
        )?;
        let set = &meshes.set;
        // A photo's outline is the frames' rectangle in both pictures: it
        // stays that rectangle in every frame.
        let interpolation = options
            .interpolation
            .clone()
            .with_outline_straight(drawings[0].shape == PictureShape::Photo);
        let interpolator = Interpolator::new(&set.meshes[0], &set.meshes[1], &interpolation)?;
        let scale = f64::from(width) / f64::from(a.width);
        let fringe = (drawings[0].tolerance.max(drawings[1].tolerance) + 1.5) * scale.max(1.0);
        let morph = PictureMorph::new(
            [a, b],
            &meshes.sources,
            set.meshes[0].triangles(),
            &set.loops,
            (width, height),
            fringe,
            drawings[0].shape,
        )?;
        Ok(Self {
            drawings,
            meshes,
            interpolator,
            morph,
            dissolve: options.dissolve,
        })
    }

    /// The frames' width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        self.morph.size()
    }

    /// Whether the pictures were traced (sprites) or taken whole (photos).
    pub fn shape(&self) -> PictureShape {
        self.drawings[0].shape
    }

    /// The weight of the second picture at moment `t` ([`dissolve_blend`]).
    pub fn blend_at(&self, t: f64) -> f64 {
        dissolve_blend(t, self.dissolve)
    }

    /// The frame at moment `t` (0: the first picture, 1: the second) into
    /// `out` (straight RGBA, `4 × width × height` bytes). Never fails.
    ///
    /// # Panics
    /// When `out` has another length.
    pub fn draw_into(&self, t: f64, out: &mut [u8]) {
        self.morph
            .draw_into(&self.interpolator.at(t), self.blend_at(t), out);
    }

    /// The frame at moment `t` as a new picture.
    pub fn draw(&self, t: f64) -> Picture {
        self.morph.draw(&self.interpolator.at(t), self.blend_at(t))
    }
}
