use meshmorph::render::palette::{slot, Palette};
use meshmorph::render::Rect;

use meshmorph::render::canvas::*;

#[test]
fn primitives_stay_inside() {
    let mut c = Canvas::new(10, 6, Palette::standard());
    c.fill_rect(
        Rect {
            x: 8,
            y: 4,
            width: 100,
            height: 100,
        },
        9,
    );
    assert_eq!(c.count(9), 4);
    c.fill_triangle(
        [[-50.0, -50.0], [50.0, -50.0], [0.0, 50.0]],
        7,
        Some(Rect {
            x: 0,
            y: 0,
            width: 2,
            height: 2,
        }),
    );
    assert_eq!(c.count(7), 4);
    c.draw_line([-5.0, 0.5], [50.0, 0.5], 3, None);
    assert_eq!(c.count(3), 10);
    c.set(10, 0, 1);
    assert_eq!(c.get(10, 0), None);
    assert_eq!(c.get(0, 0), Some(3));
    assert_eq!(c.to_rgb().len(), 180);
}

#[test]
fn text_is_drawn_in_its_box_at_its_scale() {
    let mut c = Canvas::new(40, 20, Palette::standard());
    c.draw_text(2, 3, "Hi", 2, slot::BLACK);
    assert_eq!(Canvas::text_size("Hi", 2), (22, 14));
    // Inside the box only; 'H' is 17 font pixels, 'i' 9.
    for y in 0..20 {
        for x in 0..40 {
            let inside = (2..24).contains(&x) && (3..17).contains(&y);
            assert!(inside || c.get(x, y) == Some(slot::BACKGROUND), "{x} {y}");
        }
    }
    assert_eq!(c.count(slot::BLACK), (17 + 9) * 4);
    // Clipped at the edges, not wrapped.
    c.draw_text(36, 15, "W", 3, slot::GREY);
    assert!(c.count(slot::GREY) > 0);
    assert_eq!(Canvas::text_size("", 1), (0, 7));
}
