//! SVG files to drawings, through `usvg` (shapes become paths, `use`
//! and CSS are resolved, transforms are kept apart from the points).

use std::path::Path;

use usvg::roxmltree;

use super::canvas::Canvas;
use super::flatten::{flatten, Segment};
use super::regions::{inside, regions, FilledLoop, Rule};
use super::svg_numbers::check_shape_numbers;
use super::Style;
use super::{drawing_error, parse_error, DrawingFile, DrawingKind, DrawingOptions, NamedPoint};
use crate::error::Result;
use crate::outline::Drawing;

/// An affine map `[a, b, c, d, e, f]`: $(x, y) \mapsto (a x + c y + e,\;
/// b x + d y + f)$, as SVG writes `matrix(a b c d e f)`.
type Affine = [f64; 6];

fn apply(m: &Affine, p: [f64; 2]) -> [f64; 2] {
    [
        m[0] * p[0] + m[2] * p[1] + m[4],
        m[1] * p[0] + m[3] * p[1] + m[5],
    ]
}

/// `m` after `n`: $m(n(p))$.
fn compose(m: &Affine, n: &Affine) -> Affine {
    [
        m[0] * n[0] + m[2] * n[1],
        m[1] * n[0] + m[3] * n[1],
        m[0] * n[2] + m[2] * n[3],
        m[1] * n[2] + m[3] * n[3],
        m[0] * n[4] + m[2] * n[5] + m[4],
        m[1] * n[4] + m[3] * n[5] + m[5],
    ]
}

fn of_usvg(t: usvg::Transform) -> Affine {
    [t.sx, t.ky, t.kx, t.sy, t.tx, t.ty].map(f64::from)
}

/// How the root element's `viewBox` maps onto its size (SVG 1.1, 7.8,
/// `preserveAspectRatio`), inverted: from the canvas's pixels back to the
/// drawing's own units. `None` without a usable `viewBox`.
fn from_pixels(root: roxmltree::Node, size: [f64; 2]) -> Option<([f64; 4], Affine)> {
    let numbers: Vec<f64> = root
        .attribute("viewBox")?
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .map(str::parse)
        .collect::<std::result::Result<_, _>>()
        .ok()?;
    let [x, y, w, h] = <[f64; 4]>::try_from(numbers).ok()?;
    if !(w > 0.0 && h > 0.0 && x.is_finite() && y.is_finite()) {
        return None;
    }
    let aspect = root.attribute("preserveAspectRatio").unwrap_or("");
    let mut words = aspect.split_whitespace().filter(|w| *w != "defer");
    let align = words.next().unwrap_or("xMidYMid");
    let slice = words.next() == Some("slice");
    let (mut sx, mut sy) = (size[0] / w, size[1] / h);
    let (mut tx, mut ty) = (-x * sx, -y * sy);
    if align != "none" {
        let s = if slice { sx.max(sy) } else { sx.min(sy) };
        (sx, sy) = (s, s);
        let (free_x, free_y) = (size[0] - w * s, size[1] - h * s);
        let at = |key_min: &str, key_mid: &str, free: f64| {
            if align.contains(key_min) {
                0.0
            } else if align.contains(key_mid) {
                free / 2.0
            } else {
                free
            }
        };
        tx = -x * s + at("xMin", "xMid", free_x);
        ty = -y * s + at("YMin", "YMid", free_y);
    }
    // The inverse of p -> (sx p.x + tx, sy p.y + ty).
    Some((
        [x, y, w, h],
        [1.0 / sx, 0.0, 0.0, 1.0 / sy, -tx / sx, -ty / sy],
    ))
}

/// What the walk over the tree collects.
#[derive(Default)]
struct Found {
    /// Outlines of filled paths, in the drawing's units.
    filled: Vec<Vec<Segment>>,
    /// Each filled path's rule, name and style.
    rules: Vec<Rule>,
    names: Vec<String>,
    styles: Vec<Style>,
    /// Paths with a stroke and no fill.
    stroked_only: usize,
    anchors: Vec<NamedPoint>,
}

