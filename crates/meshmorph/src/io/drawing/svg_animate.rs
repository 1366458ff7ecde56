//! A morph as one animated SVG: the path's `d` animated through every
//! frame with SMIL's `<animate>`, which browsers play without script.

use std::io::Write;

use super::svg_write::{paint_attributes, svg_open, svg_path_data};
use super::Animation;
use crate::playback::shown_order;

/// Writes every frame of `animation.frames` as one SVG document whose path's `d`
/// goes through them at `fps` frames a second, over and over
/// (`repeatCount="indefinite"`): one `values` entry a frame shown
/// (forward, then back with `boomerang`), linearly between them. `loops`,
/// `style` and `canvas` as for [`write_svg_frame`](super::write_svg_frame).
///
/// # Errors
/// The writer's.
pub fn write_animated_svg(w: &mut dyn Write, animation: &Animation<'_>) -> std::io::Result<()> {
    let a = animation;
    let order = shown_order(a.frames.num_frames(), a.boomerang);
    let mut data = vec![String::new(); a.frames.num_frames()];
    for (k, d) in data.iter_mut().enumerate() {
        a.frames
            .with_frame(k, &mut |p| *d = svg_path_data(p, a.loops, a.canvas));
    }
    w.write_all(svg_open(a.canvas).as_bytes())?;
    write!(
        w,
        "  <path {} d=\"{}\">",
        paint_attributes(a.style, a.canvas.decimals()),
        data.first().map_or("", String::as_str)
    )?;
    if order.len() > 1 {
        // With `values`, the time between two values is dur / (n - 1);
        // the loop closes on the first frame again.
        let mut shown: Vec<&str> = order.iter().map(|&k| data[k].as_str()).collect();
        if a.boomerang {
            shown.push(&data[0]);
        }
        let seconds = (shown.len() - 1) as f64 / a.fps;
        write!(
            w,
            "\n    <animate attributeName=\"d\" dur=\"{seconds}s\" repeatCount=\"indefinite\" calcMode=\"linear\" values=\""
        )?;
        for (i, d) in shown.iter().enumerate() {
            if i > 0 {
                w.write_all(b";\n")?;
            }
            w.write_all(d.as_bytes())?;
        }
        write!(w, "\"/>\n  ")?;
    }
    writeln!(w, "</path>\n</svg>")
}
