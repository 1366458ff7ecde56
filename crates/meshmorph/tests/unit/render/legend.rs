use meshmorph::render::canvas::Canvas;
use meshmorph::render::palette::{slot, Ramp};

use meshmorph::render::legend::*;
use meshmorph::render::palette::Palette;

#[test]
fn the_strip_goes_below_and_keeps_the_picture() {
    let mut c = Canvas::new(300, 40, Palette::standard());
    c.fill_rect(c.bounds(), slot::GREY);
    let legend = Legend {
        title: "distance",
        ramps: &Ramp::SCALE,
        ticks: &[(0, "0"), (7, "2 %"), (8, "more")],
    };
    let out = with_legend(&c, &legend);
    assert_eq!(out.width, 300);
    assert!(out.height > 40 + 20);
    assert_eq!(out.pixels[..c.pixels.len()], c.pixels[..]);
    for ramp in Ramp::SCALE {
        assert!(out.count(ramp.index(0.6)) > 0);
    }
    assert!(out.count(slot::EDGE_3D) > 0);
    // Too narrow for anything: no panic.
    let tiny = with_legend(&Canvas::new(3, 2, Palette::standard()), &legend);
    assert_eq!(tiny.width, 3);
    let none = Legend {
        title: "",
        ramps: &[],
        ticks: &[(5, "x")],
    };
    assert_eq!(with_legend(&c, &none).width, 300);
}