/// An element's name for messages: `<path id="leg">` or the n-th filled
/// shape.
fn element_name(id: &str, index: usize) -> String {
    if id.is_empty() {
        format!("filled shape {} (no id)", index + 1)
    } else {
        format!("element `{id}`")
    }
}

/// The name an anchor's id gives, if the id marks an anchor: `anchor`
/// alone (unnamed), or `anchor` and one of `-`, `_`, `:`, `.` before the
/// name (`anchor-eye`); an id such as `anchorage` is no anchor.
fn anchor_name(id: &str) -> Option<String> {
    let rest = id.strip_prefix("anchor")?;
    if rest.is_empty() {
        return Some(String::new());
    }
    rest.strip_prefix(['-', '_', ':', '.']).map(str::to_string)
}

fn colour(paint: &usvg::Paint) -> Option<[u8; 3]> {
    match paint {
        usvg::Paint::Color(c) => Some([c.red, c.green, c.blue]),
        _ => None,
    }
}

fn walk(group: &usvg::Group, to_user: &Affine, opacity: f64, found: &mut Found) {
    for node in group.children() {
        match node {
            usvg::Node::Group(g) => {
                walk(g, to_user, opacity * f64::from(g.opacity().get()), found);
            }
            usvg::Node::Path(p) => {
                let m = compose(to_user, &of_usvg(p.abs_transform()));
                // Anchors count hidden too (`visibility="hidden"`).
                if let Some(name) = anchor_name(p.id()) {
                    let b = p.data().bounds();
                    let centre = [
                        (f64::from(b.left()) + f64::from(b.right())) / 2.0,
                        (f64::from(b.top()) + f64::from(b.bottom())) / 2.0,
                    ];
                    found.anchors.push(NamedPoint {
                        name,
                        point: apply(&m, centre),
                    });
                    continue;
                }
                if !p.is_visible() {
                    continue;
                }
                // A fill no one sees (`fill-opacity="0"`, `opacity="0"` on
                // it or a group around it) is no fill.
                let seen = |o: usvg::Opacity| opacity * f64::from(o.get()) > 0.0;
                let Some(fill) = p.fill().filter(|f| seen(f.opacity())) else {
                    if p.stroke().is_some_and(|s| seen(s.opacity())) {
                        found.stroked_only += 1;
                    }
                    continue;
                };
                let scale = (m[0] * m[3] - m[1] * m[2]).abs().sqrt();
                let style = Style {
                    fill: colour(fill.paint()),
                    fill_opacity: opacity * f64::from(fill.opacity().get()),
                    stroke: p.stroke().and_then(|s| colour(s.paint())),
                    stroke_width: p
                        .stroke()
                        .map_or(0.0, |s| f64::from(s.width().get()) * scale),
                    stroke_opacity: p
                        .stroke()
                        .map_or(1.0, |s| opacity * f64::from(s.opacity().get())),
                };
                let pt =
                    |q: usvg::tiny_skia_path::Point| apply(&m, [f64::from(q.x), f64::from(q.y)]);
                use usvg::tiny_skia_path::PathSegment as S;
                let segments = p
                    .data()
                    .segments()
                    .map(|s| match s {
                        S::MoveTo(a) => Segment::Move(pt(a)),
                        S::LineTo(a) => Segment::Line(pt(a)),
                        S::QuadTo(c, a) => Segment::Quad(pt(c), pt(a)),
                        S::CubicTo(c1, c2, a) => Segment::Cubic(pt(c1), pt(c2), pt(a)),
                        S::Close => Segment::Close,
                    })
                    .collect();
                found.filled.push(segments);
                found.rules.push(match fill.rule() {
                    usvg::FillRule::NonZero => Rule::NonZero,
                    usvg::FillRule::EvenOdd => Rule::EvenOdd,
                });
                found.names.push(element_name(p.id(), found.names.len()));
                found.styles.push(style);
            }
            usvg::Node::Image(_) | usvg::Node::Text(_) => {}
        }
        // Shapes inside clip paths, masks and patterns are not drawn as
        // such: they are left out.
    }
}

