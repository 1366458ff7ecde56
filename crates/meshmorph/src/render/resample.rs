//! Anti-aliasing by supersampling: a picture drawn `s` times larger in each
//! direction, each block of `s × s` pixels averaged (in linear light) into
//! one, and the average matched to the nearest colour of the palette.

use std::collections::HashMap;

use super::canvas::Canvas;
use super::palette::{from_linear, to_linear, Rgb};

/// `big` reduced by `factor` in each direction to `width × height` (pixels
/// of `big` past `factor` times that are dropped), in `big`'s palette.
pub(crate) fn downsample(big: &Canvas, factor: u32, width: u32, height: u32) -> Canvas {
    let s = factor.max(1) as usize;
    let (w, h) = (width as usize, height as usize);
    let bw = big.width as usize;
    assert!(
        w * s <= bw && h * s <= big.height as usize,
        "a canvas too small to reduce"
    );
    let linear: Vec<[f64; 3]> = big
        .palette
        .colors
        .iter()
        .map(|c| c.map(to_linear))
        .collect();
    let mut nearest: HashMap<Rgb, u8> = HashMap::new();
    let mut out = Canvas::new(width, height, big.palette.clone());
    let mut block = Vec::with_capacity(s * s);
    for y in 0..h {
        for x in 0..w {
            block.clear();
            for dy in 0..s {
                let row = (y * s + dy) * bw + x * s;
                block.extend_from_slice(&big.pixels[row..row + s]);
            }
            // A uniform block keeps its index (the common case, and exact).
            if block.iter().all(|&i| i == block[0]) {
                out.pixels[y * w + x] = block[0];
                continue;
            }
            let mut sum = [0.0; 3];
            for &i in &block {
                let c = linear[i as usize];
                sum = [sum[0] + c[0], sum[1] + c[1], sum[2] + c[2]];
            }
            let n = block.len() as f64;
            let mean: Rgb = sum.map(|v| from_linear(v / n));
            out.pixels[y * w + x] = *nearest
                .entry(mean)
                .or_insert_with(|| nearest_index(&big.palette.colors, mean));
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

#[cfg(test)]
mod tests {
    use super::super::palette::{slot, Palette};
    use super::*;

    #[test]
    fn uniform_blocks_keep_their_index_and_mixed_ones_blend() {
        let mut big = Canvas::new(6, 3, Palette::standard());
        // Left block: all fill; right block: one third edge.
        for y in 0..3 {
            for x in 0..3 {
                big.set(x, y, slot::FILL);
            }
            big.set(3, y, slot::BLACK);
        }
        let small = downsample(&big, 3, 2, 1);
        assert_eq!(small.pixels[0], slot::FILL);
        let mixed = small.palette.get(small.pixels[1]);
        let white = small.palette.get(slot::BACKGROUND);
        assert!(mixed != white && mixed != [0, 0, 0], "{mixed:?}");
    }
}
