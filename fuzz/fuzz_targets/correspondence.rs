//! Any text given to the correspondence reader, then checked against two
//! small meshes: an error or a map that fits, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use meshmorph::{shapes, Correspondence};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(c) = Correspondence::parse(text, "fuzz.corr".as_ref()) {
        let source = shapes::tube(1.0, 0.2, 3, 4);
        let target = shapes::tube(1.0, 0.3, 4, 5);
        if c.check_fits(&source, &target).is_ok() {
            assert!(c
                .pairs()
                .iter()
                .all(|&[s, t]| (s as usize) < source.num_triangles()
                    && (t as usize) < target.num_triangles()));
        }
    }
});
