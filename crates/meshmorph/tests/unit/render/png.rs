use meshmorph::error::Error;
use meshmorph::render::canvas::Canvas;

use meshmorph::render::palette::{slot, Palette};
use meshmorph::render::png::*;

#[test]
fn png_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("a.png");
    let mut c = Canvas::new(7, 5, Palette::standard());
    c.set(3, 2, slot::FLIPPED_FILL);
    write_png(&path, &c).unwrap();
    let d = ::png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()));
    let mut r = d.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    let info = r.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (7, 5));
    assert_eq!(info.color_type, ::png::ColorType::Indexed);
    assert_eq!(&buf[..35], &c.pixels[..]);
    let empty = Canvas::new(0, 5, Palette::standard());
    assert!(matches!(
        write_png(&path, &empty),
        Err(Error::InvalidArgument(_))
    ));
}
