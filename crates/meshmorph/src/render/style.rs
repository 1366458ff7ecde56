//! How planar meshes look: colours, which edges to draw, which triangles
//! to mark as flipped.

use super::palette::Rgb;

/// Which edges of a planar mesh to draw.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Edges {
    /// Every edge when the triangles are big enough on screen for the
    /// edges not to bury the fill (typical edge about 6 pixels or more, in
    /// every frame of an animation), otherwise only the boundary.
    #[default]
    Auto,
    /// Every edge.
    All,
    /// Only boundary edges (those of exactly one triangle): the outline.
    Boundary,
    /// No edges.
    None,
}

/// Which triangles to draw in the warning colours.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum Flipped {
    /// Those of negative signed area (clockwise in the y-up world).
    #[default]
    NegativeArea,
    /// Those whose orientation disagrees with the sign of the total signed
    /// area: the same as `NegativeArea` for a counter-clockwise mesh, and
    /// right for clockwise ones too.
    AgainstMajority,
    /// Those whose entry is `true` (missing entries are `false`).
    Mask(Vec<bool>),
    /// None.
    None,
}

/// Colours and options of planar mesh pictures ([`svg_frame`](super::svg_frame),
/// [`draw_mesh_2d`](super::draw_mesh_2d), [`write_gif_2d`](super::write_gif_2d)).
#[derive(Clone, Debug, PartialEq)]
pub struct Style2d {
    /// Background colour (white).
    pub background: Rgb,
    /// Fill of correctly oriented triangles (light blue).
    pub fill: Rgb,
    /// Edges of correctly oriented triangles (dark slate).
    pub edge: Rgb,
    /// Fill of flipped triangles (warning red).
    pub flipped_fill: Rgb,
    /// Edges of flipped triangles (dark red).
    pub flipped_edge: Rgb,
    /// Which edges to draw ([`Edges::Auto`]).
    pub edges: Edges,
    /// Stroke width of SVG edges in pixels (0.75); raster edges are 1 pixel.
    pub edge_width: f64,
    /// Which triangles are flipped ([`Flipped::NegativeArea`]).
    pub flipped: Flipped,
}

impl Default for Style2d {
    fn default() -> Self {
        Style2d {
            background: [0xff, 0xff, 0xff],
            fill: [0xc6, 0xdb, 0xf2],
            edge: [0x2b, 0x3a, 0x55],
            flipped_fill: [0xf2, 0x6b, 0x5b],
            flipped_edge: [0x8a, 0x16, 0x10],
            edges: Edges::Auto,
            edge_width: 0.75,
            flipped: Flipped::NegativeArea,
        }
    }
}

/// Edge sets of a triangle list, computed once per connectivity.
#[derive(Clone, Debug, Default)]
pub struct EdgeSets {
    /// Every undirected edge once, smaller index first.
    pub all: Vec<[u32; 2]>,
    /// Edges of exactly one triangle.
    pub boundary: Vec<[u32; 2]>,
}

impl EdgeSets {
    /// The edges of the triangles whose indices are all below `num_vertices`.
    pub fn new(triangles: &[[u32; 3]], num_vertices: usize) -> Self {
        // Bucket the edges by their smaller vertex (a counting sort), then
        // sort each small bucket: linear time, no hashing.
        let mut start = vec![0usize; num_vertices + 1];
        let each = |f: &mut dyn FnMut(u32, u32)| {
            for t in triangles.iter().filter(|t| valid(t, num_vertices)) {
                for k in 0..3 {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    if a != b {
                        f(a.min(b), a.max(b));
                    }
                }
            }
        };
        each(&mut |a, _| start[a as usize + 1] += 1);
        for v in 0..num_vertices {
            start[v + 1] += start[v];
        }
        let mut next = start.clone();
        let mut other = vec![0u32; start[num_vertices]];
        each(&mut |a, b| {
            other[next[a as usize]] = b;
            next[a as usize] += 1;
        });
        let mut sets = EdgeSets::default();
        for a in 0..num_vertices {
            let bucket = &mut other[start[a]..start[a + 1]];
            bucket.sort_unstable();
            let mut i = 0;
            while i < bucket.len() {
                let mut j = i + 1;
                while j < bucket.len() && bucket[j] == bucket[i] {
                    j += 1;
                }
                let e = [a as u32, bucket[i]];
                sets.all.push(e);
                if j - i == 1 {
                    sets.boundary.push(e);
                }
                i = j;
            }
        }
        sets
    }
}

/// All three indices of `t` are below `n`.
#[inline]
pub fn valid(t: &[u32; 3], n: usize) -> bool {
    t.iter().all(|&i| (i as usize) < n)
}

/// Signed area of triangle `t` (0 when an index is out of range).
#[inline]
pub(crate) fn signed_area(p: &[[f64; 2]], t: &[u32; 3]) -> f64 {
    if !valid(t, p.len()) {
        return 0.0;
    }
    crate::linalg::vector::signed_area2(p[t[0] as usize], p[t[1] as usize], p[t[2] as usize])
}

impl Style2d {
    /// Which triangles to mark as flipped in the frame `positions`.
    pub fn flipped_mask(&self, positions: &[[f64; 2]], triangles: &[[u32; 3]]) -> Vec<bool> {
        match &self.flipped {
            Flipped::None => vec![false; triangles.len()],
            Flipped::NegativeArea => triangles
                .iter()
                .map(|t| signed_area(positions, t) < 0.0)
                .collect(),
            Flipped::AgainstMajority => {
                let areas: Vec<f64> = triangles
                    .iter()
                    .map(|t| signed_area(positions, t))
                    .collect();
                let total: f64 = areas.iter().sum();
                let sign = if total < 0.0 { -1.0 } else { 1.0 };
                areas.iter().map(|&a| a * sign < 0.0).collect()
            }
            Flipped::Mask(m) => (0..triangles.len())
                .map(|t| m.get(t).copied().unwrap_or(false))
                .collect(),
        }
    }

    /// Whether every edge is drawn (`true`), only the boundary (`false`),
    /// or none (`None`), for triangles drawn at `scale` pixels per unit,
    /// `smallest_mean_area` being the smallest of the frames' mean triangle
    /// areas ([`mean_area`]), so that an animation does not switch.
    pub(crate) fn resolve_edges(&self, smallest_mean_area: f64, scale: f64) -> Option<bool> {
        match self.edges {
            Edges::All => Some(true),
            Edges::Boundary => Some(false),
            Edges::None => None,
            // Root mean area in pixels: about 0.66 times the edge length of
            // an equilateral triangle; 4 pixels is an edge of 6.
            Edges::Auto => Some(smallest_mean_area.sqrt() * scale >= 4.0),
        }
    }
}

/// The mean absolute area of the triangles of one frame (those whose area
/// is a finite number; 0 without any).
pub fn mean_area(positions: &[[f64; 2]], triangles: &[[u32; 3]]) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for t in triangles {
        let a = signed_area(positions, t).abs();
        if a.is_finite() {
            sum += a;
            n += 1;
        }
    }
    if n == 0 {
        0.0
    } else {
        sum / n as f64
    }
}
