//! How closely `meshmorph expressions` puts the ARKit shapes on heads whose
//! true shapes are known: heads sampled from ICT-FaceKit's identity model
//! (normal weights on its 100 identity bases, as its
//! `Scripts/sample_random.py`), remeshed (each triangle split in four, every
//! vertex slid along the surface), with the truth the rig's own expressions
//! on that identity (its expression deltas are the same on every identity).
//!
//! ```sh
//! MESHMORPH_ICT_FACEKIT=PATH/TO/ICT-FaceKit cargo run --release -p meshmorph \
//!     --example expressions_accuracy [-- HEADS [LANDMARKS [BASES [WARP]]]]
//! ```
//!
//! BASES: how many of the template's identity bases the fit uses (default
//! all 100; 0: none, the correspondence alone). WARP: millimetres of a
//! smooth deformation outside the identity model added to each sampled
//! head (default 0), for heads the model does not reach.
//!
//! LANDMARKS: `recommended` (the default: the 17 of
//! [`RECOMMENDED_LANDMARKS`]), `all` (the 68), or iBUG numbers separated by
//! commas; each placed exactly where it lies on the sampled head.
//!
//! Prints, for each head and way of carrying the shapes: error (RMS over
//! the face after centring, over the head's bounding-box diagonal) mean and
//! worst over the shapes, the largest vertex error, and the do-nothing
//! baseline; and the time. Warnings about a head (landmarks, openings found
//! closed) go to the error stream.

use std::path::PathBuf;
use std::time::Instant;

use meshmorph::{
    expressions, CarryMethod, ExpressionOptions, ExpressionTemplate, Mesh3, RECOMMENDED_LANDMARKS,
};

/// Deterministic normal samples (xorshift64*, Box-Muller).
struct Normal(u64);
impl Normal {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        ((self.0.wrapping_mul(0x2545F4914F6CDD1D) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn sample(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    }
}

/// The positions of the first `n` vertices of an OBJ, in metres.
fn obj_positions(path: &std::path::Path, n: usize) -> Vec<[f64; 3]> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .filter_map(|l| l.strip_prefix("v "))
        .take(n)
        .map(|l| {
            let mut it = l
                .split_whitespace()
                .map(|x| x.parse::<f64>().unwrap() * 0.01);
            [it.next().unwrap(), it.next().unwrap(), it.next().unwrap()]
        })
        .collect()
}

/// `positions` moved by a smooth field the identity model does not hold:
/// three plane waves of 12 to 20 cm wavelength in random directions, each
/// moving up to `amplitude` metres along a random direction.
fn warped(positions: &[[f64; 3]], amplitude: f64, rng: &mut Normal) -> Vec<[f64; 3]> {
    if amplitude == 0.0 {
        return positions.to_vec();
    }
    let unit = |rng: &mut Normal| {
        let v = [rng.sample(), rng.sample(), rng.sample()];
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|x| x / l)
    };
    let waves: Vec<([f64; 3], [f64; 3], f64, f64)> = (0..3)
        .map(|_| {
            let length = 0.12 + 0.08 * rng.uniform();
            (
                unit(rng),
                unit(rng),
                std::f64::consts::TAU / length,
                std::f64::consts::TAU * rng.uniform(),
            )
        })
        .collect();
    positions
        .iter()
        .map(|&p| {
            waves.iter().fold(p, |acc, (k, d, f, phase)| {
                let s = amplitude / 3.0_f64.sqrt()
                    * (f * (k[0] * p[0] + k[1] * p[1] + k[2] * p[2]) + phase).sin();
                std::array::from_fn(|i| acc[i] + s * d[i])
            })
        })
        .collect()
}

/// A remeshed head: positions, triangles, and for each vertex the original
/// triangle and barycentric coordinates it lies at.
struct Remeshed {
    mesh: Mesh3,
    at: Vec<(usize, [f64; 3])>,
}

