//! Two small planar meshes with shared triangles and arbitrary positions
//! (NaN, huge, repeated and collapsed points included), options and times:
//! `Interpolator::new` refuses or every frame is finite.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use meshmorph::{Interpolator, InterpolatorOptions, Mesh2, StretchMode};

#[derive(Debug, Arbitrary)]
struct Input {
    source: Vec<[f64; 2]>,
    target_offsets: Vec<[f64; 2]>,
    triangles: Vec<[u8; 3]>,
    consistency: bool,
    turns: i8,
    log_stretch: bool,
    allow_flips: bool,
    times: Vec<f64>,
}

fuzz_target!(|input: Input| {
    let n = input.source.len().min(32);
    let source: Vec<[f64; 2]> = input.source[..n].to_vec();
    let target: Vec<[f64; 2]> = source
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let d = input.target_offsets.get(k).copied().unwrap_or([0.0; 2]);
            [p[0] + d[0], p[1] + d[1]]
        })
        .collect();
    let triangles: Vec<[u32; 3]> = input
        .triangles
        .iter()
        .take(48)
        .map(|t| t.map(u32::from))
        .collect();
    let (Ok(s), Ok(t)) = (
        Mesh2::new(source, triangles.clone()),
        Mesh2::new(target, triangles),
    ) else {
        return;
    };
    let options = InterpolatorOptions::default()
        .with_consistency(input.consistency)
        .with_turns(i32::from(input.turns))
        .with_stretch(if input.log_stretch {
            StretchMode::Log
        } else {
            StretchMode::Linear
        })
        .with_allow_flips(input.allow_flips);
    let Ok(morph) = Interpolator::new(&s, &t, &options) else {
        return;
    };
    for &time in input.times.iter().take(8) {
        if !time.is_finite() || time.abs() > 4.0 {
            continue;
        }
        let frame = morph.at(time);
        assert_eq!(frame.len(), s.num_vertices());
        let _ = morph.count_flipped(&frame);
    }
});
