//! The fixed 256-colour palette of every raster picture.
//!
//! Pictures are drawn in palette indices, not colours: GIF is an indexed
//! format, and a fixed palette means no colour quantisation when encoding.
//! The layout is fixed ([`slot`] for the flat colours of the 2D pictures,
//! [`Ramp`]s of shades for the 3D ones); the colours can be changed.

use super::style::Style2d;

/// An sRGB colour, 8 bits per channel.
pub type Rgb = [u8; 3];

/// Palette indices of the flat colours.
pub mod slot {
    /// Background (white by default). A new canvas is filled with it.
    pub const BACKGROUND: u8 = 0;
    /// Fill of correctly oriented triangles.
    pub const FILL: u8 = 1;
    /// Edges of correctly oriented triangles.
    pub const EDGE: u8 = 2;
    /// Fill of flipped triangles (a warning colour).
    pub const FLIPPED_FILL: u8 = 3;
    /// Edges of flipped triangles.
    pub const FLIPPED_EDGE: u8 = 4;
    /// Black.
    pub const BLACK: u8 = 5;
    /// A mid grey, for frames and labels.
    pub const GREY: u8 = 6;
    /// A light grey, for separators and backdrops.
    pub const LIGHT_GREY: u8 = 7;
    /// A near-black for edges over shaded 3D meshes ([`Style3d::with_edges`](crate::render::Style3d::with_edges)
    /// uses a dark shade of the ramp instead).
    pub const EDGE_3D: u8 = 8;
}

/// The first palette entry of the blends of the flat colours (see
/// [`Palette::with_style`]).
const BLENDS_FIRST: u8 = 9;

/// A run of palette entries holding shades of one colour, darkest first:
/// entry `first + k` is lit at level `k / (len - 1)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ramp {
    /// First palette index.
    pub first: u8,
    /// Number of levels (at least 1; `first + len` at most 256).
    pub len: u8,
}

impl Ramp {
    /// Number of levels of each standard ramp.
    pub const LEVELS: u8 = 32;
    /// Slate to light blue (the default, e.g. for the source meshes).
    pub const BLUE: Ramp = Ramp {
        first: 64,
        len: Self::LEVELS,
    };
    /// Brown to sand (e.g. for the target meshes).
    pub const SAND: Ramp = Ramp {
        first: 96,
        len: Self::LEVELS,
    };
    /// Dark to light green.
    pub const GREEN: Ramp = Ramp {
        first: 128,
        len: Self::LEVELS,
    };
    /// Dark to light grey.
    pub const GREY: Ramp = Ramp {
        first: 160,
        len: Self::LEVELS,
    };
    /// The standard ramps, in order.
    pub const ALL: [Ramp; 4] = [Self::BLUE, Self::SAND, Self::GREEN, Self::GREY];
    /// Number of levels of each ramp of [`Ramp::SCALE`].
    pub const SCALE_LEVELS: u8 = 8;
    /// A colour scale for a value from good to bad (a distance, an error):
    /// seven steps from green through yellow and orange to red, then a dark
    /// purple for what lies past the scale, each a ramp of
    /// [`Ramp::SCALE_LEVELS`] shades so that the surface stays shaded
    /// ([`Ramp::on_scale`]).
    pub const SCALE: [Ramp; 8] = {
        let mut ramps = [Ramp { first: 0, len: 0 }; 8];
        let mut k = 0;
        while k < 8 {
            ramps[k] = Ramp {
                first: 192 + k as u8 * Self::SCALE_LEVELS,
                len: Self::SCALE_LEVELS,
            };
            k += 1;
        }
        ramps
    };

    /// The ramp of [`Ramp::SCALE`] for `fraction` of the scale: step
    /// `⌊7 fraction⌋` from 0 to 1 (the first below 0), the last (past the
    /// scale) from 1 on and for NaN.
    pub fn on_scale(fraction: f64) -> Ramp {
        let past = Self::SCALE.len() - 1;
        let k = if fraction < 1.0 {
            (fraction.max(0.0) * past as f64) as usize
        } else {
            past
        };
        Self::SCALE[k.min(past)]
    }

    /// The palette index of brightness `level` in `[0, 1]` (clamped; NaN is
    /// the darkest shade).
    #[inline]
    pub fn index(self, level: f64) -> u8 {
        let n = self.len.max(1) - 1;
        let k = if level >= 0.0 {
            (level.min(1.0) * f64::from(n)).round() as u8
        } else {
            0
        };
        self.first.saturating_add(k)
    }
}

/// 256 colours indexed by `u8`; see [`slot`] and [`Ramp`] for the layout
/// of [`Palette::standard`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Palette {
    /// The colours.
    pub colors: [Rgb; 256],
}

impl Default for Palette {
    fn default() -> Self {
        Self::standard()
    }
}

/// The base colour of each step of [`Ramp::SCALE`].
const SCALE_COLOURS: [Rgb; 8] = [
    [0x2e, 0x8b, 0x57],
    [0x7c, 0xb3, 0x42],
    [0xc8, 0xc8, 0x2c],
    [0xf0, 0xb4, 0x28],
    [0xee, 0x84, 0x1e],
    [0xde, 0x4e, 0x20],
    [0xb8, 0x1e, 0x2a],
    [0x6e, 0x1a, 0x6e],
];

