use meshmorph::render::canvas::Canvas;

use meshmorph::render::palette::{slot, Palette};
use meshmorph::render::resample::*;

#[test]
fn uniform_blocks_keep_their_index_and_mixed_ones_blend() {
    let mut big = Canvas::new(6, 3, Palette::standard());
    // Left block: all fill; right block: one third edge.
    for y in 0..3 {
        for x in 0..3 {
            big.set(x, y, slot::FILL);
        }
        big.set(3, y, slot::BLACK);
    }
    let small = downsample(&big, 3, 2, 1);
    assert_eq!(small.pixels[0], slot::FILL);
    let mixed = small.palette.get(small.pixels[1]);
    let white = small.palette.get(slot::BACKGROUND);
    assert!(mixed != white && mixed != [0, 0, 0], "{mixed:?}");
}
