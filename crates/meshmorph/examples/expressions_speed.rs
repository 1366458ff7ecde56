//! How long `meshmorph expressions` takes, correspondence included, on heads
//! of growing size: the built-in template's head given other proportions
//! and split by midpoint subdivision (each triangle in four, one to three
//! times: 56 thousand to 900 thousand vertices), its 17 recommended
//! landmarks where the template's went; the ARKit shapes carried by
//! displacements (the default) and by deformation transfer. Also the
//! process's peak memory during each, beside the size of what it returns
//! (51 shapes' deltas of every vertex, as 64-bit floats).
//!
//! ```sh
//! cargo run --release -p meshmorph --example expressions_speed [-- LEVELS [no-identity]]
//! ```
//!
//! LEVELS: how many subdivisions, 0 to 3 (default 3). A second argument
//! `no-identity` leaves out the fit of the template's identity model.

use std::time::Instant;

use meshmorph::shapes::subdivide;
use meshmorph::{
    expressions, landmark_name, CarryMethod, ExpressionOptions, ExpressionTemplate, Mesh3,
    RECOMMENDED_LANDMARKS,
};

#[path = "support/memory.rs"]
mod memory;
use memory::{peak_memory, reset_peak};
#[path = "support/timing.rs"]
#[allow(dead_code)]
mod timing;

/// The template's head with a wider jaw, a longer face and fuller cheeks.
fn other_proportions(head: &Mesh3) -> Mesh3 {
    let diagonal = head.bounding_box_diagonal();
    let positions = head
        .positions()
        .iter()
        .map(|&[x, y, z]| {
            let (u, v) = (x / diagonal, y / diagonal);
            [
                x * (1.08 - 0.4 * v),
                1.1 * y + 0.2 * diagonal * u * u,
                0.9 * z + 0.02 * diagonal * (1.0 - 20.0 * u * u).max(0.0),
            ]
        })
        .collect();
    head.with_positions(positions).unwrap()
}

fn main() {
    let levels: usize = timing::args()
        .first()
        .map(|a| a.parse().expect("LEVELS: a number from 0 to 3"))
        .unwrap_or(3)
        .min(3);
    let mut template = ExpressionTemplate::arkit();
    if std::env::args().nth(2).as_deref() == Some("no-identity") {
        template.identity.clear();
    }
    let base = other_proportions(&template.head);
    let points: Vec<(String, [f64; 3])> = RECOMMENDED_LANDMARKS
        .iter()
        .map(|&n| {
            let v = template.landmark(&n.to_string()).unwrap();
            (landmark_name(n), base.positions()[v as usize])
        })
        .collect();
    println!(
        "| head vertices | triangles | displacements | transfer | peak memory, displacements / transfer (the result's deltas) |"
    );
    println!("|---|---|---|---|---|");
    let mut head = base;
    for level in 0..=levels {
        if level > 0 {
            head = subdivide(&head);
        }
        let mut row = Vec::new();
        let mut peaks = Vec::new();
        for method in [CarryMethod::Displacements, CarryMethod::Transfer] {
            let options = ExpressionOptions::default().with_method(method);
            reset_peak();
            let begin = Instant::now();
            let out = expressions(&template, &head, &points, &options).unwrap();
            row.push(timing::fmt(begin.elapsed().as_secs_f64()));
            peaks.extend(peak_memory());
            assert_eq!(out.names.len(), 51);
        }
        // What the call returns: a delta of every vertex in every shape.
        let result = 51 * head.num_vertices() * 24;
        let memory = match peaks[..] {
            [d, t] => format!(
                "{:.0} / {:.0} MB ({:.0} MB)",
                d as f64 / 1e6,
                t as f64 / 1e6,
                result as f64 / 1e6
            ),
            _ => "–".to_string(),
        };
        println!(
            "| {} | {} | {} | {} | {memory} |",
            head.num_vertices(),
            head.num_triangles(),
            row[0],
            row[1]
        );
    }
}