/// Shadow, base and highlight colours of the standard ramps.
const RAMP_KEYS: [[Rgb; 3]; 4] = [
    [[0x16, 0x22, 0x38], [0x4a, 0x7c, 0xc0], [0xe4, 0xee, 0xfb]],
    [[0x33, 0x1f, 0x12], [0xc4, 0x84, 0x4a], [0xfa, 0xec, 0xd8]],
    [[0x13, 0x2b, 0x1c], [0x4b, 0x9a, 0x66], [0xe2, 0xf4, 0xe6]],
    [[0x1e, 0x1e, 0x22], [0x86, 0x88, 0x8e], [0xf0, 0xf0, 0xf2]],
];

impl Palette {
    /// The standard palette: the default [`Style2d`] colours in the
    /// [`slot`]s, the four standard [`Ramp`]s and the eight of
    /// [`Ramp::SCALE`] (each from a dark shade of its colour through the
    /// colour to a light tint of it).
    pub fn standard() -> Self {
        let mut colors = [[0u8; 3]; 256];
        colors[slot::BLACK as usize] = [0, 0, 0];
        colors[slot::GREY as usize] = [0x80, 0x84, 0x8c];
        colors[slot::LIGHT_GREY as usize] = [0xe6, 0xe8, 0xec];
        colors[slot::EDGE_3D as usize] = [0x10, 0x14, 0x1c];
        let scale_keys = SCALE_COLOURS.map(|base| {
            let mix = |t: f64, to: f64| -> Rgb {
                base.map(|c| from_linear((1.0 - t) * to_linear(c) + t * to))
            };
            [mix(0.8, 0.0), base, mix(0.5, 1.0)]
        });
        for (ramp, keys) in Ramp::ALL
            .iter()
            .chain(&Ramp::SCALE)
            .zip(RAMP_KEYS.iter().chain(&scale_keys))
        {
            for k in 0..ramp.len {
                let t = f64::from(k) / f64::from(ramp.len - 1);
                colors[(ramp.first + k) as usize] = three_stop(*keys, t);
            }
        }
        Palette { colors }.with_style(&Style2d::default())
    }

    /// This palette with the flat [`slot`]s set to the colours of `style`,
    /// and entries 9 to 63 to blends of them (in linear light), so that
    /// anti-aliased planar pictures keep smooth edges: background to fill,
    /// fill to edge, background to edge, and the flipped colours likewise.
    pub fn with_style(mut self, style: &Style2d) -> Self {
        self.colors[slot::BACKGROUND as usize] = style.background;
        self.colors[slot::FILL as usize] = style.fill;
        self.colors[slot::EDGE as usize] = style.edge;
        self.colors[slot::FLIPPED_FILL as usize] = style.flipped_fill;
        self.colors[slot::FLIPPED_EDGE as usize] = style.flipped_edge;
        let pairs: [(Rgb, Rgb, u8); 6] = [
            (style.background, style.fill, 7),
            (style.fill, style.edge, 15),
            (style.background, style.edge, 15),
            (style.flipped_fill, style.flipped_edge, 7),
            (style.background, style.flipped_fill, 5),
            (style.fill, style.flipped_fill, 5),
        ];
        let mut next = BLENDS_FIRST as usize;
        for (a, b, steps) in pairs {
            for k in 1..=steps {
                let t = f64::from(k) / f64::from(steps + 1);
                self.colors[next] = std::array::from_fn(|c| {
                    from_linear((1.0 - t) * to_linear(a[c]) + t * to_linear(b[c]))
                });
                next += 1;
            }
        }
        debug_assert!(next <= 64);
        self
    }

    /// This palette with `ramp` filled by a gradient from `shadow` through
    /// `base` to `highlight` (interpolated in linear light).
    pub fn with_ramp(mut self, ramp: Ramp, shadow: Rgb, base: Rgb, highlight: Rgb) -> Self {
        let n = ramp.len.max(1);
        for k in 0..n {
            let t = if n == 1 {
                0.5
            } else {
                f64::from(k) / f64::from(n - 1)
            };
            if let Some(c) = self.colors.get_mut(ramp.first as usize + k as usize) {
                *c = three_stop([shadow, base, highlight], t);
            }
        }
        self
    }

    /// The colour of palette entry `index`.
    #[inline]
    pub fn get(&self, index: u8) -> Rgb {
        self.colors[index as usize]
    }

    /// The palette as `r, g, b, r, g, b, ...` bytes (768 of them), the form
    /// GIF and PNG encoders take.
    pub fn to_bytes(&self) -> Vec<u8> {
        self.colors.iter().flatten().copied().collect()
    }
}

/// `#rrggbb`.
pub fn hex(c: Rgb) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

pub fn to_linear(c: u8) -> f64 {
    let c = f64::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

pub fn from_linear(l: f64) -> u8 {
    let l = l.clamp(0.0, 1.0);
    let c = if l <= 0.003_130_8 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    (c * 255.0).round() as u8
}

/// Gradient through three colours at `t` in `[0, 1]`, mixed in linear light.
fn three_stop(keys: [Rgb; 3], t: f64) -> Rgb {
    let (a, b, s) = if t < 0.5 {
        (keys[0], keys[1], 2.0 * t)
    } else {
        (keys[1], keys[2], 2.0 * t - 1.0)
    };
    std::array::from_fn(|k| from_linear(to_linear(a[k]) * (1.0 - s) + to_linear(b[k]) * s))
}
