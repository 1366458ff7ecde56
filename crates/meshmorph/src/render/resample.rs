//! Anti-aliasing by supersampling: a picture drawn `s` times larger in each
//! direction, each block of `s × s` pixels averaged (in linear light) into
//! one, and the average matched to the nearest colour of the palette.

use std::sync::OnceLock;

use super::canvas::Canvas;
use super::palette::{from_linear, to_linear, Rgb};

/// Linear light in 16-bit fixed point: 0 black, [`ONE`] full intensity.
const ONE: u32 = u16::MAX as u32;

/// sRGB of each fixed-point linear level (`from_linear(l / ONE)`).
fn srgb_of_linear() -> &'static [u8] {
    static TABLE: OnceLock<Vec<u8>> = OnceLock::new();
    TABLE.get_or_init(|| {
        (0..=ONE)
            .map(|l| from_linear(f64::from(l) / f64::from(ONE)))
            .collect()
    })
}

/// A small cache of the palette entries nearest to colours already met,
/// indexed by a hash of the colour: each slot holds the colour and its
/// entry, or nothing.
struct Nearest<'a> {
    colors: &'a [Rgb; 256],
    slots: Vec<Option<(Rgb, u8)>>,
}

impl<'a> Nearest<'a> {
    const SLOTS: usize = 1 << 12;

    fn new(colors: &'a [Rgb; 256]) -> Self {
        Nearest {
            colors,
            slots: vec![None; Self::SLOTS],
        }
    }

    #[inline]
    fn get(&mut self, c: Rgb) -> u8 {
        let key = (u32::from(c[0]) << 16) | (u32::from(c[1]) << 8) | u32::from(c[2]);
        let slot = (key.wrapping_mul(0x9E37_79B1) >> 20) as usize % Self::SLOTS;
        match self.slots[slot] {
            Some((seen, index)) if seen == c => index,
            _ => {
                let index = nearest_index(self.colors, c);
                self.slots[slot] = Some((c, index));
                index
            }
        }
    }
}

/// `big` reduced by `factor` in each direction to `width × height` (pixels
/// of `big` past `factor` times that are dropped), in `big`'s palette.
pub fn downsample(big: &Canvas, factor: u32, width: u32, height: u32) -> Canvas {
    let s = factor.max(1) as usize;
    let (w, h) = (width as usize, height as usize);
    let bw = big.width as usize;
    assert!(
        w * s <= bw && h * s <= big.height as usize,
        "a canvas too small to reduce"
    );
    let linear: Vec<[u32; 3]> = big
        .palette
        .colors
        .iter()
        .map(|c| c.map(|v| (to_linear(v) * f64::from(ONE)).round() as u32))
        .collect();
    let srgb = srgb_of_linear();
    let mut nearest = Nearest::new(&big.palette.colors);
    let mut out = Canvas::new(width, height, big.palette.clone());
    let n = (s * s) as u32;
    for y in 0..h {
        let block = &big.pixels[y * s * bw..(y * s + s) * bw];
        for (x, pixel) in out.pixels[y * w..(y + 1) * w].iter_mut().enumerate() {
            let first = block[x * s];
            // A uniform block keeps its index (the common case, and exact).
            let mut uniform = true;
            for dy in 0..s {
                let at = dy * bw + x * s;
                for &i in &block[at..at + s] {
                    uniform &= i == first;
                }
            }
            if uniform {
                *pixel = first;
                continue;
            }
            let mut sum = [0u32; 3];
            for row in block.chunks_exact(bw) {
                for &i in &row[x * s..(x + 1) * s] {
                    let c = linear[i as usize];
                    sum = [sum[0] + c[0], sum[1] + c[1], sum[2] + c[2]];
                }
            }
            *pixel = nearest.get(sum.map(|v| srgb[((v + n / 2) / n) as usize]));
        }
    }
    out
}

/// The palette entry closest to `c` (squared distance in sRGB).
fn nearest_index(colors: &[Rgb; 256], c: Rgb) -> u8 {
    let d = |p: &Rgb| -> i32 {
        (0..3)
            .map(|k| (i32::from(p[k]) - i32::from(c[k])).pow(2))
            .sum()
    };
    (0..=255u8)
        .min_by_key(|&i| d(&colors[i as usize]))
        .unwrap_or(0)
}
