//! Outlines of a picture's alpha by marching squares: the contour where
//! alpha crosses a threshold, between the pixel centres, with holes.
//!
//! Samples are the pixel centres, with a ring of transparent samples
//! around the picture so that every contour closes. In each square of four
//! samples a contour crosses an edge whose two samples lie on either side
//! of the threshold, at the point found by interpolating linearly between
//! them. A square with two opposite samples inside and two outside (a
//! saddle) joins its inside samples when the square's average is inside,
//! else keeps them apart; so two neighbouring squares always agree and the
//! loops never cross or touch.

use std::collections::HashMap;

use super::Picture;

/// The closed loops where `picture`'s alpha (from 0 to 1) crosses
/// `threshold`, in pixel coordinates: each oriented with the inside (alpha
/// at or above the threshold) on its left as x turns towards y, so outer
/// loops have a positive signed area (`Σ x_i y_{i+1} - x_{i+1} y_i`) and
/// holes a negative one. Loops are given in the order their first crossing
/// is met, row by row.
///
/// # Performance
/// One pass over the pixels, then work in proportion to the outlines'
/// length.
pub fn trace_alpha(picture: &Picture, threshold: f64) -> Vec<Vec<[f64; 2]>> {
    let (w, h) = (picture.width as i64, picture.height as i64);
    let level = |x: i64, y: i64| -> f64 {
        if x < 0 || y < 0 || x >= w || y >= h {
            0.0
        } else {
            f64::from(picture.rgba[4 * (y * w + x) as usize + 3]) / 255.0
        }
    };
    // Corners of a square, going round it from the top-left as x turns
    // towards y: (i, j), (i+1, j), (i+1, j+1), (i, j+1).
    const CORNERS: [(i64, i64); 4] = [(0, 0), (1, 0), (1, 1), (0, 1)];
    let stride = w + 2;
    // An edge of the sample grid by its first corner (the lesser) and its
    // direction (0: along x, 1: along y).
    let key = |a: (i64, i64), b: (i64, i64)| -> u64 {
        let (p, dir) = if a.0 != b.0 {
            (if a.0 < b.0 { a } else { b }, 0)
        } else {
            (if a.1 < b.1 { a } else { b }, 1)
        };
        (((p.1 + 1) * stride + (p.0 + 1)) as u64) * 2 + dir
    };
    let mut next: HashMap<u64, u64> = HashMap::new();
    let mut points: HashMap<u64, [f64; 2]> = HashMap::new();
    let mut order: Vec<u64> = Vec::new();
    let mut row_above: Vec<f64> = (-1..=w).map(|x| level(x, -1)).collect();
    for j in -1..h {
        let row_below: Vec<f64> = (-1..=w).map(|x| level(x, j + 1)).collect();
        for i in -1..w {
            let at = |c: (i64, i64)| -> f64 {
                let row = if c.1 == j { &row_above } else { &row_below };
                row[(c.0 + 1) as usize]
            };
            let corners = CORNERS.map(|(dx, dy)| (i + dx, j + dy));
            let values = corners.map(at);
            let inside = values.map(|v| v >= threshold);
            if inside.iter().all(|&x| x) || inside.iter().all(|&x| !x) {
                continue;
            }
            // Crossings going round the square: entries (outside to
            // inside) and exits, each with its edge.
            let mut crossings: Vec<(bool, u64)> = Vec::with_capacity(4);
            for e in 0..4 {
                let (a, b) = (e, (e + 1) % 4);
                if inside[a] == inside[b] {
                    continue;
                }
                let k = key(corners[a], corners[b]);
                points.entry(k).or_insert_with(|| {
                    let t = (threshold - values[a]) / (values[b] - values[a]);
                    let (pa, pb) = (corners[a], corners[b]);
                    [
                        pa.0 as f64 + 0.5 + t * (pb.0 - pa.0) as f64,
                        pa.1 as f64 + 0.5 + t * (pb.1 - pa.1) as f64,
                    ]
                });
                crossings.push((inside[b], k));
            }
            let joined = crossings.len() == 4 && values.iter().sum::<f64>() / 4.0 >= threshold;
            let n = crossings.len();
            for (c, &(entry, k)) in crossings.iter().enumerate() {
                if entry {
                    continue;
                }
                // An exit leads to the next entry round the square when
                // the inside runs are joined through the middle, else to
                // the entry of its own run (the one before it).
                let to = if joined {
                    crossings[(c + 1) % n].1
                } else {
                    crossings[(c + n - 1) % n].1
                };
                if next.insert(k, to).is_none() {
                    order.push(k);
                }
            }
        }
        row_above = row_below;
    }
    let mut loops = Vec::new();
    for start in order {
        let Some(mut k) = next.remove(&start) else {
            continue;
        };
        let mut l = vec![points[&start]];
        while k != start {
            l.push(points[&k]);
            match next.remove(&k) {
                Some(n) => k = n,
                None => break,
            }
        }
        loops.push(l);
    }
    loops
}
