//! A picture as a texture: sampled bilinearly in premultiplied alpha, with
//! a mipmap for triangles drawn much smaller than they are in the picture.
//!
//! Rounding and flooring here are written as casts: `f32::round` and
//! `f64::floor` are calls into the C library on x86-64 without SSE 4.1,
//! and took a third of a frame's drawing.

use rayon::prelude::*;

use crate::io::picture::Picture;

/// A colour with premultiplied alpha, each channel from 0 to 1.
pub(crate) type Premultiplied = [f32; 4];

/// One level of the mipmap below the picture itself: premultiplied RGBA,
/// 16 bits a channel (1 = 65535).
struct Level {
    width: usize,
    height: usize,
    texels: Vec<[u16; 4]>,
}

/// A picture and its mipmap: level k is the picture halved k times, each
/// texel the average of the 2 × 2 texels above it. Level 0 is the picture
/// itself, premultiplied as it is sampled, so that a sample at a pixel's
/// centre gives that pixel exactly. Past the edge, texels are transparent
/// (a sprite), or with `repeated` each is the nearest texel of the edge (a
/// photo: the whole rectangle is the drawing, and its edge pixels are as
/// opaque as the rest); a halving at an odd edge averages the texels
/// there are.
pub(crate) struct Texture<'a> {
    picture: &'a Picture,
    levels: Vec<Level>,
    repeated: bool,
}

const U16: f32 = 65535.0;

impl<'a> Texture<'a> {
    /// The texture of `picture`, its mipmap made down to 1 × 1 (rows in
    /// parallel), its edge texels `repeated` past the edge or not.
    pub fn new(picture: &'a Picture, repeated: bool) -> Self {
        let mut levels: Vec<Level> = Vec::new();
        let (mut w, mut h) = (picture.width as usize, picture.height as usize);
        while w > 1 || h > 1 {
            let (nw, nh) = (w.div_ceil(2), h.div_ceil(2));
            let mut texels = vec![[0u16; 4]; nw * nh];
            let above = levels.last();
            texels.par_chunks_mut(nw).enumerate().for_each(|(y, row)| {
                for (x, texel) in row.iter_mut().enumerate() {
                    let mut sum = [0f32; 4];
                    let mut inside = 0;
                    for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                        let (sx, sy) = (2 * x + dx, 2 * y + dy);
                        if sx >= w || sy >= h {
                            continue;
                        }
                        inside += 1;
                        let t = match above {
                            None => premultiply(picture, sx, sy),
                            Some(l) => l.texels[sy * l.width + sx].map(|v| f32::from(v) / U16),
                        };
                        for c in 0..4 {
                            sum[c] += t[c];
                        }
                    }
                    let count = if repeated { inside as f32 } else { 4.0 };
                    *texel = sum.map(|s| round_unsigned(s / count * U16) as u16);
                }
            });
            levels.push(Level {
                width: nw,
                height: nh,
                texels,
            });
            (w, h) = (nw, nh);
        }
        Self {
            picture,
            levels,
            repeated,
        }
    }

    /// Bytes held besides the picture.
    #[allow(dead_code)]
    pub fn mipmap_bytes(&self) -> usize {
        self.levels.iter().map(|l| 8 * l.texels.len()).sum()
    }

    /// The texel at `(x, y)` of level `level` (0: the picture); outside,
    /// transparent or the nearest edge texel ([`Texture::repeated`]).
    #[inline(always)]
    fn texel(&self, level: usize, x: i64, y: i64) -> Premultiplied {
        let (w, h) = if level == 0 {
            (
                i64::from(self.picture.width),
                i64::from(self.picture.height),
            )
        } else {
            let l = &self.levels[level - 1];
            (l.width as i64, l.height as i64)
        };
        let (x, y) = if x < 0 || y < 0 || x >= w || y >= h {
            if !self.repeated {
                return [0.0; 4];
            }
            (x.clamp(0, w - 1), y.clamp(0, h - 1))
        } else {
            (x, y)
        };
        if level == 0 {
            premultiply(self.picture, x as usize, y as usize)
        } else {
            let l = &self.levels[level - 1];
            l.texels[y as usize * l.width + x as usize].map(|v| f32::from(v) / U16)
        }
    }

    /// The colour at `p` (pixels of the picture) on level `level`, by
    /// bilinear interpolation between the four texel centres around it.
    #[inline(always)]
    fn bilinear(&self, level: usize, p: [f64; 2]) -> Premultiplied {
        let scale = 1.0 / f64::from(1u32 << level);
        let (u, v) = (p[0] * scale - 0.5, p[1] * scale - 0.5);
        let (x0, y0) = (floor(u), floor(v));
        let (fx, fy) = ((u - x0 as f64) as f32, (v - y0 as f64) as f32);
        if fx == 0.0 && fy == 0.0 {
            return self.texel(level, x0, y0);
        }
        let picture = self.picture;
        let (w, h) = (i64::from(picture.width), i64::from(picture.height));
        let [t00, t10, t01, t11] = if level == 0 && x0 >= 0 && y0 >= 0 && x0 + 1 < w && y0 + 1 < h {
            // The four texels inside the picture (most samples): read
            // from its rows, no bounds to test.
            let i = 4 * (y0 as usize * w as usize + x0 as usize);
            let j = i + 4 * w as usize;
            let (top, bottom) = (&picture.rgba[i..i + 8], &picture.rgba[j..j + 8]);
            // Written out: `array::map` is not inlined here, and took a
            // sixth of a frame.
            [
                premultiplied(&top[..4]),
                premultiplied(&top[4..]),
                premultiplied(&bottom[..4]),
                premultiplied(&bottom[4..]),
            ]
        } else {
            [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(dx, dy)| self.texel(level, x0 + dx, y0 + dy))
        };
        let mut out = [0.0; 4];
        for c in 0..4 {
            let top = t00[c] + fx * (t10[c] - t00[c]);
            let bottom = t01[c] + fx * (t11[c] - t01[c]);
            out[c] = top + fy * (bottom - top);
        }
        out
    }

    /// The colour at `p` for a triangle drawn at `lod` (log2 of how many
    /// times smaller it is drawn than it is in the picture; 0 or less: not
    /// smaller): bilinear on level 0 when `lod` is 0, else between the two
    /// levels around it (trilinear).
    #[inline]
    pub fn sample(&self, p: [f64; 2], lod: f32) -> Premultiplied {
        if lod.is_nan() || lod <= 0.0 || !p[0].is_finite() || !p[1].is_finite() {
            if !p[0].is_finite() || !p[1].is_finite() {
                return [0.0; 4];
            }
            return self.bilinear(0, p);
        }
        let top = self.levels.len();
        let l0 = (lod.floor() as usize).min(top);
        let f = if l0 == top { 0.0 } else { lod - l0 as f32 };
        let a = self.bilinear(l0, p);
        if f == 0.0 {
            return a;
        }
        let b = self.bilinear(l0 + 1, p);
        [0, 1, 2, 3].map(|c| a[c] + f * (b[c] - a[c]))
    }
}

