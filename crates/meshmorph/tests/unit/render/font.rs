use meshmorph::render::font::*;

#[test]
fn glyphs_fit_their_box_and_differ() {
    for row in GLYPHS.iter().flatten() {
        assert!(u32::from(*row) < 1 << GLYPH_WIDTH);
    }
    let mut seen = std::collections::HashSet::new();
    for c in ' '..='~' {
        assert!(seen.insert(glyph(c)), "{c:?} looks like another glyph");
    }
    assert_eq!(glyph('é'), glyph('?'));
    assert_eq!(glyph(' '), [0; 7]);
}
