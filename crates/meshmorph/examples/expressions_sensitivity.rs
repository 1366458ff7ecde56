//! How precisely a head's correspondence to the built-in template must be
//! found for the shapes carried through it to be right at every vertex:
//! for each slip along the template's surface (0.1 to 2 mm), the largest
//! change of any ARKit shape's displacement between a face vertex and a
//! point of the surface that close to it, as a fraction of the template's
//! bounding-box diagonal, and how many face vertices can change by more
//! than 1 %.
//!
//! ```sh
//! cargo run --release -p meshmorph --example expressions_sensitivity
//! ```
//!
//! Needs only the shipped template. A slip that changes a vertex's motion by
//! more than 1 % of the diagonal is a correspondence that can put that
//! vertex off by more than 1 %, however the shape is carried.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

use meshmorph::{arkit_recipes, ExpressionTemplate};

/// Slips along the surface, in metres (the template is modelled in metres).
const SLIPS: [f64; 5] = [0.1e-3, 0.25e-3, 0.5e-3, 1e-3, 2e-3];

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt()
}

/// The vertices within `radius` of `from` along the edges of the mesh.
fn within(
    from: usize,
    radius: f64,
    positions: &[[f64; 3]],
    neighbours: &[Vec<usize>],
) -> Vec<usize> {
    let mut reached: HashMap<usize, f64> = HashMap::from([(from, 0.0)]);
    // Distances in nanometres, so the heap orders integers.
    let mut heap = BinaryHeap::from([(Reverse(0u64), from)]);
    while let Some((Reverse(d), u)) = heap.pop() {
        let d = d as f64 * 1e-9;
        if d > reached[&u] {
            continue;
        }
        for &w in &neighbours[u] {
            let next = d + distance(positions[u], positions[w]);
            if next <= radius && next < *reached.get(&w).unwrap_or(&f64::INFINITY) {
                reached.insert(w, next);
                heap.push((Reverse((next * 1e9) as u64), w));
            }
        }
    }
    reached.into_keys().collect()
}

fn main() {
    let template = ExpressionTemplate::arkit();
    let positions = template.head.positions();
    let diagonal = template.head.bounding_box_diagonal();
    let mut neighbours = vec![Vec::new(); positions.len()];
    for t in template.head.triangles() {
        for k in 0..3 {
            let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
            neighbours[a].push(b);
            neighbours[b].push(a);
        }
    }
    let (recipes, _) = arkit_recipes(&template.shape_names, false);
    let deltas: Vec<Vec<[f64; 3]>> = recipes
        .iter()
        .map(|r| {
            (0..positions.len())
                .map(|v| template.recipe_delta(r, v))
                .collect()
        })
        .collect();
    let corners: Vec<[f64; 3]> = ["61", "65"]
        .iter()
        .map(|n| positions[template.landmark(n).expect("iBUG landmark") as usize])
        .collect();
    println!(
        "template: {} face vertices, diagonal {:.4} m, {} shapes",
        template.face.len(),
        diagonal,
        recipes.len()
    );
    println!("| slip along the surface | largest change (% of the diagonal) | shape | face vertices that can change by more than 1 % | of them within 5 mm of a mouth's inner corner (iBUG 61, 65) |");
    println!("|---|---|---|---|---|");
    for slip in SLIPS {
        let (mut largest, mut shape) = (0.0f64, 0);
        let (mut over, mut at_corner) = (0, 0);
        for v in template.face.clone() {
            let near = within(v, slip, positions, &neighbours);
            let mut most = 0.0f64;
            for (k, d) in deltas.iter().enumerate() {
                for &u in &near {
                    let change = distance(d[v], d[u]) / diagonal;
                    most = most.max(change);
                    if change > largest {
                        (largest, shape) = (change, k);
                    }
                }
            }
            if most > 0.01 {
                over += 1;
                if corners.iter().any(|&c| distance(c, positions[v]) < 5e-3) {
                    at_corner += 1;
                }
            }
        }
        println!(
            "| {:.2} mm | {:.3} | {} | {over} | {at_corner} |",
            slip * 1e3,
            100.0 * largest,
            recipes[shape].name
        );
    }
}
