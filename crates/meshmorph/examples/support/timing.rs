//! Timing helpers shared by the benchmarks that print tables: medians of repeated
//! runs, and durations as short strings.

use std::hint::black_box;
use std::time::Instant;

/// The program's arguments, without the `--bench` flag `cargo bench` adds.
pub fn args() -> Vec<String> {
    std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect()
}

/// The median of `v`.
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Seconds of each of `runs` calls of `f`.
pub fn samples<T>(runs: usize, mut f: impl FnMut() -> T) -> Vec<f64> {
    (0..runs)
        .map(|_| {
            let t = Instant::now();
            black_box(f());
            t.elapsed().as_secs_f64()
        })
        .collect()
}

/// Median seconds of `runs` calls of `f`.
pub fn time<T>(runs: usize, f: impl FnMut() -> T) -> f64 {
    median(samples(runs, f))
}

/// Seconds as µs, ms or s.
pub fn fmt(s: f64) -> String {
    if s < 1e-3 {
        format!("{:.1} µs", s * 1e6)
    } else if s < 1.0 {
        format!("{:.2} ms", s * 1e3)
    } else {
        format!("{:.2} s", s)
    }
}
