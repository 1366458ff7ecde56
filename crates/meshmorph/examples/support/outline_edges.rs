//! The drawings' benchmarks' measure of a morph's outline edges (one
//! definition for `outline_benchmark` and `outline_stress`).

/// The mean relative deviation of the outline's edge lengths from the
/// straight blend of their lengths in the first and last of `frames`
/// (evenly spaced in time, each a list of loops with the same points),
/// over the frames between them; edges whose blend is at most `eps` are
/// left out. 0 for a rigid turn.
pub fn edges_off_blend(frames: &[Vec<Vec<[f64; 2]>>], eps: f64) -> f64 {
    let n = frames.len();
    let (first, last) = (&frames[0], &frames[n - 1]);
    let (mut deviation, mut count) = (0.0, 0usize);
    for (k, frame) in frames.iter().enumerate().take(n - 1).skip(1) {
        let t = k as f64 / (n - 1) as f64;
        for (l, points) in frame.iter().enumerate() {
            for i in 0..points.len() {
                let j = (i + 1) % points.len();
                let length = |f: &Vec<Vec<[f64; 2]>>| {
                    let (p, q) = (f[l][i], f[l][j]);
                    (q[0] - p[0]).hypot(q[1] - p[1])
                };
                let blend = (1.0 - t) * length(first) + t * length(last);
                if blend > eps {
                    deviation += (length(frame) - blend).abs() / blend;
                    count += 1;
                }
            }
        }
    }
    deviation / count.max(1) as f64
}
