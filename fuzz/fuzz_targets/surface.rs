//! Keys of a small mesh in space (two or three: the first on a coarse grid,
//! the others moved from it by grid offsets, and one coordinate of one key
//! possibly replaced by any number: NaN, huge and tiny included; repeated and
//! collapsed points happen on the grid), options, times and blend weights:
//! `Sequence::<3>::new` and `Blend::<3>::new` refuse, or every frame has one
//! position per vertex, finite between the keys (times from 0 to the last
//! key, weights from 0 to 1; farther out, extrapolated stretches may
//! overflow, which the command line reports).
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use meshmorph::{Blend, InterpolatorOptions, Mesh3, Sequence, StretchMode};

#[derive(Debug, Arbitrary)]
struct Input {
    first: Vec<[i8; 3]>,
    offsets: Vec<Vec<[i8; 3]>>,
    wild: Option<(u8, u8, u8, f64)>,
    triangles: Vec<[u8; 3]>,
    consistency: bool,
    log_stretch: bool,
    allow_flips: bool,
    times: Vec<f64>,
    weights: Vec<f64>,
}

fuzz_target!(|input: Input| {
    let n = input.first.len().min(32);
    if n < 3 {
        return;
    }
    let grid = |p: [i8; 3]| p.map(|x| f64::from(x) / 16.0);
    let first: Vec<[f64; 3]> = input.first[..n].iter().map(|&p| grid(p)).collect();
    // Vertices are taken modulo n so that most inputs make a mesh; a
    // triangle index out of range is tried by the other targets.
    let triangles: Vec<[u32; 3]> = input
        .triangles
        .iter()
        .take(48)
        .map(|t| t.map(|v| u32::from(v) % n as u32))
        .collect();
    let mut positions = vec![first.clone()];
    for offsets in input.offsets.iter().take(2) {
        positions.push(
            first
                .iter()
                .enumerate()
                .map(|(v, p)| {
                    let d = grid(offsets.get(v).copied().unwrap_or([0; 3]));
                    [p[0] + d[0], p[1] + d[1], p[2] + d[2]]
                })
                .collect(),
        );
    }
    if let Some((key, vertex, axis, value)) = input.wild {
        let key = usize::from(key) % positions.len();
        positions[key][usize::from(vertex) % n][usize::from(axis) % 3] = value;
    }
    let mut keys = Vec::new();
    for p in positions {
        let Ok(key) = Mesh3::new(p, triangles.clone()) else {
            return;
        };
        keys.push(key);
    }
    let options = InterpolatorOptions::default()
        .with_consistency(input.consistency)
        .with_stretch(if input.log_stretch {
            StretchMode::Log
        } else {
            StretchMode::Linear
        })
        .with_allow_flips(input.allow_flips);
    if let Ok(sequence) = Sequence::<3>::new(&keys, &options) {
        let last = (keys.len() - 1) as f64;
        for &s in input.times.iter().take(8) {
            if !s.is_finite() || s < -1.0 || s > last + 1.0 {
                continue;
            }
            let frame = sequence.at(s);
            assert_eq!(frame.len(), n);
            if (0.0..=last).contains(&s) {
                assert!(
                    frame.iter().flatten().all(|x| x.is_finite()),
                    "{s}: {frame:?}"
                );
            }
            let _ = sequence.count_turned_over(&frame);
        }
    }
    if let Ok(blend) = Blend::<3>::new(&keys[0], &keys[1..], &options) {
        let weights: Vec<f64> = (0..keys.len() - 1)
            .map(|k| input.weights.get(k).copied().unwrap_or(0.0))
            .collect();
        if weights.iter().all(|w| w.is_finite() && w.abs() <= 4.0) {
            let frame = blend.at(&weights);
            assert_eq!(frame.len(), n);
            if weights.iter().all(|w| (0.0..=1.0).contains(w)) {
                assert!(
                    frame.iter().flatten().all(|x| x.is_finite()),
                    "{weights:?}: {frame:?}"
                );
            }
            let _ = blend.count_turned_over(&frame);
        }
    }
});