/// The largest integer not above `v` (finite, within `i64`).
#[inline]
fn floor(v: f64) -> i64 {
    let t = v as i64;
    t - i64::from((t as f64) > v)
}

/// `v` rounded to the nearest integer, halves up, for `v` of 0 or more
/// (less than 0 gives 0).
#[inline]
fn round_unsigned(v: f32) -> u32 {
    (v + 0.5) as u32
}

/// Pixel `(x, y)` of `picture`, premultiplied, channels from 0 to 1.
#[inline(always)]
fn premultiply(picture: &Picture, x: usize, y: usize) -> Premultiplied {
    let i = 4 * (y * picture.width as usize + x);
    premultiplied(&picture.rgba[i..i + 4])
}

/// An RGBA pixel's 4 bytes, premultiplied, channels from 0 to 1.
#[inline(always)]
fn premultiplied(p: &[u8]) -> Premultiplied {
    const INV_255: f32 = 1.0 / 255.0;
    let a = f32::from(p[3]) * INV_255;
    let k = a * INV_255;
    [
        f32::from(p[0]) * k,
        f32::from(p[1]) * k,
        f32::from(p[2]) * k,
        a,
    ]
}

/// A premultiplied colour as straight 8-bit RGBA (transparent black where
/// it rounds to no alpha).
#[inline]
pub(crate) fn to_straight(c: Premultiplied) -> [u8; 4] {
    let a = round_unsigned(c[3] * 255.0);
    if a < 1 {
        return [0; 4];
    }
    let inv = 255.0 / c[3];
    let ch = |v: f32| round_unsigned(v * inv).min(255) as u8;
    [ch(c[0]), ch(c[1]), ch(c[2]), a.min(255) as u8]
}
