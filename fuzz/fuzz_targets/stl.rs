//! Any bytes given to the STL reader: an error or a valid mesh, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use meshmorph::io::{parse_mesh, Format};

fuzz_target!(|data: &[u8]| {
    if let Ok(mesh) = parse_mesh(data, Format::Stl, "fuzz.stl".as_ref()) {
        let n = mesh.num_vertices();
        assert!(mesh.positions().iter().flatten().all(|x| x.is_finite()));
        assert!(mesh.triangles().iter().flatten().all(|&i| (i as usize) < n));
    }
});
