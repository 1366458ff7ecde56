use meshmorph::render::palette::*;

#[test]
fn ramps_go_from_dark_to_light_and_do_not_overlap_slots() {
    let p = Palette::standard();
    for r in Ramp::ALL {
        assert!(r.first as usize + r.len as usize <= 256);
        assert!(r.first > slot::EDGE_3D);
        let lum = |c: Rgb| c.iter().map(|&x| u32::from(x)).sum::<u32>();
        for k in 1..r.len {
            assert!(lum(p.get(r.first + k)) >= lum(p.get(r.first + k - 1)));
        }
        assert_eq!(r.index(0.0), r.first);
        assert_eq!(r.index(1.0), r.first + r.len - 1);
        assert_eq!(r.index(7.0), r.first + r.len - 1);
        assert_eq!(r.index(f64::NAN), r.first);
    }
    // The scale's steps fill the rest of the palette, each its own hue.
    let scale = Ramp::SCALE;
    assert_eq!(scale[0].first, Ramp::GREY.first + Ramp::GREY.len);
    assert_eq!(scale[7].first as usize + scale[7].len as usize, 256);
    for pair in scale.windows(2) {
        assert_eq!(pair[0].first + pair[0].len, pair[1].first);
        assert_ne!(p.get(pair[0].index(0.5)), p.get(pair[1].index(0.5)));
    }
    assert_eq!(Ramp::on_scale(0.0), scale[0]);
    assert_eq!(Ramp::on_scale(-3.0), scale[0]);
    assert_eq!(Ramp::on_scale(0.13), scale[0]);
    assert_eq!(Ramp::on_scale(0.15), scale[1]);
    assert_eq!(Ramp::on_scale(0.99), scale[6]);
    assert_eq!(Ramp::on_scale(1.0), scale[7]);
    assert_eq!(Ramp::on_scale(5.0), scale[7]);
    assert_eq!(Ramp::on_scale(f64::NAN), scale[7]);
    assert_eq!(p.get(slot::BACKGROUND), [255, 255, 255]);
    assert_eq!(p.to_bytes().len(), 768);
    assert_eq!(hex([255, 0, 16]), "#ff0010");
}
