//! Meshes in space: an orthographic [`Camera3d`] and z-buffered, flat
//! shaded drawing ([`draw_mesh_3d`]).

use super::canvas::Canvas;
use super::palette::Ramp;
use super::raster;
use super::Rect;
use crate::linalg::vector::{cross, dot, norm, scale, sub};

/// An orthographic camera: the direction it looks in, which way is up on
/// screen, and the region of space it shows.
///
/// `right`, `up` and `forward` are orthonormal with `right = forward × up`;
/// a point `p` appears at `dot(p - center, right)` to the right of the
/// picture's centre and `dot(p - center, up)` above it, and is hidden by
/// points of smaller `dot(p - center, forward)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera3d {
    /// Screen x axis in world coordinates.
    pub right: [f64; 3],
    /// Screen y axis (up) in world coordinates.
    pub up: [f64; 3],
    /// The viewing direction, into the screen.
    pub forward: [f64; 3],
    /// The world point drawn at the centre of the viewport.
    pub center: [f64; 3],
    /// Half the width and height of the shown region along `right` and
    /// `up`, in world units; the region is scaled to fit the viewport
    /// keeping its aspect ratio.
    pub half_size: [f64; 2],
}

impl Camera3d {
    /// A camera looking along `direction` with `up` (projected to be
    /// perpendicular to it) pointing up on screen, showing the cube of
    /// half-size 1 around the origin. Zero or parallel vectors are replaced
    /// by sensible ones: looking along -z, then y up (or z up when looking
    /// along y).
    pub fn looking(direction: [f64; 3], up: [f64; 3]) -> Self {
        let forward = normalized(direction).unwrap_or([0.0, 0.0, -1.0]);
        let perpendicular = |u: [f64; 3]| {
            let u = normalized(u)?;
            let v = sub(u, scale(forward, dot(u, forward)));
            if norm(v) > 1e-6 {
                normalized(v)
            } else {
                None
            }
        };
        let up = perpendicular(up)
            .or_else(|| perpendicular([0.0, 1.0, 0.0]))
            .or_else(|| perpendicular([0.0, 0.0, 1.0]))
            .unwrap_or([1.0, 0.0, 0.0]);
        let right = cross(forward, up);
        Camera3d {
            right,
            up,
            forward,
            center: [0.0; 3],
            half_size: [1.0, 1.0],
        }
    }

    /// The camera at azimuth `azimuth_deg` around the y axis and elevation
    /// `elevation_deg` above the x-z plane, looking at the origin with y up
    /// (the usual convention of OBJ models). `(0, 0)` looks along -z at the
    /// side facing +z; azimuth 90 looks from +x.
    pub fn orbit(azimuth_deg: f64, elevation_deg: f64) -> Self {
        let (a, e) = (azimuth_deg.to_radians(), elevation_deg.to_radians());
        let eye = [a.sin() * e.cos(), e.sin(), a.cos() * e.cos()];
        Self::looking(scale(eye, -1.0), [0.0, 1.0, 0.0])
    }

    /// This camera's direction with `center` and `half_size` fitted to the
    /// projections of all points of all `meshes` (non-finite points are
    /// ignored; with none, the camera is returned unchanged).
    pub fn fitted<'a>(mut self, meshes: impl IntoIterator<Item = &'a [[f64; 3]]>) -> Self {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in meshes.into_iter().flatten() {
            if p.iter().all(|x| x.is_finite()) {
                let q = [dot(*p, self.right), dot(*p, self.up), dot(*p, self.forward)];
                for k in 0..3 {
                    lo[k] = lo[k].min(q[k]);
                    hi[k] = hi[k].max(q[k]);
                }
            }
        }
        if lo[0] > hi[0] {
            return self;
        }
        let mid: [f64; 3] = std::array::from_fn(|k| lo[k] / 2.0 + hi[k] / 2.0);
        self.center = [0, 1, 2]
            .map(|k| mid[0] * self.right[k] + mid[1] * self.up[k] + mid[2] * self.forward[k]);
        let mut half = [hi[0] / 2.0 - lo[0] / 2.0, hi[1] / 2.0 - lo[1] / 2.0];
        let biggest = half[0].max(half[1]);
        for h in &mut half {
            // A flat or point-like set still gets a region of some size.
            if h.is_nan() || *h <= biggest * 1e-6 {
                *h = if biggest > 0.0 { biggest * 1e-6 } else { 1.0 };
            }
        }
        self.half_size = half;
        self
    }

    /// Width over height of the shown region.
    pub fn aspect(&self) -> f64 {
        self.half_size[0] / self.half_size[1]
    }

    /// Pixels per world unit when the region fills `viewport`.
    pub fn pixels_per_unit(&self, viewport: Rect) -> f64 {
        (f64::from(viewport.width) / (2.0 * self.half_size[0]))
            .min(f64::from(viewport.height) / (2.0 * self.half_size[1]))
    }

    /// Pixel coordinates of `p` in `viewport` and its depth (world units
    /// along `forward` from the centre: smaller is nearer).
    #[inline]
    pub fn project(&self, p: [f64; 3], viewport: Rect) -> [f64; 3] {
        self.projector(viewport).apply(p)
    }

    fn projector(&self, viewport: Rect) -> Projector {
        let s = self.pixels_per_unit(viewport);
        Projector {
            right: scale(self.right, s),
            down: scale(self.up, -s),
            forward: self.forward,
            center: self.center,
            origin: [
                f64::from(viewport.x) + f64::from(viewport.width) / 2.0,
                f64::from(viewport.y) + f64::from(viewport.height) / 2.0,
            ],
        }
    }
}

