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
fn push_pair(d: &mut String, v: [i64; 2], sep: bool) {
    for (k, &x) in v.iter().enumerate() {
        if (sep || k == 1) && x >= 0 {
            d.push(' ');
        }
        push_num(d, x);
    }
}

/// `x / 100` in the shortest decimal form: `12`, `1.5`, `-.25`.
fn push_num(d: &mut String, x: i64) {
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

fn fmt_width(w: f64) -> String {
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

#[cfg(test)]
mod tests {
    use super::super::style::{Edges, Flipped};
    use super::*;

    fn grid(n: u32) -> (Vec<[f64; 2]>, Vec<[u32; 3]>) {
        let mut p = vec![];
        for j in 0..=n {
            for i in 0..=n {
                p.push([f64::from(i), f64::from(j)]);
            }
        }
        let mut t = vec![];
        for j in 0..n {
            for i in 0..n {
                let v = j * (n + 1) + i;
                t.push([v, v + 1, v + n + 2]);
                t.push([v, v + n + 2, v + n + 1]);
            }
        }
        (p, t)
    }

    /// Every `<` opens a tag closed by `>`; elements balance.
    fn check_balanced(svg: &str) {
        assert!(svg.starts_with("<svg "), "{svg}");
        assert!(svg.trim_end().ends_with("</svg>"));
        let mut depth = 0i32;
        let mut rest = svg;
        while let Some(i) = rest.find('<') {
            let j = rest[i..].find('>').expect("unclosed tag") + i;
            let tag = &rest[i + 1..j];
            assert!(!tag.contains('<'));
            assert_eq!(tag.matches('"').count() % 2, 0, "{tag}");
            if tag.starts_with('/') {
                depth -= 1;
            } else if !tag.ends_with('/') {
                depth += 1;
            }
            assert!(depth >= 0);
            rest = &rest[j + 1..];
        }
        assert_eq!(depth, 0);
    }

    #[test]
    fn one_subpath_per_triangle_and_balanced_tags() {
        let (mut p, t) = grid(4);
        p[6] = [2.5, 2.4]; // pushes a vertex over its neighbours: flips
        let view = View2d::fitting([p.as_slice()], 200, None, 8);
        let style = Style2d::default();
        let svg = svg_frame(&p, &t, &view, &style);
        check_balanced(&svg);
        let flipped = crate::mesh::signed_areas(&p, &t)
            .iter()
            .filter(|&&a| a < 0.0)
            .count();
        assert!(flipped > 0);
        assert_eq!(svg.matches("<path").count(), 2);
        assert_eq!(svg.matches('z').count(), 32);
        let paths: Vec<&str> = svg.lines().filter(|l| l.starts_with("<path")).collect();
        assert_eq!(paths[1].matches('z').count(), flipped);
        assert!(paths[1].contains(&hex(style.flipped_fill)));
        // Big triangles: Auto draws every edge as strokes of the fills.
        assert!(paths[0].contains("stroke="));

        // A dense mesh gets only its outline, as a third path.
        let (p, t) = grid(60);
        let svg = svg_frame(
            &p,
            &t,
            &View2d::fitting([p.as_slice()], 200, None, 8),
            &style,
        );
        check_balanced(&svg);
        assert_eq!(svg.matches("<path").count(), 2);
        assert!(svg.lines().nth(2).unwrap().starts_with("<path fill=\"#"));
        assert!(!svg.lines().nth(2).unwrap().contains("stroke"));
        assert_eq!(svg.lines().nth(3).unwrap().matches('M').count(), 240);
        let none = Style2d {
            edges: Edges::None,
            flipped: Flipped::None,
            ..Style2d::default()
        };
        let svg = svg_frame(
            &p,
            &t,
            &View2d::fitting([p.as_slice()], 200, None, 8),
            &none,
        );
        assert_eq!(svg.matches("<path").count(), 1);
        assert!(svg.len() < 36 * t.len(), "{} bytes", svg.len());
    }

    #[test]
    fn numbers_are_short() {
        let mut s = String::new();
        for x in [0, 100, -100, 150, -25, 5, 12345, -7] {
            push_num(&mut s, x);
            s.push(',');
        }
        assert_eq!(s, "0,1,-1,1.5,-.25,.05,123.45,-.07,");
        let mut s = String::new();
        push_pair(&mut s, [-5, 7], true);
        push_pair(&mut s, [5, -7], true);
        assert_eq!(s, "-.05 .07 .05-.07");
        assert_eq!(fmt_width(0.75), "0.75");
    }

    #[test]
    fn degenerate_input_gives_a_valid_empty_picture() {
        let p = vec![[2.0, 2.0]; 3];
        let t = vec![[0, 1, 2], [0, 1, 5]];
        let svg = svg_frame(
            &p,
            &t,
            &View2d::fitting([p.as_slice()], 50, None, 2),
            &Style2d::default(),
        );
        check_balanced(&svg);
        assert_eq!(svg.matches("<path").count(), 0);
        let p = vec![[-1e300, 0.0], [1e300, 1.0], [0.0, 1e300]];
        let svg = svg_frame(
            &p,
            &t,
            &View2d::fitting([p.as_slice()], 50, None, 2),
            &Style2d::default(),
        );
        check_balanced(&svg);
    }
}
