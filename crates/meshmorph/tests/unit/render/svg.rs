use meshmorph::render::palette::hex;
use meshmorph::render::style::Style2d;
use meshmorph::render::view::View2d;

use meshmorph::render::style::{Edges, Flipped};
use meshmorph::render::svg::*;

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
    let flipped = meshmorph::mesh::signed_areas(&p, &t)
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
