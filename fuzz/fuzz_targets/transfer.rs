//! A small source mesh with a pose, a target mesh and a triangle map, all
//! arbitrary: `Transfer::new` refuses or applying the pose gives one
//! position per target vertex.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use meshmorph::{Correspondence, Mesh3, Transfer, TransferOptions};

#[derive(Debug, Arbitrary)]
struct Input {
    source: Vec<[f64; 3]>,
    source_triangles: Vec<[u8; 3]>,
    pose_offsets: Vec<[f64; 3]>,
    target: Vec<[f64; 3]>,
    target_triangles: Vec<[u8; 3]>,
    pairs: Vec<[u8; 2]>,
    pins: Vec<u8>,
}

fn mesh(positions: &[[f64; 3]], triangles: &[[u8; 3]]) -> Option<Mesh3> {
    let positions = positions[..positions.len().min(24)].to_vec();
    let triangles = triangles.iter().take(32).map(|t| t.map(u32::from)).collect();
    Mesh3::new(positions, triangles).ok()
}

fuzz_target!(|input: Input| {
    let (Some(source), Some(target)) = (
        mesh(&input.source, &input.source_triangles),
        mesh(&input.target, &input.target_triangles),
    ) else {
        return;
    };
    let pairs = input
        .pairs
        .iter()
        .map(|p| p.map(u32::from))
        .filter(|&[s, t]| (s as usize) < source.num_triangles() && (t as usize) < target.num_triangles())
        .collect();
    let correspondence = Correspondence::new(pairs, &source, &target);
    let pins = input
        .pins
        .iter()
        .filter(|&&v| (v as usize) < target.num_vertices())
        .map(|&v| (u32::from(v), target.positions()[v as usize]))
        .collect();
    let Ok(transfer) = Transfer::new(
        &source,
        &target,
        &correspondence,
        &TransferOptions::default().with_pins(pins),
    ) else {
        return;
    };
    let pose: Vec<[f64; 3]> = source
        .positions()
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let d = input.pose_offsets.get(k).copied().unwrap_or([0.0; 3]);
            [p[0] + d[0], p[1] + d[1], p[2] + d[2]]
        })
        .collect();
    if let Ok(pose) = source.with_positions(pose) {
        if let Ok(out) = transfer.apply(&pose) {
            assert_eq!(out.len(), target.num_vertices());
        }
    }
});
