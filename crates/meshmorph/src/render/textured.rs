//! Frames of a picture morph: each frame's mesh filled with the first
//! picture carried to the frame's shape and the second carried back to it,
//! blended.
//!
//! For every pixel centre inside a frame triangle, the triangle's affine
//! map from the frame to each picture's mesh gives where that pixel's
//! colour is in each picture; the two colours are sampled bilinearly (from
//! the mipmap, trilinearly, where the triangle is drawn smaller than it is
//! in the picture) and blended in premultiplied alpha: `(1 - w) A + w B`.
//! The frame's triangles tessellate it with an exact fill rule, so every
//! pixel is drawn once. Around the outline a fringe of `fringe` pixels is
//! drawn with the maps of the triangles along it carried on past the edge,
//! so that the pictures' own soft edges (a sprite's anti-aliased alpha, a
//! photo's border, which fades as the samples leave the picture) are kept:
//! the frame's edges are anti-aliased by the pictures themselves, and when
//! a frame's mesh is a picture's own (the ends) every pixel of that
//! picture within the fringe of its outline comes back exactly. Outside:
//! transparent.
//!
//! Rows are drawn in bands in parallel (rayon), each band taking the
//! triangles that reach it.

use rayon::prelude::*;

use super::raster::{fill_triangle, Clip};
use super::texture::{to_straight, Premultiplied, Texture};
use super::Rect;
use crate::error::{Error, Result};
use crate::io::picture::{Picture, PictureShape};

/// Rows of a band drawn by one task.
const BAND_ROWS: usize = 32;

/// Setup of the frames of a morph between two pictures: their textures,
/// where each mesh vertex lies in each picture, the triangles and the
/// outline.
pub struct PictureMorph<'a> {
    textures: [Texture<'a>; 2],
    sources: [Vec<[f64; 2]>; 2],
    triangles: Vec<[u32; 3]>,
    /// Each boundary loop's edges in order: `(from, to, triangle)`.
    outline: Vec<Vec<(u32, u32, u32)>>,
    width: u32,
    height: u32,
    fringe: f64,
}

/// An affine map of the plane: `p ↦ o + J p`.
#[derive(Clone, Copy)]
struct Affine {
    o: [f64; 2],
    j: [[f64; 2]; 2],
}

impl Affine {
    #[inline]
    fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        [
            self.o[0] + self.j[0][0] * p[0] + self.j[0][1] * p[1],
            self.o[1] + self.j[1][0] * p[0] + self.j[1][1] * p[1],
        ]
    }

    /// The map taking triangle `p` onto `s`, with the log2 of how many
    /// times smaller (in length) `p` is than `s`; `None` for a triangle
    /// `p` of no area.
    fn between(p: [[f64; 2]; 3], s: [[f64; 2]; 3]) -> Option<(Self, f32)> {
        let (e1, e2) = (sub(p[1], p[0]), sub(p[2], p[0]));
        let det = e1[0] * e2[1] - e1[1] * e2[0];
        if det.is_nan() || det.abs() <= 1e-12 {
            return None;
        }
        let (f1, f2) = (sub(s[1], s[0]), sub(s[2], s[0]));
        // J = [f1 f2] [e1 e2]^-1.
        let inv = [[e2[1] / det, -e2[0] / det], [-e1[1] / det, e1[0] / det]];
        let j = [
            [
                f1[0] * inv[0][0] + f2[0] * inv[1][0],
                f1[0] * inv[0][1] + f2[0] * inv[1][1],
            ],
            [
                f1[1] * inv[0][0] + f2[1] * inv[1][0],
                f1[1] * inv[0][1] + f2[1] * inv[1][1],
            ],
        ];
        let o = [
            s[0][0] - j[0][0] * p[0][0] - j[0][1] * p[0][1],
            s[0][1] - j[1][0] * p[0][0] - j[1][1] * p[0][1],
        ];
        let ratio = ((f1[0] * f2[1] - f1[1] * f2[0]) / det).abs();
        // Mipmapped only where the triangle is drawn more than a quarter
        // smaller than in the picture: at the ends (ratio 1) the picture
        // itself.
        let lod = 0.5 * ratio.log2();
        let lod = if lod > 0.4 { lod as f32 } else { 0.0 };
        Some((Self { o, j }, lod))
    }
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

/// A triangle to fill in a frame: its corners in frame pixels, and the
/// maps into each picture with their mipmap levels.
#[derive(Clone, Copy)]
struct Piece {
    corners: [[f64; 2]; 3],
    rows: [f64; 2],
    maps: [(Affine, f32); 2],
}