fn remesh(head: &Mesh3, rng: &mut Normal) -> Remeshed {
    use std::collections::HashMap;
    let tris = head.triangles();
    let mut at: Vec<(usize, [f64; 3])> = Vec::new();
    let mut corner_of = vec![u32::MAX; head.num_vertices()];
    let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
    let mut out = Vec::new();
    let mut sub_tri_of = Vec::new();
    for (t, tri) in tris.iter().enumerate() {
        let mut corner = |k: usize, at: &mut Vec<(usize, [f64; 3])>| {
            let v = tri[k] as usize;
            if corner_of[v] == u32::MAX {
                corner_of[v] = at.len() as u32;
                let mut b = [0.0; 3];
                b[k] = 1.0;
                at.push((t, b));
            }
            corner_of[v]
        };
        let c = [corner(0, &mut at), corner(1, &mut at), corner(2, &mut at)];
        let mut m = [0u32; 3];
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let key = (a.min(b), a.max(b));
            m[k] = *mid.entry(key).or_insert_with(|| {
                let mut w = [0.0; 3];
                w[k] = 0.5;
                w[(k + 1) % 3] = 0.5;
                at.push((t, w));
                at.len() as u32 - 1
            });
        }
        for s in [
            [c[0], m[0], m[2]],
            [m[0], c[1], m[1]],
            [m[2], m[1], c[2]],
            [m[0], m[1], m[2]],
        ] {
            out.push(s);
            sub_tri_of.push(t);
        }
    }
    // Barycentric coordinates of a new vertex in original triangle `t`.
    let bary_in = |v: usize, t: usize, at: &[(usize, [f64; 3])]| -> [f64; 3] {
        let (t0, b0) = at[v];
        if t0 == t {
            return b0;
        }
        let p: [f64; 3] = std::array::from_fn(|i| {
            (0..3)
                .map(|k| b0[k] * head.positions()[tris[t0][k] as usize][i])
                .sum()
        });
        let mut b = [0.0; 3];
        for k in 0..3 {
            let q = head.positions()[tris[t][k] as usize];
            if (0..3).all(|i| (q[i] - p[i]).abs() < 1e-12) {
                b[k] = 1.0;
                return b;
            }
        }
        // On an edge of t: solve along it.
        for k in 0..3 {
            let a = head.positions()[tris[t][k] as usize];
            let c = head.positions()[tris[t][(k + 1) % 3] as usize];
            let d: [f64; 3] = std::array::from_fn(|i| c[i] - a[i]);
            let s = (0..3).map(|i| (p[i] - a[i]) * d[i]).sum::<f64>()
                / (0..3).map(|i| d[i] * d[i]).sum::<f64>();
            let r: f64 = (0..3).map(|i| (a[i] + s * d[i] - p[i]).powi(2)).sum();
            if r < 1e-20 && (0.0..=1.0).contains(&s) {
                b[k] = 1.0 - s;
                b[(k + 1) % 3] = s;
                return b;
            }
        }
        b0
    };
    // Slide every vertex a random way into one of its triangles.
    let mut first_tri = vec![usize::MAX; at.len()];
    for (s, tri) in out.iter().enumerate() {
        for &v in tri {
            if first_tri[v as usize] == usize::MAX {
                first_tri[v as usize] = s;
            }
        }
    }
    let slid: Vec<(usize, [f64; 3])> = (0..at.len())
        .map(|v| {
            let s = first_tri[v];
            let t = sub_tri_of[s];
            let corners = out[s].map(|c| bary_in(c as usize, t, &at));
            let amount = 0.3 * rng.uniform();
            let own = bary_in(v, t, &at);
            let b = std::array::from_fn(|i| {
                (1.0 - amount) * own[i]
                    + amount * (corners[0][i] + corners[1][i] + corners[2][i]) / 3.0
            });
            (t, b)
        })
        .collect();
    let positions = slid
        .iter()
        .map(|&(t, b)| {
            std::array::from_fn(|i| {
                (0..3)
                    .map(|k| b[k] * head.positions()[tris[t][k] as usize][i])
                    .sum()
            })
        })
        .collect();
    Remeshed {
        mesh: Mesh3::new(positions, out).unwrap(),
        at: slid,
    }
}

