use meshmorph::error::Error;
use meshmorph::io::picture::{Picture, PictureShape};

use meshmorph::io::picture::arm_sprite;
use meshmorph::render::picture_frames::*;

#[test]
fn dissolve_blends_between_its_moments_only() {
    assert_eq!(dissolve_blend(0.25, None), 0.25);
    let span = Some([0.3, 0.7]);
    assert_eq!(dissolve_blend(0.1, span), 0.0);
    assert!((dissolve_blend(0.5, span) - 0.5).abs() < 1e-12);
    assert_eq!(dissolve_blend(0.9, span), 1.0);
    let step = Some([0.5, 0.5]);
    assert_eq!(dissolve_blend(0.49, step), 0.0);
    assert_eq!(dissolve_blend(0.5, step), 1.0);
}

#[test]
fn frame_times_include_both_ends() {
    assert_eq!(frame_times(1), vec![0.0]);
    assert_eq!(frame_times(3), vec![0.0, 0.5, 1.0]);
}

#[test]
fn the_ends_are_the_pictures_and_bad_options_are_refused() {
    let size = (80, 60);
    let (a, b) = (arm_sprite(0.0, size), arm_sprite(1.2, size));
    let names = [String::from("a"), String::from("b")];
    let frames =
        PictureFrames::new([&a, &b], &[], &PictureMorphOptions::default(), &names).unwrap();
    assert_eq!(frames.shape(), PictureShape::Sprite);
    assert_eq!(frames.draw(0.0), a);
    assert_eq!(frames.draw(1.0), b);
    for options in [
        PictureMorphOptions::default().with_trace_tolerance(0.0),
        PictureMorphOptions::default().with_frame_size(Some((0, 10))),
        PictureMorphOptions::default().with_dissolve(Some([0.2, f64::NAN])),
    ] {
        let e = PictureFrames::new([&a, &b], &[], &options, &names).err();
        assert!(matches!(e, Some(Error::InvalidArgument(_))), "{options:?}");
    }
    let opaque = Picture::from_fn(80, 60, |_, _| [10, 20, 30, 255]);
    let e = PictureFrames::new([&a, &opaque], &[], &PictureMorphOptions::default(), &names)
        .err()
        .unwrap();
    assert!(e.to_string().contains("has transparency"), "{e}");
}