/// Reads an SVG document as one drawing: every visible filled shape
/// (`path` with lines, quadratic and cubic Béziers and arcs, `rect`,
/// `circle`, `ellipse`, `polygon`, `polyline`; through nested groups,
/// transforms and `use`), its curves flattened to chords within
/// `options.tolerance` of the drawing's bounding-box diagonal. Each path's
/// fill rule (`fill-rule`, non-zero by default) tells its holes; the whole
/// must be one region, an outer loop and its holes. The coordinates are
/// the document's own user units (inside its `viewBox`, y down).
///
/// Elements whose `id` is `anchor` or starts with `anchor-` (or `anchor_`,
/// `anchor:`, `anchor.`), such as `<circle id="anchor-eye" cx=... />`, are
/// anchors, not part of the drawing: one point at the centre of the
/// element's bounding box, named by the rest of the id (`eye`; an id of
/// just `anchor` is unnamed). They may be hidden (`visibility="hidden"`);
/// like any SVG shape they need a fill or a stroke to be kept, and
/// `display="none"` drops them.
///
/// The style kept is the first filled element's; the canvas is the
/// document's `viewBox` and size.
///
/// # Errors
/// [`Error::Parse`](crate::Error::Parse) naming `path` when the file is
/// not SVG, has no filled shape (saying how many stroked-only shapes it
/// has), has several separate regions (how many, each's element and
/// bounding box, and what to do), or loops that cross, touch or are too
/// small ([`Drawing::new`]'s checks, naming the element).
pub fn parse_svg_drawing(
    bytes: &[u8],
    path: &Path,
    options: &DrawingOptions,
) -> Result<DrawingFile> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        parse_error(
            path,
            None,
            format!(
                "not UTF-8 text at byte {}: an SVG file is text",
                e.valid_up_to()
            ),
        )
    })?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let doc = roxmltree::Document::parse_with_options(
        text,
        roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        },
    )
    .map_err(|e| parse_error(path, None, format!("not valid SVG (XML): {e}")))?;
    let root = doc.root_element();
    if root.tag_name().name() != "svg" {
        return Err(parse_error(
            path,
            None,
            format!(
                "the document's root element is `<{}>`, not `<svg>`",
                root.tag_name().name()
            ),
        ));
    }
    check_shape_numbers(&doc, path)?;
    let tree = usvg::Tree::from_xmltree(&doc, &usvg::Options::default()).map_err(|e| {
        parse_error(
            path,
            None,
            match e {
                usvg::Error::InvalidSize => "the SVG has no usable size: give the `<svg>` element a width and height or a viewBox".to_string(),
                e => format!("not a usable SVG: {e}"),
            },
        )
    })?;
    let size = [
        f64::from(tree.size().width()),
        f64::from(tree.size().height()),
    ];
    let (view_box, to_user) = from_pixels(root, size)
        .unwrap_or(([0.0, 0.0, size[0], size[1]], [1.0, 0.0, 0.0, 1.0, 0.0, 0.0]));
    let mut found = Found::default();
    walk(tree.root(), &to_user, 1.0, &mut found);
    if found.filled.is_empty() {
        let stroked = match found.stroked_only {
            0 => String::new(),
            n => format!(
                " ({n} shape{} with a stroke and no fill: a drawing is a filled region, so give the outline a fill)",
                if n == 1 { "" } else { "s" }
            ),
        };
        return Err(parse_error(
            path,
            None,
            format!("no filled shape found{stroked}: draw the shape as a filled path, rect, circle, ellipse or polygon"),
        ));
    }
    // The tolerance is relative to the drawing's size: its control points'
    // bounding box.
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for s in found.filled.iter().flatten() {
        let (points, n): ([[f64; 2]; 3], usize) = match *s {
            Segment::Move(a) | Segment::Line(a) => ([a; 3], 1),
            Segment::Quad(c, a) => ([c, a, a], 2),
            Segment::Cubic(c1, c2, a) => ([c1, c2, a], 3),
            Segment::Close => ([[0.0; 2]; 3], 0),
        };
        for p in &points[..n] {
            for i in 0..2 {
                lo[i] = lo[i].min(p[i]);
                hi[i] = hi[i].max(p[i]);
            }
        }
    }
    let diagonal = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    let tolerance = options.tolerance * diagonal;
    let mut loops = Vec::new();
    let mut curves = 0;
    for (element, segments) in found.filled.iter().enumerate() {
        let (flat, c) = flatten(segments, tolerance.max(f64::MIN_POSITIVE));
        curves += c;
        loops.extend(
            flat.into_iter()
                .map(|points| FilledLoop { element, points }),
        );
    }
    let found_regions = regions(&loops, &found.rules);
    let describe = |r: &super::regions::Region| {
        let pts = &loops[r.outer].points;
        let (mut a, mut b) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in pts {
            for i in 0..2 {
                a[i] = a[i].min(p[i]);
                b[i] = b[i].max(p[i]);
            }
        }
        format!(
            "{} from ({}, {}) to ({}, {})",
            found.names[loops[r.outer].element],
            short(a[0]),
            short(a[1]),
            short(b[0]),
            short(b[1])
        )
    };
    let region = match found_regions.len() {
        0 => {
            return Err(parse_error(
                path,
                None,
                "the filled shapes enclose no area: draw the shape as a closed, filled outline"
                    .into(),
            ))
        }
        1 => &found_regions[0],
        n => {
            let list: Vec<String> = found_regions.iter().map(describe).collect();
            let nested = found_regions.iter().any(|r| {
                found_regions.iter().any(|s| {
                    s.outer != r.outer && inside(&loops[s.outer].points, loops[r.outer].points[0])
                })
            });
            let advice = if nested {
                "; a shape drawn over another does not cut a hole in it: to make a hole, draw the outer loop and the hole in one path (with fill-rule=\"evenodd\", or the hole the other way round)"
            } else {
                ""
            };
            return Err(parse_error(
                path,
                None,
                format!(
                    "{n} separate filled regions where a drawing is one region (an outer loop and its holes): {}{advice}; put each region in a file of its own, or join them into one outline",
                    list.join("; ")
                ),
            ));
        }
    };
    let mut chosen = vec![loops[region.outer].points.clone()];
    chosen.extend(region.holes.iter().map(|&h| loops[h].points.clone()));
    let names: Vec<String> = std::iter::once(region.outer)
        .chain(region.holes.iter().copied())
        .map(|l| found.names[loops[l].element].clone())
        .collect();
    let drawing = Drawing::new(chosen).map_err(|e| {
        let which = match &e {
            crate::Error::InvalidDrawing { loop_index, .. } => names
                .get(*loop_index)
                .cloned()
                .unwrap_or_default(),
            _ => String::new(),
        };
        drawing_error(
            e,
            path,
            &format!(
                "loop 0 is the outline of {}, the holes follow in the file's order; this loop is in {which}",
                names[0]
            ),
        )
    })?;
    Ok(DrawingFile {
        drawing,
        style: found.styles[0].clone(),
        canvas: Some(Canvas {
            view_box,
            size,
            flip_y: false,
        }),
        anchors: found.anchors,
        tolerance,
        curves,
        kind: DrawingKind::Svg,
    })
}

/// A coordinate for a message: at most two decimals.
fn short(x: f64) -> String {
    let s = format!("{x:.2}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}