struct Projector {
    right: [f64; 3],
    down: [f64; 3],
    forward: [f64; 3],
    center: [f64; 3],
    origin: [f64; 2],
}

impl Projector {
    #[inline]
    fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        let d = sub(p, self.center);
        [
            self.origin[0] + dot(d, self.right),
            self.origin[1] + dot(d, self.down),
            dot(d, self.forward),
        ]
    }
}

/// Triangles meeting at a larger angle than this (60°, as its cosine) are
/// shaded apart: a crease.
const CREASE_COS: f64 = 0.5;

/// The unit normal at each corner of each triangle: the area-weighted mean
/// of the normals of the triangles around the corner's vertex that meet
/// this triangle at less than 60°. Smooth surfaces shade smoothly; creases
/// (a cube's edges) stay sharp. Zero for a degenerate triangle.
fn corner_normals(positions: &[[f64; 3]], triangles: &[[u32; 3]]) -> Vec<[[f64; 3]; 3]> {
    let area_normals: Vec<[f64; 3]> = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            cross(sub(b, a), sub(c, a))
        })
        .collect();
    let units: Vec<Option<[f64; 3]>> = area_normals.iter().map(|&n| normalized(n)).collect();
    // Triangles around each vertex, as offsets into one list.
    let mut start = vec![0usize; positions.len() + 1];
    for t in triangles {
        for &v in t {
            start[v as usize + 1] += 1;
        }
    }
    for v in 0..positions.len() {
        start[v + 1] += start[v];
    }
    let mut next = start.clone();
    let mut around = vec![0u32; start[positions.len()]];
    for (k, t) in triangles.iter().enumerate() {
        for &v in t {
            around[next[v as usize]] = k as u32;
            next[v as usize] += 1;
        }
    }
    triangles
        .iter()
        .zip(&units)
        .map(|(t, own)| {
            t.map(|v| {
                let Some(own) = own else {
                    return [0.0; 3];
                };
                let mut sum = [0.0; 3];
                for &k in &around[start[v as usize]..start[v as usize + 1]] {
                    let k = k as usize;
                    // Either orientation: both sides are lit the same.
                    let Some(u) = units[k] else { continue };
                    let d = dot(u, *own);
                    if d.abs() >= CREASE_COS {
                        let n = area_normals[k];
                        sum = [0, 1, 2].map(|c| sum[c] + d.signum() * n[c]);
                    }
                }
                normalized(sum).unwrap_or(*own)
            })
        })
        .collect()
}

/// The thresholds of a 4 × 4 ordered (Bayer) dither, in `(0, 1)`: pixel
/// `(x, y)` takes `BAYER[y % 4][x % 4]`.
const BAYER: [[f64; 4]; 4] = {
    const M: [[u8; 4]; 4] = [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];
    let mut t = [[0.0; 4]; 4];
    let mut y = 0;
    while y < 4 {
        let mut x = 0;
        while x < 4 {
            t[y][x] = (M[y][x] as f64 + 0.5) / 16.0;
            x += 1;
        }
        y += 1;
    }
    t
};

fn normalized(v: [f64; 3]) -> Option<[f64; 3]> {
    let n = norm(v);
    (n > 0.0 && n.is_finite()).then(|| scale(v, 1.0 / n))
}

/// How meshes in space look.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Style3d {
    /// The shades of the surface ([`Ramp::BLUE`]).
    pub ramp: Ramp,
    /// The palette index of edges drawn over the surface, `None` for no
    /// edges (the default); see [`Style3d::with_edges`].
    pub edges: Option<u8>,
    /// Direction towards the light in camera coordinates (right, up,
    /// towards the viewer): from the upper left, in front.
    pub light: [f64; 3],
    /// Brightness of surfaces facing away from the light, in `[0, 1]`.
    pub ambient: f64,
    /// The side of the dither's cells in pixels (1). A picture drawn `n`
    /// times larger and then reduced dithers in cells of `n`, so that the
    /// samples of one pixel of the result agree inside a triangle (the
    /// reduction keeps them exactly, and the result compresses well).
    pub dither_px: u32,
}

