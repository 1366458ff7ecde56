//! Drawings read from SVG and text, and frames written back.

mod flatten;
mod mesh_outline;
mod regions;

use meshmorph::io::drawing::anchors::match_anchors;
use meshmorph::io::drawing::canvas::Canvas;
use meshmorph::io::drawing::lottie::write_lottie;
use meshmorph::io::drawing::regions::signed_area2;
use meshmorph::io::drawing::svg_animate::write_animated_svg;
use meshmorph::io::drawing::svg_read::parse_svg_drawing;
use meshmorph::io::drawing::svg_write::{svg_path_data, write_svg_frame};
use meshmorph::io::drawing::text_read::parse_text_drawing;
use meshmorph::io::drawing::text_write::write_text_frame;

use std::path::Path;

use meshmorph::io::drawing::*;

fn svg(body: &str) -> String {
    format!("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"200\" height=\"100\" viewBox=\"0 0 200 100\">{body}</svg>")
}

fn read(body: &str) -> DrawingFile {
    parse_svg_drawing(
        svg(body).as_bytes(),
        Path::new("t.svg"),
        &DrawingOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{body}: {e}"))
}

fn refusal(body: &str) -> String {
    parse_svg_drawing(
        svg(body).as_bytes(),
        Path::new("t.svg"),
        &DrawingOptions::default(),
    )
    .map(|_| ())
    .expect_err(body)
    .to_string()
}

fn area(d: &DrawingFile) -> f64 {
    d.drawing
        .loops()
        .iter()
        .map(|l| signed_area2(l) / 2.0)
        .sum()
}

fn bbox(d: &DrawingFile) -> [f64; 4] {
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for p in d.drawing.loops().iter().flatten() {
        b = [
            b[0].min(p[0]),
            b[1].min(p[1]),
            b[2].max(p[0]),
            b[3].max(p[1]),
        ];
    }
    b
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn path_lines_keep_their_points() {
    let d = read(r#"<path d="M10 10 L90 10 L90 60 L10 60 Z"/>"#);
    assert_eq!(d.drawing.num_points(), 4);
    assert_eq!(area(&d), 4000.0);
    assert_eq!(d.curves, 0);
    assert_eq!(bbox(&d), [10.0, 10.0, 90.0, 60.0]);
    // Relative commands, H and V.
    let r = read(r#"<path d="m10 10 h80 v50 h-80 z"/>"#);
    assert_eq!(bbox(&r), [10.0, 10.0, 90.0, 60.0]);
}

#[test]
fn quadratic_and_cubic_curves_keep_within_the_tolerance() {
    // A parabola's cap: the area under a quadratic from (0,0) to (100,0)
    // with control (50,-100) is 2/3 of its triangle.
    let q = read(r#"<path d="M0 50 Q50 -50 100 50 Z"/>"#);
    assert_eq!(q.curves, 1);
    let exact = 2.0 / 3.0 * 100.0 * 50.0;
    assert!(close(area(&q).abs(), exact, 0.01 * exact), "{}", area(&q));
    let tol = q.tolerance;
    assert!(tol > 0.0 && tol < 0.1, "{tol}");
    // Every point lies on the curve y = 50 - 100 t (1 - t) * 2 at x = 100 t.
    for p in &q.drawing.loops()[0] {
        let t = p[0] / 100.0;
        assert!(close(p[1], 50.0 - 200.0 * t * (1.0 - t), 1e-4), "{p:?}");
    }
    let c = read(r#"<path d="M0 50 C0 0 100 0 100 50 Z"/>"#);
    assert_eq!(c.curves, 1);
    // The cubic's cap: area 3/5 of the control polygon's height times width... by Green's theorem, 30 * 100 * 50 / 60 ... measured against a fine flattening.
    let fine = parse_svg_drawing(
        svg(r#"<path d="M0 50 C0 0 100 0 100 50 Z"/>"#).as_bytes(),
        Path::new("t.svg"),
        &DrawingOptions { tolerance: 1e-7 },
    )
    .unwrap();
    assert!(close(area(&c), area(&fine), 0.005 * area(&fine).abs()));
    assert!(fine.drawing.num_points() > c.drawing.num_points());
}

#[test]
fn arcs_circles_and_ellipses_are_round() {
    for body in [
        r#"<circle cx="100" cy="50" r="40"/>"#,
        r#"<path d="M60 50 A40 40 0 0 1 140 50 A40 40 0 0 1 60 50 Z"/>"#,
        r#"<ellipse cx="100" cy="50" rx="40" ry="40"/>"#,
    ] {
        let d = read(body);
        let a = area(&d).abs();
        let exact = std::f64::consts::PI * 1600.0;
        assert!(close(a, exact, 0.002 * exact), "{body}: {a}");
        for p in &d.drawing.loops()[0] {
            let r = (p[0] - 100.0).hypot(p[1] - 50.0);
            assert!(close(r, 40.0, 0.05), "{body}: {p:?} at {r}");
        }
        assert!(d.curves >= 2, "{body}");
    }
    let e = read(r#"<ellipse cx="100" cy="50" rx="80" ry="20"/>"#);
    assert_eq!(bbox(&e).map(|x| x.round()), [20.0, 30.0, 180.0, 70.0]);
}

#[test]
fn rect_and_polygon() {
    let r = read(r#"<rect x="20" y="10" width="60" height="30"/>"#);
    assert_eq!(bbox(&r), [20.0, 10.0, 80.0, 40.0]);
    assert_eq!(area(&r).abs(), 1800.0);
    let p = read(r#"<polygon points="10,10 90,10 50,80"/>"#);
    assert_eq!(p.drawing.num_points(), 3);
    assert_eq!(area(&p).abs(), 2800.0);
}

#[test]
fn transforms_and_nested_groups_are_applied() {
    let d = read(
        r#"<g transform="translate(100 0)"><g transform="scale(2)"><rect x="1" y="2" width="10" height="5" transform="rotate(90 1 2)"/></g></g>"#,
    );
    // rotate(90) about (1,2): the rectangle spans x from -4 to 1, y from 2
    // to 12; then scaled by 2 and moved by 100 in x.
    let b = bbox(&d);
    for (got, want) in b.iter().zip([92.0, 4.0, 102.0, 24.0]) {
        assert!(close(*got, want, 1e-4), "{b:?}");
    }
}

#[test]
fn the_view_box_maps_back_to_user_units() {
    let doc = r#"<svg xmlns="http://www.w3.org/2000/svg" width="400" height="200" viewBox="-10 -10 20 10"><rect x="-5" y="-8" width="10" height="4"/></svg>"#;
    let d = parse_svg_drawing(
        doc.as_bytes(),
        Path::new("v.svg"),
        &DrawingOptions::default(),
    )
    .unwrap();
    let b = bbox(&d);
    for (got, want) in b.iter().zip([-5.0, -8.0, 5.0, -4.0]) {
        assert!(close(*got, want, 1e-5), "{b:?}");
    }
    let c = d.canvas.unwrap();
    assert_eq!(c.view_box, [-10.0, -10.0, 20.0, 10.0]);
    assert_eq!(c.size, [400.0, 200.0]);
}

#[test]
fn holes_by_fill_rule_a_ring_and_a_letter() {
    // A ring: a circle with a circular hole, even-odd.
    let ring = read(
        r#"<path fill-rule="evenodd" d="M60 50 A40 40 0 1 1 140 50 A40 40 0 1 1 60 50 Z M80 50 A20 20 0 1 0 120 50 A20 20 0 1 0 80 50 Z"/>"#,
    );
    assert_eq!(ring.drawing.num_loops(), 2);
    let exact = std::f64::consts::PI * (1600.0 - 400.0);
    assert!(close(area(&ring).abs(), exact, 0.005 * exact));
    // The same with non-zero and the hole drawn the other way round.
    let ring2 = read(
        r#"<path d="M60 50 A40 40 0 1 1 140 50 A40 40 0 1 1 60 50 Z M80 50 A20 20 0 1 0 120 50 A20 20 0 1 0 80 50 Z"/>"#,
    );
    assert_eq!(ring2.drawing.num_loops(), 2);
    assert!(close(area(&ring2).abs(), exact, 0.005 * exact));
    // Non-zero with the inner loop the same way round: no hole, one disc.
    let disc = read(
        r#"<path d="M60 50 A40 40 0 1 1 140 50 A40 40 0 1 1 60 50 Z M80 50 A20 20 0 1 1 120 50 A20 20 0 1 1 80 50 Z"/>"#,
    );
    assert_eq!(disc.drawing.num_loops(), 1);
    // A letter B-like shape: one outline and two holes, non-zero with the
    // holes reversed.
    let b = read(
        r##"<path d="M10 10 H60 V90 H10 Z M20 20 V45 H50 V20 Z M20 55 V80 H50 V55 Z" fill="#123456" stroke="#ff0000" stroke-width="2"/>"##,
    );
    assert_eq!(b.drawing.num_loops(), 3);
    assert_eq!(area(&b).abs(), 4000.0 - 750.0 - 750.0);
    assert_eq!(b.style.fill, Some([0x12, 0x34, 0x56]));
    assert_eq!(b.style.stroke, Some([255, 0, 0]));
    assert_eq!(b.style.stroke_width, 2.0);
}

#[test]
fn marked_anchors_are_points_not_shapes() {
    let d = read(
        r#"<rect x="0" y="0" width="100" height="50"/><g transform="translate(10 5)"><circle id="anchor-eye" cx="20" cy="10" r="2" fill="red" visibility="hidden"/></g><rect id="anchor" x="98" y="48" width="4" height="4" fill="blue"/>"#,
    );
    assert_eq!(d.drawing.num_points(), 4);
    assert_eq!(d.anchors.len(), 2);
    assert_eq!(d.anchors[0].name, "eye");
    assert!(close(d.anchors[0].point[0], 30.0, 1e-4) && close(d.anchors[0].point[1], 15.0, 1e-4));
    assert_eq!(d.anchors[1].name, "");
    assert!(close(d.anchors[1].point[0], 100.0, 1e-4));
    // `anchorage` is a shape, not an anchor: here a second region.
    let m = refusal(
        r#"<rect x="0" y="0" width="100" height="50"/><rect id="anchorage" x="150" y="10" width="4" height="4"/>"#,
    );
    assert!(m.contains("2 separate filled regions"), "{m}");
}

#[test]
fn refusals_name_the_file_and_what_was_found() {
    let m = refusal(r#"<path d="M0 0 L10 10" stroke="black" fill="none"/>"#);
    assert!(
        m.starts_with("`t.svg`")
            && m.contains("no filled shape")
            && m.contains("1 shape with a stroke"),
        "{m}"
    );
    let m = refusal(
        r#"<rect x="0" y="0" width="10" height="10"/><rect id="b" x="50" y="0" width="10" height="10"/>"#,
    );
    assert!(
        m.contains("2 separate filled regions")
            && m.contains("element `b` from (50, 0) to (60, 10)")
            && m.contains("file of its own"),
        "{m}"
    );
    let m = refusal(
        r#"<rect x="0" y="0" width="50" height="50"/><rect x="10" y="10" width="10" height="10" fill="white"/>"#,
    );
    assert!(m.contains("does not cut a hole"), "{m}");
    // Shapes no one sees are not regions.
    for unseen in [r#"fill-opacity="0""#, r#"opacity="0""#] {
        let svg = format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="100"><rect x="0" y="0" width="50" height="50"/><rect {unseen} x="100" y="0" width="50" height="50"/></svg>"#
        );
        let d = parse_svg_drawing(
            svg.as_bytes(),
            Path::new("t.svg"),
            &DrawingOptions::default(),
        )
        .unwrap_or_else(|e| panic!("{unseen}: {e}"));
        assert_eq!(d.drawing.num_points(), 4, "{unseen}");
    }
    // A figure eight in one path, its two loops meeting where both start:
    // two regions, neither left out.
    let m = refusal(
        r#"<path d="M100 100 L150 50 L190 100 L150 150 Z M100 100 L50 150 L10 100 L50 50 Z"/>"#,
    );
    assert!(m.contains("2 separate filled regions"), "{m}");
    let m = refusal(r#"<path id="bow" d="M0 0 L50 50 L50 0 L0 50 Z"/>"#);
    assert!(
        m.starts_with("`t.svg`") && m.contains("crosses itself") && m.contains("element `bow`"),
        "{m}"
    );
    let m = parse_svg_drawing(b"<svg", Path::new("t.svg"), &DrawingOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        m.starts_with("`t.svg`") && m.contains("not valid SVG"),
        "{m}"
    );
    let m = parse_svg_drawing(b"<html/>", Path::new("t.svg"), &DrawingOptions::default())
        .unwrap_err()
        .to_string();
    assert!(m.contains("not `<svg>`"), "{m}");
}

/// A number that does not read (NaN, one beyond f64, a slip) in any
/// shape or transform is refused naming the attribute, the element and
/// its line: SVG's own handling would cut the path short there or leave
/// the shape out, and a different drawing would be morphed. Numbers
/// written without separators, as SVG allows, still read.
#[test]
fn malformed_numbers_are_refused_naming_the_element() {
    for (body, attribute, element) in [
        (
            r#"<path id="p" d="M20 20 L180 20 L180 90 L100 NaN L20 90 Z"/>"#,
            "`d`",
            "<path id=\"p\">",
        ),
        (
            r#"<path d="M1e400 20 L180 20 L100 90 Z"/>"#,
            "`d`",
            "<path>",
        ),
        (
            r#"<polygon points="20,20 180,20 180,nan 20,90"/>"#,
            "`points`",
            "<polygon>",
        ),
        (r#"<circle cx="50" cy="50" r="NaN"/>"#, "`r`", "<circle>"),
        (
            r#"<rect x="0" y="0" width="1e999" height="10"/>"#,
            "`width`",
            "<rect>",
        ),
        (
            r#"<g transform="rotate(NaN)"><rect x="0" y="0" width="10" height="10"/></g>"#,
            "`transform`",
            "<g>",
        ),
    ] {
        let m = refusal(body);
        assert!(
            m.starts_with("`t.svg`, line 1")
                && m.contains(&format!("{attribute} attribute of `{element}`"))
                && m.contains("correct the number"),
            "{body}: {m}"
        );
    }
    let d = read(r#"<path d="M10-5L190,10 100.5.5z" transform="translate(0 20)"/>"#);
    assert_eq!(d.drawing.num_points(), 3);
    let d = read(
        r#"<polygon points="10-5 190,10 100 50"/><rect rx="auto" x="0" y="60" width="0" height="0"/>"#,
    );
    assert_eq!(d.drawing.num_points(), 3);
}

#[test]
fn text_polygons_with_holes_comments_and_anchors() {
    let text = "# a square with a hole\n0 0\n10 0\n10 10 # corner\n0 10\n\n\n4 4\n4 6\n6 6\n6 4\nanchor corner 10 10\n";
    let d = parse_text_drawing(text, Path::new("sq.txt")).unwrap();
    assert_eq!(d.drawing.num_loops(), 2);
    assert_eq!(area(&d), 100.0 - 4.0);
    assert_eq!(
        d.anchors,
        vec![NamedPoint {
            name: "corner".into(),
            point: [10.0, 10.0]
        }]
    );
    let err = |t: &str| {
        parse_text_drawing(t, Path::new("bad.txt"))
            .unwrap_err()
            .to_string()
    };
    let m = err("0 0\n1 0\n1 x\n");
    assert!(
        m.starts_with("`bad.txt`, line 3") && m.contains("`x` is not a number"),
        "{m}"
    );
    let m = err("0 0 0\n");
    assert!(m.contains("line 1") && m.contains("found 3 values"), "{m}");
    let m = err("# nothing\n");
    assert!(m.contains("no points"), "{m}");
    let m = err("0 0\n10 0\n10 10\n0 10\n\n20 20\n21 20\n21 21\n");
    assert!(
        m.starts_with("`bad.txt`") && m.contains("outside") && m.contains("starts on line 6"),
        "{m}"
    );
}

#[test]
fn anchor_files_and_marked_anchors_match() {
    let rows =
        anchors::parse_anchor_text("# name a b\neye 1 2 3 4\n5,6 7,8\n", Path::new("a.txt"), 2)
            .unwrap();
    assert_eq!(rows.len(), 2);
    assert_eq!(
        (rows[0].name.as_str(), rows[0].points.clone()),
        ("eye", vec![[1.0, 2.0], [3.0, 4.0]])
    );
    assert_eq!(rows[1].points, vec![[5.0, 6.0], [7.0, 8.0]]);
    let m = anchors::parse_anchor_text("eye 1 2 3\n", Path::new("a.txt"), 2)
        .unwrap_err()
        .to_string();
    assert!(
        m.contains("line 1") && m.contains("expected 4 numbers"),
        "{m}"
    );
    let np = |name: &str, x: f64| NamedPoint {
        name: name.into(),
        point: [x, 0.0],
    };
    let names = vec!["`a.svg`".to_string(), "`b.svg`".to_string()];
    let rows = match_anchors(
        &[
            vec![np("eye", 1.0), np("", 2.0)],
            vec![np("", 3.0), np("eye", 4.0)],
        ],
        &names,
    )
    .unwrap();
    assert_eq!(rows[0].points, vec![[1.0, 0.0], [4.0, 0.0]]);
    assert_eq!(rows[1].points, vec![[2.0, 0.0], [3.0, 0.0]]);
    let m = match_anchors(&[vec![np("eye", 1.0)], vec![]], &names)
        .unwrap_err()
        .to_string();
    assert!(m.contains("marked in `a.svg` but not in `b.svg`"), "{m}");
}

/// Frames held in memory.
struct List(Vec<Vec<[f64; 2]>>);

impl meshmorph::FrameSource<2> for List {
    fn num_frames(&self) -> usize {
        self.0.len()
    }

    fn with_frame(&self, k: usize, use_frame: &mut dyn FnMut(&[[f64; 2]])) {
        use_frame(&self.0[k])
    }
}

/// A square with a square hole as vertex indices, and two frames.
fn frames() -> (Vec<Vec<[f64; 2]>>, Vec<Vec<u32>>) {
    let f0 = vec![
        [0.0, 0.0],
        [10.0, 0.0],
        [10.0, 10.0],
        [0.0, 10.0],
        [4.0, 4.0],
        [4.0, 6.0],
        [6.0, 6.0],
        [6.0, 4.0],
    ];
    let f1: Vec<[f64; 2]> = f0
        .iter()
        .map(|p| [p[0] * 0.5 + 0.1, p[1] * 2.0 - 1.0 / 3.0])
        .collect();
    (vec![f0, f1], vec![vec![0, 1, 2, 3], vec![4, 5, 6, 7]])
}

/// The numbers of a path's `d`, as written.
fn path_numbers(d: &str) -> Vec<&str> {
    d.split(|c: char| c.is_ascii_alphabetic() || c == ' ')
        .filter(|s| !s.is_empty())
        .collect()
}

/// The coordinates of `loops`' points in `frame`, x then y, loop by loop.
fn loop_coordinates(frame: &[[f64; 2]], loops: &[Vec<u32>]) -> Vec<f64> {
    loops
        .iter()
        .flatten()
        .flat_map(|&v| frame[v as usize])
        .collect()
}

#[test]
fn an_svg_frame_reads_back_with_the_same_points() {
    let (frames, loops) = frames();
    let page = Canvas {
        view_box: [-1.0, -1.0, 22.0, 22.0],
        size: [220.0, 220.0],
        flip_y: false,
    };
    let canvas = Canvas::for_frames(Some(&page), &List(frames.clone()), &loops, 0.0);
    assert_eq!(canvas, page);
    let mut out = Vec::new();
    let style = Style {
        stroke: Some([1, 2, 3]),
        stroke_width: 0.5,
        ..Style::default()
    };
    write_svg_frame(&mut out, &frames[1], &loops, &style, &canvas).unwrap();
    let text = String::from_utf8(out.clone()).unwrap();
    assert!(
        text.contains("fill-rule=\"evenodd\"") && text.contains("stroke=\"#010203\""),
        "{text}"
    );
    assert_eq!(text.matches("<path").count(), 1);
    let back = parse_svg_drawing(&out, Path::new("f.svg"), &DrawingOptions::default()).unwrap();
    let f32_close =
        |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-5 && (a[1] - b[1]).abs() < 1e-5;
    for (l, indices) in loops.iter().enumerate() {
        let got = &back.drawing.loops()[l];
        assert_eq!(got.len(), indices.len());
        for &v in indices {
            assert!(
                got.iter().any(|p| f32_close(*p, frames[1][v as usize])),
                "{:?}",
                frames[1][v as usize]
            );
        }
    }
    // The path's numbers are the frame's to eight significant digits at
    // the page's size, with no digit beyond (no float noise).
    let d = svg_path_data(&frames[1], &loops, &canvas);
    let decimals = canvas.decimals();
    let words = path_numbers(&d);
    let want = loop_coordinates(&frames[1], &loops);
    assert_eq!(words.len(), want.len());
    let extent = canvas.view_box[2].max(canvas.view_box[3]);
    for (word, x) in words.iter().zip(&want) {
        let n: f64 = word.parse().unwrap();
        assert!(
            (n - x).abs() <= 0.5e-8 * 10f64.powf(extent.log10().ceil()) + 1e-15,
            "{word} {x}"
        );
        let after = word.split('.').nth(1).map_or(0, str::len);
        assert!(
            after <= decimals && !word.ends_with('0') || !word.contains('.'),
            "{word}"
        );
    }
    assert!(words.contains(&"0.1") && words.contains(&"5.1"), "{d}");
    // Frames leaving the page grow it.
    let small = Canvas {
        view_box: [0.0, 0.0, 5.0, 5.0],
        size: [50.0, 50.0],
        flip_y: false,
    };
    let grown = Canvas::for_frames(Some(&small), &List(frames.clone()), &loops, 0.0);
    assert_eq!(grown.view_box, [0.0, -1.0 / 3.0, 10.0, 20.0]);
    assert_eq!(grown.size[0], 100.0);
}

/// A small drawing on a large page keeps its own eight significant
/// digits (not the page's, which would write it as zeros), and the page
/// grown to hold the frames is written without float noise.
#[test]
fn a_small_drawing_on_a_large_page_keeps_its_shape() {
    let (frames, loops) = frames();
    let tiny: Vec<Vec<[f64; 2]>> = frames
        .iter()
        .map(|f| f.iter().map(|p| [1e-4 * p[0], 1e-4 * p[1]]).collect())
        .collect();
    let page = Canvas {
        view_box: [0.0, 0.0, 1e6, 1e6],
        size: [1000.0, 1000.0],
        flip_y: false,
    };
    let d = svg_path_data(&tiny[1], &loops, &page);
    let words: Vec<f64> = path_numbers(&d)
        .iter()
        .map(|w| w.parse().unwrap())
        .collect();
    let want = loop_coordinates(&tiny[1], &loops);
    assert_eq!(words.len(), want.len());
    // The drawing is about 2e-3 across: eight digits of that.
    for (got, x) in words.iter().zip(&want) {
        assert!((got - x).abs() <= 1e-10, "{got} {x} in {d}");
    }
    // A drawing shrunk to a point far from the origin: no float noise.
    let point: Vec<[f64; 2]> = (0..tiny[1].len())
        .map(|k| [123.45 + 1e-13 * k as f64, 0.1 + 0.2])
        .collect();
    let d = svg_path_data(&point, &loops, &page);
    assert!(d.starts_with("M123.45 0.3L"), "{d}");
    for word in path_numbers(&d) {
        let digits = word.chars().filter(char::is_ascii_digit).count();
        assert!(digits <= 15, "{word} in {d}");
    }
    // A thin stroke on a large page keeps its width.
    let style = Style {
        stroke: Some([0, 0, 0]),
        stroke_width: 2e-5,
        ..Style::default()
    };
    let mut out = Vec::new();
    write_svg_frame(&mut out, &tiny[1], &loops, &style, &page).unwrap();
    let text = String::from_utf8(out).unwrap();
    assert!(text.contains("stroke-width=\"0.00002\""), "{text}");
    // A page grown by a third: its size and viewBox as short numbers.
    let small = Canvas {
        view_box: [0.0, 0.0, 3.0, 3.0],
        size: [100.0, 100.0],
        flip_y: false,
    };
    let grown = Canvas::for_frames(Some(&small), &List(frames.clone()), &loops, 0.0);
    let mut out = Vec::new();
    write_svg_frame(&mut out, &frames[1], &loops, &Style::default(), &grown).unwrap();
    let text = String::from_utf8(out).unwrap();
    let open = text.lines().next().unwrap();
    for number in open
        .split('"')
        .filter(|s| s.starts_with(|c: char| c.is_ascii_digit() || c == '-'))
        .flat_map(|s| s.split(' '))
    {
        let digits = number.chars().filter(char::is_ascii_digit).count();
        assert!(digits <= 9, "{number} in {open}");
    }
}

#[test]
fn smil_has_one_value_a_frame_and_loops() {
    let (frames, loops) = frames();
    let canvas = Canvas::for_frames(None, &List(frames.clone()), &loops, 0.0);
    assert!(canvas.flip_y);
    let mut out = Vec::new();
    write_animated_svg(
        &mut out,
        &Animation {
            frames: &List(frames.clone()),
            loops: &loops,
            style: &Style::default(),
            canvas: &canvas,
            fps: 10.0,
            boomerang: false,
        },
    )
    .unwrap();
    let text = String::from_utf8(out).unwrap();
    let values = text
        .split("values=\"")
        .nth(1)
        .unwrap()
        .split('"')
        .next()
        .unwrap();
    assert_eq!(values.split(';').count(), 2);
    assert!(
        text.contains("repeatCount=\"indefinite\"")
            && text.contains("attributeName=\"d\"")
            && text.contains("dur=\"0.1s\""),
        "{text}"
    );
    // Every value has the same commands: M, L and Z in the same places.
    let shape = |d: &str| {
        d.chars()
            .filter(|c| c.is_ascii_alphabetic())
            .collect::<String>()
    };
    let shapes: Vec<String> = values.split(';').map(shape).collect();
    assert!(shapes.windows(2).all(|w| w[0] == w[1]));
    // Forward and back: 0, 1, 0 for two frames... three frames give 0 1 2 1 0.
    let three = vec![frames[0].clone(), frames[1].clone(), frames[0].clone()];
    let mut out = Vec::new();
    write_animated_svg(
        &mut out,
        &Animation {
            frames: &List(three.clone()),
            loops: &loops,
            style: &Style::default(),
            canvas: &canvas,
            fps: 10.0,
            boomerang: true,
        },
    )
    .unwrap();
    let text = String::from_utf8(out).unwrap();
    assert_eq!(
        text.split("values=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap()
            .split(';')
            .count(),
        5
    );
}

#[test]
fn lottie_has_a_shape_layer_with_a_keyframe_a_frame() {
    let (frames, loops) = frames();
    let canvas = Canvas {
        view_box: [-5.0, -5.0, 20.0, 30.0],
        size: [200.0, 300.0],
        flip_y: false,
    };
    let style = Style {
        fill: Some([255, 0, 0]),
        fill_opacity: 0.5,
        ..Style::default()
    };
    let mut out = Vec::new();
    write_lottie(
        &mut out,
        &Animation {
            frames: &List(frames.clone()),
            loops: &loops,
            style: &style,
            canvas: &canvas,
            fps: 25.0,
            boomerang: false,
        },
    )
    .unwrap();
    let doc: serde_json::Value = serde_json::from_slice(&out).unwrap();
    assert_eq!(
        (
            doc["w"].as_u64(),
            doc["h"].as_u64(),
            doc["fr"].as_f64(),
            doc["op"].as_u64()
        ),
        (Some(200), Some(300), Some(25.0), Some(2))
    );
    let layer = &doc["layers"][0];
    assert_eq!(layer["ty"], 4);
    let items = layer["shapes"][0]["it"].as_array().unwrap();
    let paths: Vec<&serde_json::Value> = items.iter().filter(|i| i["ty"] == "sh").collect();
    assert_eq!(paths.len(), 2);
    let keys = paths[0]["ks"]["k"].as_array().unwrap();
    assert_eq!((paths[0]["ks"]["a"].as_u64(), keys.len()), (Some(1), 2));
    let shape = &keys[1]["s"][0];
    assert_eq!(shape["c"], true);
    assert_eq!(shape["v"].as_array().unwrap().len(), 4);
    assert_eq!(shape["i"].as_array().unwrap().len(), 4);
    assert_eq!(shape["o"].as_array().unwrap().len(), 4);
    // Frame 1's point 0, (0.1, -1/3), in pixels: (x + 5) * 10, (y + 5) * 10.
    assert_eq!(shape["v"][0], serde_json::json!([51.0, 46.667]));
    let fill = items.iter().find(|i| i["ty"] == "fl").unwrap();
    assert_eq!(
        (fill["r"].as_u64(), fill["o"]["k"].as_f64()),
        (Some(2), Some(50.0))
    );
    assert_eq!(items.last().unwrap()["ty"], "tr");
}

#[test]
fn text_frames_read_back_exactly() {
    let (frames, loops) = frames();
    let mut out = Vec::new();
    write_text_frame(&mut out, &frames[1], &loops).unwrap();
    let back = parse_text_drawing(std::str::from_utf8(&out).unwrap(), Path::new("f.txt")).unwrap();
    assert_eq!(back.drawing.num_loops(), 2);
    let mut got: Vec<[f64; 2]> = back.drawing.loops().iter().flatten().copied().collect();
    let mut want: Vec<[f64; 2]> = loops
        .iter()
        .flatten()
        .map(|&v| frames[1][v as usize])
        .collect();
    got.sort_by(|a, b| a.partial_cmp(b).unwrap());
    want.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(got, want);
}
