//! Any text given to the marker file reader, then checked against small
//! meshes: an error, or markers whose points all lie on the meshes, never a
//! panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use meshmorph::shapes::tube;
use meshmorph::{Markers, VertexNumbering};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let (source, target) = (tube(1.0, 0.2, 4, 8), tube(1.5, 0.3, 5, 10));
    for numbering in [VertexNumbering::FromZero, VertexNumbering::FromOne] {
        if let Ok(markers) = Markers::parse(text, "fuzz.txt".as_ref(), numbering) {
            let Ok((markers, _)) = markers.snap(&source, &target) else {
                continue;
            };
            if markers.validate(&source, &target).is_ok() {
                assert!(markers.pairs().iter().all(|[s, t]| {
                    s.position(&source).iter().all(|x| x.is_finite())
                        && t.position(&target).iter().all(|x| x.is_finite())
                }));
            }
        }
    }
});
