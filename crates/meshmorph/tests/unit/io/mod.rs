mod atomic;
mod correspondence_file;
mod drawing;
mod gltf;
mod marker_file;
mod marker_points;
mod material_paths;
mod morph_storage;
mod mtl;
mod normal_groups;
mod picked_points;
mod picture;
mod read;
mod triangulate;
mod vertex_attributes;
mod wrap_points;

use meshmorph::error::Error;
use std::path::Path;

use meshmorph::io::*;

#[test]
fn lines_strip_line_ends() {
    let got: Vec<_> = Lines::new(b"\xEF\xBB\xBFa\r\n\nb c\nd").collect();
    assert_eq!(
        got,
        vec![
            (1, &b"a"[..]),
            (2, &b""[..]),
            (3, &b"b c"[..]),
            (4, &b"d"[..])
        ]
    );
}

#[test]
fn uncommented_lines_end_at_comments() {
    let text = b"\xEF\xBB\xBFv 1 # a # b\r\n\nf 1#\n# all\nplain\r\nlast #";
    let got: Vec<_> = UncommentedLines::new(text).collect();
    assert_eq!(
        got,
        vec![
            (1, &b"v 1 "[..]),
            (2, &b""[..]),
            (3, &b"f 1"[..]),
            (4, &b""[..]),
            (5, &b"plain"[..]),
            (6, &b"last "[..])
        ]
    );
    let plain: Vec<_> = UncommentedLines::new(b"a\nb").collect();
    assert_eq!(plain, vec![(1, &b"a"[..]), (2, &b"b"[..])]);
}

/// The fast path of [`parse_f64`] gives the standard library's `f64`,
/// bit for bit, and refuses what it refuses.
#[test]
fn numbers_parse_as_the_standard_library_parses_them() {
    let same = |s: &str| {
        let want = s.parse::<f64>().ok().map(f64::to_bits);
        assert_eq!(parse_f64(s.as_bytes()).map(f64::to_bits), want, "`{s}`");
    };
    for s in [
        "0",
        "-0",
        "+0",
        "-0.0",
        "1.",
        ".5",
        "-.5",
        "1.5",
        "00012.3400",
        "9007199254740992",
        "9007199254740993",
        "0.1",
        "0.18771723470000001",
        "123456789.123456789",
        "1234567890123456789",
        "12345678901234567890",
        "0.0000000000000000000001",
        "1e5",
        "1.5E-3",
        "inf",
        "-infinity",
        "NaN",
        "1.2.3",
        "--1",
        "+-1",
        "1_0",
        "",
        "-",
        "+",
        ".",
        "0x10",
        "1,5",
        " 1",
        "1 ",
    ] {
        same(s);
    }
    // Seeded decimals of 1 to 22 digits, the point anywhere or absent.
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = |n: u64| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state % n
    };
    for _ in 0..100_000 {
        let count = 1 + next(22) as usize;
        let mut s = String::new();
        match next(3) {
            0 => s.push('-'),
            1 if next(4) == 0 => s.push('+'),
            _ => {}
        }
        let point = next(count as u64 + 2) as usize;
        for k in 0..count {
            if k == point {
                s.push('.');
            }
            s.push(char::from(b'0' + next(10) as u8));
        }
        same(&s);
    }
}

#[test]
fn integers_and_numbers() {
    assert_eq!(parse_i64(b"-12"), Some(-12));
    assert_eq!(parse_i64(b"+7"), Some(7));
    assert_eq!(parse_i64(b"-"), None);
    assert_eq!(parse_i64(b"1x"), None);
    assert_eq!(parse_i64(b"99999999999999999999999"), None);
    assert_eq!(parse_f64(b"1e-3"), Some(1e-3));
    let mut buf = Vec::new();
    assert_eq!(parse_f64(b"\xff"), None);
    for x in [
        0.0,
        -0.0,
        1.0,
        0.1,
        1e-7,
        2.5e20,
        5e-324,
        f64::MAX,
        -123.456,
    ] {
        buf.clear();
        push_f64(&mut buf, x);
        let s = std::str::from_utf8(&buf).unwrap();
        assert_eq!(s.parse::<f64>().unwrap().to_bits(), x.to_bits(), "{s}");
        assert!(!s.ends_with(".0"), "{s}");
    }
    for n in [0, 7, 10, 4_294_967_295, u64::MAX] {
        buf.clear();
        push_uint(&mut buf, n);
        assert_eq!(buf, n.to_string().into_bytes());
    }
}

#[test]
fn formats() {
    assert_eq!(
        Format::from_path(Path::new("a/b.OBJ")).unwrap(),
        Format::Obj
    );
    assert_eq!(Format::from_path(Path::new("b.ply")).unwrap(), Format::Ply);
    assert!(matches!(
        Format::from_path(Path::new("b.stp")),
        Err(Error::UnknownFormat { .. })
    ));
    assert!(matches!(
        Format::from_path(Path::new("off")),
        Err(Error::UnknownFormat { .. })
    ));
    assert_eq!("OFF".parse::<Format>().unwrap(), Format::Off);
    let e = "stp".parse::<Format>().unwrap_err().to_string();
    assert!(e.contains("obj, off, ply"), "{e}");
    assert_eq!(Format::Ply.to_string(), "ply");
}
