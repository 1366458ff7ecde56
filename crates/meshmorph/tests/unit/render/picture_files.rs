use meshmorph::io::picture::Picture;

use meshmorph::render::picture_files::*;
use meshmorph::render::GifOptions;

/// Frame `k`: every pixel's red is `40 k`, opaque.
fn frame(k: usize) -> Picture {
    Picture::from_fn(3, 2, |_, _| [40 * k as u8, 0, 0, 255])
}

#[test]
fn animations_show_their_frames_in_the_order_given() {
    let schedule = GifOptions::default().schedule(4);
    let mut gif = Vec::new();
    write_picture_gif(&mut gif, (3, 2), &schedule, &mut frame).unwrap();
    let mut options = ::gif::DecodeOptions::new();
    options.set_color_output(::gif::ColorOutput::RGBA);
    let mut decoder = options.read_info(gif.as_slice()).unwrap();
    let (mut reds, mut delays) = (Vec::new(), Vec::new());
    while let Some(f) = decoder.read_next_frame().unwrap() {
        reds.push(f.buffer[0]);
        delays.push(f.delay);
    }
    assert_eq!(reds, [0, 40, 80, 120, 80, 40]);
    // The ends held half a second longer, as the other animations' are.
    assert_eq!(delays, [54, 4, 4, 54, 4, 4]);
    let mut apng = Vec::new();
    write_apng(&mut apng, (3, 2), &schedule, &mut frame).unwrap();
    let actl = apng.windows(4).position(|w| w == b"acTL").unwrap();
    let count = u32::from_be_bytes(apng[actl + 4..actl + 8].try_into().unwrap());
    assert_eq!(count, 6);
}