impl Default for Style3d {
    fn default() -> Self {
        Style3d {
            ramp: Ramp::BLUE,
            edges: None,
            light: [-0.45, 0.6, 0.65],
            ambient: 0.12,
            dither_px: 1,
        }
    }
}

impl Style3d {
    /// The default style with the shades of `ramp`.
    pub fn with_ramp(ramp: Ramp) -> Self {
        Style3d {
            ramp,
            ..Self::default()
        }
    }

    /// This style with edges in a dark shade of its ramp (darker than any
    /// lit surface).
    pub fn with_edges(self) -> Self {
        Style3d {
            edges: Some(self.ramp.index(0.06)),
            ..self
        }
    }
}

/// Draws a mesh in space into `viewport` of `canvas` through `camera`:
/// hidden surfaces removed with a depth buffer (of the viewport, cleared
/// on each call), smooth shaded (Gouraud: Lambert's law at the vertices from
/// area-weighted vertex normals, interpolated across each triangle) and
/// dithered (4 × 4 ordered dither) into the shades of `style.ramp`. Both
/// sides are lit the same, so open meshes look right.
///
/// Nothing is drawn outside `viewport` (clipped to the canvas). Triangles
/// with an index out of range or a non-finite coordinate are skipped.
pub fn draw_mesh_3d(
    canvas: &mut Canvas,
    positions: &[[f64; 3]],
    triangles: &[[u32; 3]],
    camera: &Camera3d,
    viewport: Rect,
    style: &Style3d,
) {
    draw_mesh_3d_coloured(canvas, positions, triangles, camera, viewport, style, &[]);
}

