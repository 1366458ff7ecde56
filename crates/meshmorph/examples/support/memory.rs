//! What the process holds and has used, read from /proc/self (Linux), for
//! the benchmarks: its resident memory at its peak, and its CPU time.

/// A line of /proc/self/status (`VmRSS:`, `VmHWM:`, ...) in bytes; `None`
/// where the file is not there.
fn status(key: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find_map(|l| l.strip_prefix(key))?;
    let kb: u64 = line.split_whitespace().next()?.parse().ok()?;
    Some(kb * 1024)
}

/// The peak resident memory of this process since the last
/// [`reset_peak`], in bytes.
#[allow(dead_code)]
pub fn peak_memory() -> Option<u64> {
    status("VmHWM:")
}

/// The resident memory of this process now, in bytes.
#[allow(dead_code)]
pub fn resident_memory() -> Option<u64> {
    status("VmRSS:")
}

/// Starts the peak of [`peak_memory`] again from what is in use now
/// (Linux 4.0 and later; elsewhere the peak stays the whole run's).
pub fn reset_peak() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// The CPU seconds this process has used, all its threads, user and
/// system (from /proc/self/stat, in clock ticks of 1/100 s): a measure of
/// work that other programs on the machine do not inflate as they do the
/// time on the clock.
#[allow(dead_code)]
pub fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The fields after the command's name (in parentheses, which may hold
    // spaces): state is the 3rd field, utime the 14th, stime the 15th.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: u64 = fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?;
    Some(ticks as f64 / 100.0)
}
