//! A frame of a morph as an SVG file: one `<path>` with the drawing's
//! loops.

use std::io::Write;

use super::{Canvas, Style};

/// Appends a number as the shortest text that reads back to it.
pub(super) fn push_number(out: &mut Vec<u8>, x: f64) {
    super::super::push_f64(out, if x == 0.0 { 0.0 } else { x });
}

/// Appends `x` with at most `decimals` digits after the point, trailing
/// zeros dropped (`18`, not `18.000000741839404`; `-0` as `0`); with 17
/// or more, as [`push_number`] (no rounding asked for).
pub(super) fn push_rounded(out: &mut Vec<u8>, x: f64, decimals: usize) {
    use std::io::Write as _;
    if decimals >= 17 {
        push_number(out, x);
        return;
    }
    let start = out.len();
    write!(out, "{x:.decimals$}").expect("writing to a Vec");
    if out[start..].contains(&b'.') {
        while out.last() == Some(&b'0') {
            out.pop();
        }
        if out.last() == Some(&b'.') {
            out.pop();
        }
    }
    if &out[start..] == b"-0" {
        out.truncate(start);
        out.push(b'0');
    }
}

/// The `d` of a path through the loops: `loops[l]` lists vertex indices
/// into `positions`; each loop is `M x y L x y ... Z`, the outer loop
/// first, in the order given, mapped by `canvas` (y flipped for drawings
/// with y up), to the canvas's [`decimals_for`](Canvas::decimals_for) the
/// loops' size in this frame.
pub fn svg_path_data(positions: &[[f64; 2]], loops: &[Vec<u32>], canvas: &Canvas) -> String {
    let mut out = Vec::with_capacity(loops.iter().map(Vec::len).sum::<usize>() * 20);
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for &v in loops.iter().flatten() {
        let p = positions[v as usize];
        lo = [lo[0].min(p[0]), lo[1].min(p[1])];
        hi = [hi[0].max(p[0]), hi[1].max(p[1])];
    }
    let magnitude = lo.iter().chain(&hi).fold(0.0f64, |m, x| m.max(x.abs()));
    let decimals = canvas.decimals_for((hi[0] - lo[0]).max(hi[1] - lo[1]), magnitude);
    for (l, indices) in loops.iter().enumerate() {
        if l > 0 {
            out.push(b' ');
        }
        for (i, &v) in indices.iter().enumerate() {
            out.extend_from_slice(match i {
                0 => b"M",
                1 => b"L",
                _ => b" ",
            });
            let p = canvas.map(positions[v as usize]);
            push_rounded(&mut out, p[0], decimals);
            out.push(b' ');
            push_rounded(&mut out, p[1], decimals);
        }
        out.push(b'Z');
    }
    String::from_utf8(out).expect("numbers are ASCII")
}

/// `#rrggbb`.
pub(super) fn hex(c: [u8; 3]) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// The opening `<svg>` tag of `canvas`: its size and viewBox to
/// [`SIGNIFICANT_DIGITS`](super::canvas::SIGNIFICANT_DIGITS) (a page grown
/// to hold the frames is written `100.5`, not `100.50000000000001`).
pub(super) fn svg_open(canvas: &Canvas) -> String {
    let n = |x: f64, decimals: usize| {
        let mut b = Vec::new();
        push_rounded(&mut b, x, decimals);
        String::from_utf8(b).expect("ASCII")
    };
    // A length to at least its own digits (a flat page's height is not
    // rounded to zero); the viewBox's to the page's where those are more.
    let (v, d) = (canvas.view_box, canvas.decimals());
    let length = |x: f64, d: usize| n(x, d.max(super::canvas::decimals_at(x)));
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" viewBox=\"{} {} {} {}\">\n",
        length(canvas.size[0], 0),
        length(canvas.size[1], 0),
        n(v[0], d),
        n(v[1], d),
        length(v[2], d),
        length(v[3], d)
    )
}

/// The paint attributes of a path drawn in `style`, even-odd filled,
/// the stroke's width to `decimals`.
pub(super) fn paint_attributes(style: &Style, decimals: usize) -> String {
    let mut a = format!(
        "fill=\"{}\" fill-rule=\"evenodd\"",
        hex(style.fill.unwrap_or([0, 0, 0]))
    );
    if style.fill_opacity < 1.0 {
        a += &format!(" fill-opacity=\"{}\"", style.fill_opacity);
    }
    if let Some(s) = style.stroke.filter(|_| style.stroke_width > 0.0) {
        let mut width = Vec::new();
        // (To its own digits where it is finer than the page's: a small
        // drawing's thin stroke is not written as 0.)
        push_rounded(
            &mut width,
            style.stroke_width,
            decimals.max(super::canvas::decimals_at(style.stroke_width)),
        );
        a += &format!(
            " stroke=\"{}\" stroke-width=\"{}\" stroke-linejoin=\"round\"",
            hex(s),
            String::from_utf8(width).expect("ASCII")
        );
        if style.stroke_opacity < 1.0 {
            a += &format!(" stroke-opacity=\"{}\"", style.stroke_opacity);
        }
    }
    a
}

/// Writes one frame as an SVG document: `canvas`'s viewBox and size, one
/// `<path>` (even-odd filled, in `style`) through `loops` (vertex indices
/// into `positions`, outer loop first), every point to the canvas's
/// [`decimals`](Canvas::decimals).
///
/// # Errors
/// The writer's.
pub fn write_svg_frame(
    w: &mut dyn Write,
    positions: &[[f64; 2]],
    loops: &[Vec<u32>],
    style: &Style,
    canvas: &Canvas,
) -> std::io::Result<()> {
    w.write_all(svg_open(canvas).as_bytes())?;
    writeln!(
        w,
        "  <path {} d=\"{}\"/>\n</svg>",
        paint_attributes(style, canvas.decimals()),
        svg_path_data(positions, loops, canvas)
    )
}