/// [`draw_mesh_3d`] with triangle `t` shaded in `ramps[t]` instead of
/// `style.ramp` (those past the end of `ramps` in `style.ramp`): a value
/// per triangle shown in colour ([`Ramp::on_scale`]) with the surface
/// still shaded.
pub fn draw_mesh_3d_coloured(
    canvas: &mut Canvas,
    positions: &[[f64; 3]],
    triangles: &[[u32; 3]],
    camera: &Camera3d,
    viewport: Rect,
    style: &Style3d,
    ramps: &[Ramp],
) {
    // The dither's thresholds along each of its four kinds of row, for
    // every column (no division per pixel).
    let cell = style.dither_px.max(1) as usize;
    let dither: Vec<Vec<f64>> = BAYER
        .iter()
        .map(|row| {
            (0..canvas.width as usize)
                .map(|x| row[(x / cell) % 4])
                .collect()
        })
        .collect();
    let clip = canvas.clip(viewport);
    let vx0 = viewport.x.min(canvas.width) as usize;
    let vy0 = viewport.y.min(canvas.height) as usize;
    let vw = (viewport.x.saturating_add(viewport.width)).min(canvas.width) as usize - vx0;
    let vh = (viewport.y.saturating_add(viewport.height)).min(canvas.height) as usize - vy0;
    if vw == 0 || vh == 0 {
        return;
    }
    let mut depth = vec![f32::INFINITY; vw * vh];
    let proj = camera.projector(viewport);
    let q: Vec<[f64; 3]> = positions.iter().map(|&p| proj.apply(p)).collect();
    let fixed: Vec<[i64; 2]> = q.iter().map(|p| raster::snap_point([p[0], p[1]])).collect();
    let light = {
        let l = style.light;
        let d = [0, 1, 2]
            .map(|k| l[0] * camera.right[k] + l[1] * camera.up[k] - l[2] * camera.forward[k]);
        normalized(d).unwrap_or(scale(camera.forward, -1.0))
    };
    let ambient = if style.ambient.is_finite() {
        style.ambient.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let w = canvas.width as usize;
    let n = positions.len();
    // Gouraud shading: Lambert's law at each vertex from its area-weighted
    // normal, interpolated over the triangle, then an ordered dither between
    // the ramp's two nearest shades (no bands, even with 32 shades).
    let finite: Vec<[f64; 3]> = positions
        .iter()
        .map(|p| {
            if p.iter().all(|x| x.is_finite()) {
                *p
            } else {
                [0.0; 3]
            }
        })
        .collect();
    let (valid, valid_ramps): (Vec<[u32; 3]>, Vec<Ramp>) = triangles
        .iter()
        .enumerate()
        .filter(|(_, t)| super::style::valid(t, n))
        .map(|(k, t)| (*t, ramps.get(k).copied().unwrap_or(style.ramp)))
        .unzip();
    let shade: Vec<[f64; 3]> = corner_normals(&finite, &valid)
        .iter()
        .map(|c| c.map(|nn| ambient + (1.0 - ambient) * dot(nn, light).abs()))
        .collect();
    // Nearest first: the depth test then turns away most hidden pixels
    // before they are shaded, with a branch that mostly goes one way. (Only
    // exact ties of depth depend on the order: the first drawn keeps them.)
    let mut nearest_first: Vec<(f32, u32)> = valid
        .iter()
        .enumerate()
        .map(|(k, t)| {
            let z = t
                .iter()
                .map(|&i| q[i as usize][2])
                .fold(f64::INFINITY, f64::min);
            (z as f32, k as u32)
        })
        .collect();
    nearest_first.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    for (t, corner_shade, ramp) in nearest_first.iter().map(|&(_, k)| {
        let k = k as usize;
        (&valid[k], &shade[k], valid_ramps[k])
    }) {
        let levels = f64::from(ramp.len.max(1) - 1);
        let top = u32::from(ramp.len.max(1) - 1);
        let first = ramp.first;
        let [a, b, c] = t.map(|i| i as usize);
        let normal = cross(
            sub(positions[b], positions[a]),
            sub(positions[c], positions[a]),
        );
        // A triangle without a normal keeps the flat ambient shade.
        let flat = normalized(normal).is_none();
        let (pa, pb, pc) = (q[a], q[b], q[c]);
        // Depth and shade as planes over the screen, clamped to the corners'
        // range (slivers seen edge-on have wild gradients).
        let det = (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pc[0] - pa[0]) * (pb[1] - pa[1]);
        if det == 0.0 || !det.is_finite() {
            continue;
        }
        let plane = |va: f64, vb: f64, vc: f64| {
            let gx = ((vb - va) * (pc[1] - pa[1]) - (vc - va) * (pb[1] - pa[1])) / det;
            let gy = ((vc - va) * (pb[0] - pa[0]) - (vb - va) * (pc[0] - pa[0])) / det;
            (gx, gy, va.min(vb).min(vc), va.max(vb).max(vc))
        };
        let (gx, gy, zmin, zmax) = plane(pa[2], pb[2], pc[2]);
        let (zmin, zmax) = (zmin as f32, zmax as f32);
        let [sa, sb, sc] = if flat { [ambient; 3] } else { *corner_shade };
        let (hx, hy, smin, smax) = plane(sa, sb, sc);
        let gx32 = gx as f32;
        let pixels = &mut canvas.pixels;
        let corners = [[pa[0], pa[1]], [pb[0], pb[1]], [pc[0], pc[1]]];
        raster::fill_snapped(
            [fixed[a], fixed[b], fixed[c]],
            corners,
            &clip,
            |y, x0, x1| {
                let (dx, dy) = (x0 as f64 + 0.5 - pa[0], y as f64 + 0.5 - pa[1]);
                let row_z = (pa[2] + gx * dx + gy * dy) as f32;
                let row_s = sa + hx * dx + hy * dy;
                let zrow = &mut depth[(y - vy0) * vw..(y - vy0 + 1) * vw];
                let thresholds = &dither[(y / cell) % 4];
                let prow = &mut pixels[y * w..(y + 1) * w];
                for (i, x) in (x0..x1).enumerate() {
                    let z = (row_z + gx32 * i as f32).clamp(zmin, zmax);
                    if z < zrow[x - vx0] {
                        zrow[x - vx0] = z;
                        let s = (row_s + hx * i as f64).clamp(smin, smax).clamp(0.0, 1.0);
                        // Not negative: truncating is `floor`, in one
                        // instruction where `floor` may be a library call.
                        let level = ((s * levels + thresholds[x]) as u32).min(top);
                        prow[x] = first.saturating_add(level as u8);
                    }
                }
            },
        );
    }
    if let Some(edge) = style.edges {
        // Edges win against the surface they lie on, within a couple of
        // pixels' worth of depth.
        let eps = (2.0 / camera.pixels_per_unit(viewport)) as f32;
        for t in triangles.iter().filter(|t| super::style::valid(t, n)) {
            for k in 0..3 {
                let (a, b) = (q[t[k] as usize], q[t[(k + 1) % 3] as usize]);
                let pixels = &mut canvas.pixels;
                raster::draw_line([a[0], a[1]], [b[0], b[1]], &clip, |x, y, s| {
                    let z = (a[2] + f64::from(s) * (b[2] - a[2])) as f32;
                    if z <= depth[(y - vy0) * vw + x - vx0] + eps {
                        pixels[y * w + x] = edge;
                    }
                });
            }
        }
    }
}