impl<'a> PictureMorph<'a> {
    /// The setup for frames of `width × height` pixels between pictures
    /// `a` and `b`: `sources[k]` holds each mesh vertex's place in picture
    /// `k` (pixels; two pictures, two lists), `triangles` the meshes' triangles, `loops` the
    /// boundary loops (as [`CompatibleSet::loops`](crate::outline::CompatibleSet::loops)),
    /// `fringe` how far past the outline the pictures are drawn, in frame
    /// pixels (the simplification's tolerance and one and a half pixels
    /// for the pictures' soft edges is right), `shape` whether they are
    /// sprites (transparent past their edges) or photos (whole rectangles:
    /// their edge pixels go on past their edges, so that a frame's edge is
    /// as opaque as its inside). Makes the mipmaps.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] for sources of other lengths, a triangle
    /// or loop index out of range, a loop edge in no triangle, or a frame
    /// size of 0.
    pub fn new(
        [a, b]: [&'a Picture; 2],
        sources: &[Vec<[f64; 2]>],
        triangles: &[[u32; 3]],
        loops: &[Vec<u32>],
        (width, height): (u32, u32),
        fringe: f64,
        shape: PictureShape,
    ) -> Result<Self> {
        if sources.len() != 2 {
            return Err(Error::InvalidArgument(format!(
                "the meshes' places in {} pictures, not two",
                sources.len()
            )));
        }
        let n = sources[0].len();
        if sources[1].len() != n {
            return Err(Error::InvalidArgument(format!(
                "the meshes' places in the two pictures have {} and {} vertices",
                n,
                sources[1].len()
            )));
        }
        if width == 0 || height == 0 {
            return Err(Error::InvalidArgument(format!(
                "frames of {width} × {height} pixels"
            )));
        }
        if let Some(t) = triangles
            .iter()
            .position(|t| t.iter().any(|&v| v as usize >= n))
        {
            return Err(Error::InvalidArgument(format!(
                "triangle {t} names a vertex past the {n} vertices"
            )));
        }
        let mut of_edge = std::collections::HashMap::new();
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (u, v) = (tri[k], tri[(k + 1) % 3]);
                of_edge.insert((u.min(v), u.max(v)), t as u32);
            }
        }
        let mut outline = Vec::with_capacity(loops.len());
        for (l, lp) in loops.iter().enumerate() {
            let mut edges = Vec::with_capacity(lp.len());
            for i in 0..lp.len() {
                let (u, v) = (lp[i], lp[(i + 1) % lp.len()]);
                let t = of_edge.get(&(u.min(v), u.max(v))).ok_or_else(|| {
                    Error::InvalidArgument(format!(
                        "edge {u}-{v} of boundary loop {l} is in no triangle"
                    ))
                })?;
                edges.push((u, v, *t));
            }
            outline.push(edges);
        }
        let repeated = shape == PictureShape::Photo;
        let textures = [Texture::new(a, repeated), Texture::new(b, repeated)];
        Ok(Self {
            textures,
            sources: [sources[0].clone(), sources[1].clone()],
            triangles: triangles.to_vec(),
            outline,
            width,
            height,
            fringe,
        })
    }

    /// The frames' width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Draws the frame whose mesh vertices are at `positions` (frame
    /// pixels), the pictures blended by `blend` (0: the first alone, 1:
    /// the second alone), into `out` (straight RGBA, `4 × width × height`
    /// bytes; every byte written). Never fails: triangles of no area or
    /// with a coordinate that is not finite draw nothing.
    ///
    /// # Panics
    /// When `positions` or `out` have other lengths than the setup's.
    pub fn draw_into(&self, positions: &[[f64; 2]], blend: f64, out: &mut [u8]) {
        assert_eq!(positions.len(), self.sources[0].len(), "vertex count");
        let (w, h) = (self.width as usize, self.height as usize);
        assert_eq!(out.len(), 4 * w * h, "frame bytes");
        let blend = blend.clamp(0.0, 1.0) as f32;
        let piece = |corners: [[f64; 2]; 3], t: usize| -> Option<Piece> {
            let tri = self.triangles[t];
            let frame = tri.map(|v| positions[v as usize]);
            let maps =
                [0, 1].map(|k| Affine::between(frame, tri.map(|v| self.sources[k][v as usize])));
            let [Some(ma), Some(mb)] = maps else {
                return None;
            };
            let ys = corners.map(|c| c[1]);
            Some(Piece {
                corners,
                rows: [ys[0].min(ys[1]).min(ys[2]), ys[0].max(ys[1]).max(ys[2])],
                maps: [ma, mb],
            })
        };
        let inside: Vec<Piece> = (0..self.triangles.len())
            .into_par_iter()
            .filter_map(|t| {
                let corners = self.triangles[t].map(|v| positions[v as usize]);
                piece(corners, t)
            })
            .collect();
        let fringe: Vec<Piece> = self
            .fringe_triangles(positions)
            .into_iter()
            .filter_map(|(corners, t)| piece(corners, t as usize))
            .collect();
        let colour = |p: &Piece, x: usize, y: usize| -> [u8; 4] {
            let c = [x as f64 + 0.5, y as f64 + 0.5];
            let sample = |k: usize| -> Premultiplied {
                let (map, lod) = p.maps[k];
                self.textures[k].sample(map.apply(c), lod)
            };
            let mixed = if blend <= 0.0 {
                sample(0)
            } else if blend >= 1.0 {
                sample(1)
            } else {
                let (mut a, b) = (sample(0), sample(1));
                for i in 0..4 {
                    a[i] += blend * (b[i] - a[i]);
                }
                a
            };
            to_straight(mixed)
        };
        out.par_chunks_mut(4 * w * BAND_ROWS)
            .enumerate()
            .for_each(|(band, rows)| {
                rows.fill(0);
                let y0 = band * BAND_ROWS;
                let band_h = rows.len() / (4 * w);
                let clip = Clip::new(
                    Rect {
                        x: 0,
                        y: y0 as u32,
                        width: w as u32,
                        height: band_h as u32,
                    },
                    w as u32,
                    h as u32,
                );
                let mut drawn = vec![false; w * band_h];
                let reaches = |p: &Piece| {
                    p.rows[1] >= y0 as f64 - 1.0 && p.rows[0] <= (y0 + band_h) as f64 + 1.0
                };
                for (pass, pieces) in [&inside, &fringe].into_iter().enumerate() {
                    for p in pieces.iter().filter(|p| reaches(p)) {
                        fill_triangle(p.corners, &clip, |y, xs, xe| {
                            let row = y - y0;
                            for x in xs..xe {
                                let at = row * w + x;
                                if pass == 1 && drawn[at] {
                                    continue;
                                }
                                drawn[at] = true;
                                rows[4 * at..4 * at + 4].copy_from_slice(&colour(p, x, y));
                            }
                        });
                    }
                }
            });
    }

    /// [`PictureMorph::draw_into`] into a new picture.
    pub fn draw(&self, positions: &[[f64; 2]], blend: f64) -> Picture {
        let mut rgba = vec![0; 4 * self.width as usize * self.height as usize];
        self.draw_into(positions, blend, &mut rgba);
        Picture {
            width: self.width,
            height: self.height,
            rgba,
        }
    }

    /// The fringe past the outline at `positions`: a quadrilateral on each
    /// boundary edge, `fringe` wide, and a wedge at each vertex between
    /// its two edges', as triangles with the mesh triangle whose map they
    /// carry on.
    fn fringe_triangles(&self, positions: &[[f64; 2]]) -> Vec<([[f64; 2]; 3], u32)> {
        let f = self.fringe;
        let mut out = Vec::new();
        if f.is_nan() || f <= 0.0 {
            return out;
        }
        let at = |v: u32| positions[v as usize];
        let add = |p: [f64; 2], d: [f64; 2], s: f64| [p[0] + s * d[0], p[1] + s * d[1]];
        for edges in &self.outline {
            // Each edge's outward unit normal (away from its triangle's
            // third corner), `None` for an edge of no length.
            let normals: Vec<Option<[f64; 2]>> = edges
                .iter()
                .map(|&(u, v, t)| {
                    let d = sub(at(v), at(u));
                    let len = d[0].hypot(d[1]);
                    if len.is_nan() || len <= 1e-12 {
                        return None;
                    }
                    let mut n = [d[1] / len, -d[0] / len];
                    let third = self.triangles[t as usize]
                        .into_iter()
                        .find(|&x| x != u && x != v)
                        .unwrap_or(u);
                    let r = sub(at(third), at(u));
                    if n[0] * r[0] + n[1] * r[1] > 0.0 {
                        n = [-n[0], -n[1]];
                    }
                    Some(n)
                })
                .collect();
            let m = edges.len();
            for i in 0..m {
                let (u, v, t) = edges[i];
                let Some(n) = normals[i] else { continue };
                let (pu, pv) = (at(u), at(v));
                out.push(([pu, pv, add(pv, n, f)], t));
                out.push(([pu, add(pv, n, f), add(pu, n, f)], t));
                // The wedge at `v`, between this edge's normal and the
                // next's, drawn with the next edge's triangle.
                let (_, _, t2) = edges[(i + 1) % m];
                let Some(n2) = normals[(i + 1) % m] else {
                    continue;
                };
                let mid = [n[0] + n2[0], n[1] + n2[1]];
                let len = mid[0].hypot(mid[1]);
                let mid = if len > 1e-6 {
                    let c = (len / 2.0).max(0.25);
                    [mid[0] / len / c, mid[1] / len / c]
                } else {
                    // A hairpin: straight on along the edge.
                    let d = sub(pv, pu);
                    let l = d[0].hypot(d[1]);
                    [d[0] / l, d[1] / l]
                };
                out.push(([pv, add(pv, n, f), add(pv, mid, f)], t2));
                out.push(([pv, add(pv, mid, f), add(pv, n2, f)], t2));
            }
        }
        out
    }
}