fn main() {
    let Some(root) = std::env::var_os("MESHMORPH_ICT_FACEKIT").map(PathBuf::from) else {
        eprintln!(
            "set MESHMORPH_ICT_FACEKIT to a copy of ICT-FaceKit (github.com/ICT-VGL/ICT-FaceKit)"
        );
        std::process::exit(2);
    };
    let heads: usize = std::env::args().nth(1).map_or(3, |a| a.parse().unwrap());
    let landmarks: Vec<String> = match std::env::args().nth(2).as_deref() {
        None | Some("recommended") => RECOMMENDED_LANDMARKS.iter().map(u8::to_string).collect(),
        Some("all") => (1..=68).map(|k: u8| k.to_string()).collect(),
        Some(list) => list.split(',').map(str::to_string).collect(),
    };
    println!("{} landmarks: {}", landmarks.len(), landmarks.join(", "));
    let used_bases: usize = std::env::args().nth(3).map_or(100, |a| a.parse().unwrap());
    let warp: f64 = std::env::args().nth(4).map_or(0.0, |a| a.parse().unwrap());
    let template = ExpressionTemplate::arkit();
    let mut used = template.clone();
    used.identity.truncate(used_bases);
    println!(
        "identity bases fitted: {}; out-of-model warp: {warp} mm",
        used.identity.len()
    );
    let n = template.head.num_vertices();
    let neutral = template.head.positions().to_vec();
    let model = root.join("FaceXModel");
    let bases: Vec<Vec<[f64; 3]>> = (0..100)
        .map(|i| {
            let p = obj_positions(&model.join(format!("identity{i:03}.obj")), n);
            p.iter()
                .zip(&neutral)
                .map(|(a, b)| std::array::from_fn(|k| a[k] - b[k]))
                .collect()
        })
        .collect();
    let mut rng = Normal(0x9E3779B97F4A7C15);
    println!("| head | vertices | way | mean % | worst % (shape) | largest vertex % | baseline mean % | baseline worst % | time s |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for h in 0..heads {
        let w: Vec<f64> = (0..100).map(|_| rng.sample()).collect();
        let identity: Vec<[f64; 3]> = (0..n)
            .map(|v| {
                std::array::from_fn(|k| {
                    neutral[v][k] + (0..100).map(|i| w[i] * bases[i][v][k]).sum::<f64>()
                })
            })
            .collect();
        let identity = warped(&identity, warp * 1e-3, &mut rng);
        let id_head = template.head.with_positions(identity.clone()).unwrap();
        let remeshed = remesh(&id_head, &mut rng);
        let head = &remeshed.mesh;
        let diagonal = head.bounding_box_diagonal();
        let tris = template.head.triangles();
        let face: Vec<usize> = (0..head.num_vertices())
            .filter(|&v| {
                tris[remeshed.at[v].0]
                    .iter()
                    .all(|&c| template.face.contains(&(c as usize)))
            })
            .collect();
        let points: Vec<(String, [f64; 3])> = landmarks
            .iter()
            .map(|k| {
                let v = template
                    .landmark(k)
                    .unwrap_or_else(|| panic!("no landmark {k} in the template"));
                (k.clone(), identity[v as usize])
            })
            .collect();
        for method in [CarryMethod::Displacements, CarryMethod::Transfer] {
            let start = Instant::now();
            let out = expressions(
                &used,
                head,
                &points,
                &ExpressionOptions::default().with_method(method),
            )
            .unwrap();
            let secs = start.elapsed().as_secs_f64();
            for w in &out.warnings {
                eprintln!("head {h}, {method:?}: warning: {w}");
            }
            let (mut sum, mut worst, mut worst_name, mut largest) =
                (0.0, 0.0f64, String::new(), 0.0f64);
            let (mut base_sum, mut base_worst) = (0.0, 0.0f64);
            for (k, name) in out.names.iter().enumerate() {
                let recipe = meshmorph::arkit_recipes(&template.shape_names, false)
                    .0
                    .into_iter()
                    .find(|r| &r.name == name)
                    .unwrap();
                let truth = |v: usize| -> [f64; 3] {
                    let (t, b) = remeshed.at[v];
                    let corner = tris[t].map(|c| template.recipe_delta(&recipe, c as usize));
                    std::array::from_fn(|i| (0..3).map(|c| b[c] * corner[c][i]).sum())
                };
                let errors: Vec<[f64; 3]> = face
                    .iter()
                    .map(|&v| {
                        let t = truth(v);
                        std::array::from_fn(|i| out.deltas[k][v][i] - t[i])
                    })
                    .collect();
                let rms_centred = |e: &[[f64; 3]]| {
                    let m: [f64; 3] = std::array::from_fn(|i| {
                        e.iter().map(|x| x[i]).sum::<f64>() / e.len() as f64
                    });
                    (e.iter()
                        .map(|x| (0..3).map(|i| (x[i] - m[i]).powi(2)).sum::<f64>())
                        .sum::<f64>()
                        / e.len() as f64)
                        .sqrt()
                        / diagonal
                };
                let r = rms_centred(&errors);
                sum += r;
                if r > worst {
                    worst = r;
                    worst_name = name.clone();
                }
                largest = largest.max(
                    errors
                        .iter()
                        .map(|e| (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt())
                        .fold(0.0, f64::max)
                        / diagonal,
                );
                let base: Vec<[f64; 3]> = face.iter().map(|&v| truth(v).map(|x| -x)).collect();
                let b = rms_centred(&base);
                base_sum += b;
                base_worst = base_worst.max(b);
            }
            let m = out.names.len() as f64;
            println!(
                "| {h} | {} | {method:?} | {:.4} | {:.4} ({worst_name}) | {:.3} | {:.4} | {:.4} | {secs:.2} |",
                head.num_vertices(),
                100.0 * sum / m,
                100.0 * worst,
                100.0 * largest,
                100.0 * base_sum / m,
                100.0 * base_worst
            );
        }
    }
}
