//! Any text given to the marker file reader, then checked against small
//! meshes: an error or markers in range, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use meshmorph::{Markers, VertexNumbering};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    for numbering in [VertexNumbering::FromZero, VertexNumbering::FromOne] {
        if let Ok(markers) = Markers::parse(text, "fuzz.txt".as_ref(), numbering) {
            if markers.validate(40, 60).is_ok() {
                assert!(markers.pairs().iter().all(|&[s, t]| s < 40 && t < 60));
            }
        }
    }
});
