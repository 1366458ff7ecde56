use meshmorph::io::picture::Picture;
use std::time::Duration;

use meshmorph::playback::shown_order;
use meshmorph::render::picture_files::*;

/// Frame `k`: every pixel's red is `40 k`, opaque.
fn frame(k: usize) -> Picture {
    Picture::from_fn(3, 2, |_, _| [40 * k as u8, 0, 0, 255])
}

#[test]
fn animations_show_their_frames_in_the_order_given() {
    let order = shown_order(4, true);
    let mut gif = Vec::new();
    write_picture_gif(
        &mut gif,
        (3, 2),
        &order,
        Duration::from_millis(40),
        &mut frame,
    )
    .unwrap();
    let mut options = ::gif::DecodeOptions::new();
    options.set_color_output(::gif::ColorOutput::RGBA);
    let mut decoder = options.read_info(gif.as_slice()).unwrap();
    let mut reds = Vec::new();
    while let Some(f) = decoder.read_next_frame().unwrap() {
        reds.push(f.buffer[0]);
    }
    assert_eq!(reds, [0, 40, 80, 120, 80, 40]);
    let mut apng = Vec::new();
    write_apng(
        &mut apng,
        (3, 2),
        &order,
        Duration::from_millis(40),
        &mut frame,
    )
    .unwrap();
    let actl = apng.windows(4).position(|w| w == b"acTL").unwrap();
    let count = u32::from_be_bytes(apng[actl + 4..actl + 8].try_into().unwrap());
    assert_eq!(count, 6);
}
