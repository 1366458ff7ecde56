use meshmorph::transfer::correspondence::Correspondence;
use std::path::Path;

use meshmorph::io::correspondence_file::*;

/// A map of one pair with the alignment `values` (13 numbers).
fn with_alignment(values: &str) -> String {
    format!("{MAGIC}\nsource 3 1 0\ntarget 3 1 0\nalignment {values}\npairs 1\n0 0\n")
}

#[test]
fn alignments_that_are_similarities_are_read() {
    let p = Path::new("m.corr");
    let turn = "2.5 0 -1 0 1 0 0 0 0 1 1 2 3";
    let c = Correspondence::parse(&with_alignment(turn), p).unwrap();
    assert_eq!(c.alignment().scale, 2.5);
    // Six significant digits of a turn about z by 30 degrees.
    let rounded = "1 0.866025 -0.5 0 0.5 0.866025 0 0 0 1 0 0 0";
    assert!(Correspondence::parse(&with_alignment(rounded), p).is_ok());
}

#[test]
fn alignments_that_are_not_are_blamed_on_the_file() {
    let p = Path::new("m.corr");
    for (values, says) in [
        (
            "1e308 1 0 0 0 1 0 0 0 1 0 0 0",
            "scale 1e308 is out of the range",
        ),
        ("1e-300 1 0 0 0 1 0 0 0 1 0 0 0", "scale 1e-300"),
        ("1 1 0.5 0 0 1 0 0 0 1 0 0 0", "is not a rotation"),
        ("1 2 0 0 0 2 0 0 0 2 0 0 0", "is not a rotation"),
        ("1 -1 0 0 0 1 0 0 0 1 0 0 0", "mirrors"),
    ] {
        let e = Correspondence::parse(&with_alignment(values), p)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("`m.corr`, line 4") && e.contains(says),
            "{values}: {e}"
        );
    }
}
