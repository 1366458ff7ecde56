use meshmorph::render::canvas::Canvas;
use meshmorph::render::palette::{slot, Ramp};
use meshmorph::render::shade3d::Style3d;
use meshmorph::render::Rect;

use meshmorph::render::grid::*;

#[test]
fn rows_share_a_scale_and_stay_in_their_cells() {
    let (p, t) = crate::render::shade3d::cube();
    let big: Vec<[f64; 3]> = p.iter().map(|q| q.map(|x| 3.0 * x)).collect();
    let camel: Vec<[f64; 3]> = p.iter().map(|q| [q[0], 2.0 * q[1], q[2]]).collect();
    let rows = [
        GridRow {
            triangles: &t,
            poses: vec![p.as_slice(), big.as_slice(), p.as_slice()],
            style: Style3d::default(),
        },
        GridRow {
            triangles: &t,
            poses: vec![camel.as_slice()],
            style: Style3d::with_ramp(Ramp::SAND),
        },
    ];
    let options = GridOptions {
        cell_width: 100,
        margin_px: 5,
        ..GridOptions::default()
    };
    let layout = GridLayout::fit(&rows, &options);
    assert_eq!(layout.columns, 3);
    assert_eq!(layout.cell_height % 2, 0);
    let c = layout.render(&rows);
    assert_eq!((c.width, c.height), (300, 2 * layout.cell_height));
    let in_ramp = |r: Ramp, i: u8| (r.first..r.first + r.len).contains(&i);
    let count_in = |rect: Rect, r: Ramp| {
        let mut n = 0;
        for y in rect.y..rect.y + rect.height {
            for x in rect.x..rect.x + rect.width {
                n += usize::from(in_ramp(r, c.get(x, y).unwrap()));
            }
        }
        n
    };
    // Same scale along the row: the small cube is 1/9 of the big one.
    let (small, large) = (
        count_in(layout.cell(0, 0), Ramp::BLUE),
        count_in(layout.cell(0, 1), Ramp::BLUE),
    );
    assert!(
        small > 0 && (8.0..10.0).contains(&(large as f64 / small as f64)),
        "{small} {large}"
    );
    assert_eq!(count_in(layout.cell(0, 2), Ramp::BLUE), small);
    assert!(count_in(layout.cell(1, 0), Ramp::SAND) > small);
    assert_eq!(count_in(layout.cell(1, 1), Ramp::SAND), 0);
    // Margins are background.
    for x in 0..300 {
        assert_eq!(c.get(x, 0), Some(slot::BACKGROUND));
    }
    let none = render_grid_3d(&[], &GridOptions::default());
    assert!(none.width > 0 && none.height > 0);
}

#[test]
fn captions_sit_in_their_band_and_tall_rows_stand_side_by_side() {
    let (p, t) = crate::render::shade3d::cube();
    let tall: Vec<[f64; 3]> = p.iter().map(|q| [q[0], 3.0 * q[1], q[2]]).collect();
    let rows = [
        GridRow {
            triangles: &t,
            poses: vec![tall.as_slice()],
            style: Style3d::default(),
        },
        GridRow {
            triangles: &t,
            poses: vec![tall.as_slice()],
            style: Style3d::with_ramp(Ramp::SAND),
        },
    ];
    let options = GridOptions {
        longest_side: Some(400),
        captions: true,
        tall_rows_side_by_side: true,
        ..GridOptions::default()
    };
    let layout = GridLayout::fit(&rows, &options);
    assert!(layout.transposed());
    let (w, h) = layout.size();
    assert_eq!((w, h), (2 * layout.cell_width, layout.cell_height));
    assert_eq!(layout.cell(1, 0).x, layout.cell_width);
    assert_eq!(layout.caption_px, 2 * 13);
    let mut c = layout.render(&rows);
    let band = |c: &Canvas, column: u32| {
        let cell = layout.cell(column, 0);
        (cell.x..cell.x + cell.width)
            .flat_map(|x| (cell.y..cell.y + layout.caption_px).map(move |y| (x, y)))
            .filter(|&(x, y)| c.get(x, y) != Some(slot::BACKGROUND))
            .count()
    };
    // The meshes stay below the band; the caption is drawn in it.
    assert_eq!((band(&c, 0), band(&c, 1)), (0, 0));
    layout.caption(&mut c, 1, 0, "target: a tall cube");
    assert_eq!(band(&c, 0), 0);
    assert!(band(&c, 1) > 100);
    // Without the option, the same rows stand one above the other.
    let stacked = GridLayout::fit(
        &rows,
        &GridOptions {
            tall_rows_side_by_side: false,
            ..options
        },
    );
    assert!(!stacked.transposed());
    assert_eq!(stacked.size(), (w / 2, 2 * h));
}

#[test]
fn the_longest_side_holds_tall_and_wide_meshes() {
    let (p, t) = crate::render::shade3d::cube();
    let stretch = |s: [f64; 3]| -> Vec<[f64; 3]> {
        p.iter()
            .map(|q| std::array::from_fn(|k| q[k] * s[k]))
            .collect()
    };
    let options = GridOptions {
        longest_side: Some(200),
        direction: [0.0, 0.0, -1.0],
        up: [0.0, 1.0, 0.0],
        margin_px: 10,
        ..GridOptions::default()
    };
    let size = |pose: &[[f64; 3]]| {
        let rows = [GridRow {
            triangles: &t,
            poses: vec![pose],
            style: Style3d::default(),
        }];
        let layout = GridLayout::fit(&rows, &options);
        (layout.cell_width, layout.cell_height)
    };
    // Four times as tall as wide: 200 high, 45 + 20 wide, raised to half.
    assert_eq!(size(&stretch([1.0, 4.0, 1.0])), (100, 200));
    let (w, h) = size(&stretch([1.0, 1.5, 1.0])); // 120 + 20 wide
    assert_eq!((w, h), (140, 200));
    // Twice as wide as tall: 200 wide, 90 + 20 high.
    assert_eq!(size(&stretch([2.0, 1.0, 1.0])), (200, 110));
}
