//! Pictures of meshes for people to look at: SVG and PNG stills, GIF
//! animations.
//!
//! Everything takes plain data, positions `&[[f64; 2]]` or `&[[f64; 3]]`
//! and triangles `&[[u32; 3]]`, and never fails on odd geometry:
//! triangles with an index out of range or a non-finite coordinate are
//! skipped, zero-area ones cover no pixels, huge coordinates are clipped.
//!
//! **Planar meshes** (shape interpolation): a [`View2d`] fitted once over
//! every frame maps the plane to pixels; [`Style2d`] says how the mesh
//! looks (light fill, dark edges, flipped triangles in a warning colour).
//! [`svg_frame`] makes a standalone SVG, [`draw_mesh_2d`] draws into a
//! [`Canvas`], and [`write_gif_2d`] writes a whole animation.
//!
//! **Meshes in space** (deformation transfer): a [`Camera3d`] (orthographic,
//! fitted to a set of meshes) and [`draw_mesh_3d`] (z-buffered, flat shaded
//! in a [`Ramp`] of palette shades, both sides lit) draw one mesh into a
//! rectangle of a canvas; [`render_grid_3d`] lays out rows of poses side by
//! side, each row with its own camera. A value per triangle (a distance)
//! is shown by [`draw_mesh_3d_coloured`] in the steps of [`Ramp::SCALE`],
//! explained by a [`Legend`] drawn below the picture ([`with_legend`]).
//!
//! **Pictures morphed** (sprites and photos): [`PictureMorph`] draws a
//! frame of two pictures carried by compatible meshes, textured, in full
//! colour; [`PictureFrames`] sets up a whole morph of one picture into
//! another (drawings, meshes, interpolator, frames); [`write_picture_png`], [`write_apng`], [`write_picture_gif`]
//! and [`sprite_sheet`] write such frames.
//!
//! **Files**: [`write_png`] for a canvas, [`write_gif`] for any sequence of
//! canvases, [`write_gif_grid`] for animated grids of meshes in space.
//!
//! Raster pictures are made of indices into one fixed 256-colour
//! [`Palette`] (layout in [`slot`] and [`Ramp`]), so GIF frames need no
//! colour quantisation and encode fast. The rasteriser samples pixel
//! centres with an exact fill rule: a tessellation is drawn with no gaps
//! between triangles and no pixel drawn twice. Grids of meshes in space are
//! anti-aliased by supersampling ([`GridOptions::supersample`]): drawn larger,
//! averaged in linear light and matched to the nearest palette colour.
//!
//! ```no_run
//! use meshmorph::render::{svg_frame, write_gif_2d, GifOptions, Style2d, View2d};
//! # fn frames() -> (Vec<Vec<[f64; 2]>>, Vec<[u32; 3]>) { unimplemented!() }
//! let (frames, triangles) = frames();
//! let style = Style2d::default();
//! write_gif_2d("morph.gif".as_ref(), &frames, &triangles, &GifOptions::default(), &style)?;
//! let view = View2d::fitting(frames.iter().map(Vec::as_slice), 640, None, 16);
//! std::fs::write("first.svg", svg_frame(&frames[0], &triangles, &view, &style)).unwrap();
//! # Ok::<(), meshmorph::Error>(())
//! ```

#[doc(hidden)]
pub mod canvas;
#[doc(hidden)]
pub mod font;
#[doc(hidden)]
pub mod gif;
#[doc(hidden)]
pub mod grid;
#[doc(hidden)]
pub mod legend;
#[doc(hidden)]
pub mod mesh2d;
#[doc(hidden)]
pub mod palette;
#[doc(hidden)]
pub mod picture_files;
#[doc(hidden)]
pub mod picture_frames;
#[doc(hidden)]
pub mod png;
#[doc(hidden)]
pub mod raster;
#[doc(hidden)]
pub mod resample;
#[doc(hidden)]
pub mod shade3d;
#[doc(hidden)]
pub mod style;
#[doc(hidden)]
pub mod svg;
#[doc(hidden)]
pub mod texture;
#[doc(hidden)]
pub mod textured;
#[doc(hidden)]
pub mod view;

pub use self::canvas::Canvas;
pub use self::gif::{
    write_gif, write_gif_2d, write_gif_2d_frames, write_gif_3d_frames, write_gif_grid, GifOptions,
};
pub use self::grid::{render_grid_3d, GridLayout, GridOptions, GridRow};
pub use self::legend::{with_legend, Legend};
pub use self::mesh2d::draw_mesh_2d;
pub use self::palette::{slot, Palette, Ramp, Rgb};
pub use self::picture_files::{sprite_sheet, write_apng, write_picture_gif, write_picture_png};
pub use self::picture_frames::{
    dissolve_blend, frame_times, PictureFrames, PictureMorphOptions, MAX_FRAME_SIDE,
    MAX_TRACE_TOLERANCE,
};
pub use self::png::write_png;
pub use self::shade3d::{draw_mesh_3d, draw_mesh_3d_coloured, Camera3d, Style3d};
pub use self::style::{Edges, Flipped, Style2d};
pub use self::svg::svg_frame;
pub use self::textured::PictureMorph;
pub use self::view::View2d;

/// A rectangle of pixels: columns `x..x + width`, rows `y..y + height`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Rect {
    /// Left column.
    pub x: u32,
    /// Top row.
    pub y: u32,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}
