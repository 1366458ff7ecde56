//! Planar meshes as standalone SVG documents.

use std::fmt::Write as _;

use super::palette::hex;
use super::style::{valid, EdgeSets, Style2d};
use super::view::View2d;

/// A standalone SVG picture of a planar mesh seen through `view`.
///
/// The picture is `view.width` × `view.height` pixels: a background
/// rectangle, then one `<path>` holding every correctly oriented triangle
/// and one holding the flipped ones (see [`Style2d::flipped`]), each
/// triangle a closed subpath, drawn with the style's colours. Edges
/// ([`Style2d::edges`]) are the strokes of those paths, or a separate
/// `<path>` of boundary segments. Filling all triangles of a colour as one
/// path avoids the hairline seams renderers leave between separately
/// anti-aliased neighbours, and keeps the file small: coordinates are
/// rounded to 0.01 pixel and written relative to the first corner.
///
/// Triangles with an index out of range, a non-finite coordinate or zero
/// area (after rounding) are left out.
pub fn svg_frame(
    positions: &[[f64; 2]],
    triangles: &[[u32; 3]],
    view: &View2d,
    style: &Style2d,
) -> String {
    let (w, h) = (view.width, view.height);
    let mut out = String::with_capacity(256 + 36 * triangles.len());
    let _ = write!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">\n\
         <rect width=\"{w}\" height=\"{h}\" fill=\"{}\"/>\n",
        hex(style.background)
    );
    // Pixel coordinates in hundredths.
    let q: Vec<Option<[i64; 2]>> = positions
        .iter()
        .map(|&p| {
            let v = view.to_pixel(p);
            v.iter().all(|x| x.is_finite()).then(|| v.map(hundredths))
        })
        .collect();
    let corners = |t: &[u32; 3]| -> Option<[[i64; 2]; 3]> {
        if !valid(t, q.len()) {
            return None;
        }
        Some([q[t[0] as usize]?, q[t[1] as usize]?, q[t[2] as usize]?])
    };
    let flipped = style.flipped_mask(positions, triangles);
    let mode = style.resolve_edges(super::style::mean_area(positions, triangles), view.scale);
    let stroke = |color| {
        format!(
            " stroke=\"{}\" stroke-width=\"{}\" stroke-linejoin=\"round\" stroke-linecap=\"round\"",
            hex(color),
            fmt_width(style.edge_width)
        )
    };
    for (pass, fill, edge) in [
        (false, style.fill, style.edge),
        (true, style.flipped_fill, style.flipped_edge),
    ] {
        let mut d = String::new();
        for (t, _) in triangles.iter().zip(&flipped).filter(|(_, &f)| f == pass) {
            let Some([a, mut b, mut c]) = corners(t) else {
                continue;
            };
            let area = (b[0] - a[0]) as i128 * (c[1] - a[1]) as i128
                - (b[1] - a[1]) as i128 * (c[0] - a[0]) as i128;
            if area == 0 {
                continue;
            }
            // One winding for all subpaths, so that overlaps stay filled.
            if area < 0 {
                std::mem::swap(&mut b, &mut c);
            }
            d.push('M');
            push_pair(&mut d, a, false);
            d.push('l');
            push_pair(&mut d, [b[0] - a[0], b[1] - a[1]], false);
            push_pair(&mut d, [c[0] - b[0], c[1] - b[1]], true);
            d.push('z');
        }
        if d.is_empty() {
            continue;
        }
        let strokes = if mode == Some(true) {
            stroke(edge)
        } else {
            String::new()
        };
        let _ = writeln!(out, "<path fill=\"{}\"{strokes} d=\"{d}\"/>", hex(fill));
    }
    if mode == Some(false) {
        let edges = EdgeSets::new(triangles, positions.len());
        let mut d = String::new();
        for [a, b] in edges.boundary {
            let (Some(a), Some(b)) = (q[a as usize], q[b as usize]) else {
                continue;
            };
            if a == b {
                continue;
            }
            d.push('M');
            push_pair(&mut d, a, false);
            d.push('l');
            push_pair(&mut d, [b[0] - a[0], b[1] - a[1]], false);
        }
        if !d.is_empty() {
            let _ = writeln!(out, "<path fill=\"none\"{} d=\"{d}\"/>", stroke(style.edge));
        }
    }
    out.push_str("</svg>\n");
    out
}

/// `v` in hundredths, saturated far outside any picture.
fn hundredths(v: f64) -> i64 {
    (v * 100.0).round().clamp(-1e13, 1e13) as i64
}

/// Appends `x y` (with a separator before `x` if `sep`), omitting spaces
/// before minus signs.
pub fn push_pair(d: &mut String, v: [i64; 2], sep: bool) {
    for (k, &x) in v.iter().enumerate() {
        if (sep || k == 1) && x >= 0 {
            d.push(' ');
        }
        push_num(d, x);
    }
}

/// `x / 100` in the shortest decimal form: `12`, `1.5`, `-.25`.
pub fn push_num(d: &mut String, x: i64) {
    if x < 0 {
        d.push('-');
    }
    let (int, frac) = (x.unsigned_abs() / 100, x.unsigned_abs() % 100);
    if int != 0 || frac == 0 {
        let _ = write!(d, "{int}");
    }
    if frac != 0 {
        if frac % 10 == 0 {
            let _ = write!(d, ".{}", frac / 10);
        } else {
            let _ = write!(d, ".{frac:02}");
        }
    }
}

pub fn fmt_width(w: f64) -> String {
    let mut s = String::new();
    push_num(
        &mut s,
        hundredths(if w.is_finite() { w.max(0.0) } else { 1.0 }),
    );
    if s.starts_with('.') {
        s.insert(0, '0');
    }
    s
}
