//! A frame of a morph as polygons in text, read back by
//! [`parse_text_drawing`](super::parse_text_drawing).

use std::io::Write;

use super::svg_write::push_number;

/// Writes the loops (vertex indices into `positions`, outer loop first)
/// as lines `x y`, a blank line between loops, every number the shortest
/// text that reads back to it.
///
/// # Errors
/// The writer's.
pub fn write_text_frame(
    w: &mut dyn Write,
    positions: &[[f64; 2]],
    loops: &[Vec<u32>],
) -> std::io::Result<()> {
    let mut out = Vec::with_capacity(loops.iter().map(Vec::len).sum::<usize>() * 24);
    for (l, indices) in loops.iter().enumerate() {
        if l > 0 {
            out.push(b'\n');
        }
        for &v in indices {
            let p = positions[v as usize];
            push_number(&mut out, p[0]);
            out.push(b' ');
            push_number(&mut out, p[1]);
            out.push(b'\n');
        }
    }
    w.write_all(&out)
}
