//! Refusing sizes the machine cannot hold, before allocating them.
//!
//! A duration of 1e9 s or an input rate of 1 MHz is a valid number, and an allocation
//! that large aborts the process instead of returning an error. The builders that allocate
//! in proportion to a setting (the trajectory's position grid, the simulator's recorded
//! inputs and one run's truth) ask [`check`] first, which refuses more than the machine's
//! memory with the amount needed and the setting to change.

use crate::error::DynamicsError;

/// Ceiling where the machine's memory cannot be read (no `/proc/meminfo`): 1 TiB.
const UNKNOWN_MEMORY_BYTES: f64 = (1u64 << 40) as f64;

/// The machine's memory, bytes (`MemTotal` on Linux).
pub fn total_bytes() -> f64 {
    std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find_map(|l| l.strip_prefix("MemTotal:"))
                .and_then(|rest| {
                    rest.trim()
                        .trim_end_matches("kB")
                        .trim()
                        .parse::<f64>()
                        .ok()
                })
        })
        .map_or(UNKNOWN_MEMORY_BYTES, |kib| kib * 1024.0)
}

/// Bytes in a readable unit.
pub fn human(bytes: f64) -> String {
    let units = ["B", "KB", "MB", "GB", "TB", "PB", "EB"];
    let mut v = bytes;
    let mut u = 0;
    while v >= 1000.0 && u + 1 < units.len() {
        v /= 1000.0;
        u += 1;
    }
    format!("{v:.3} {}", units[u])
}

/// Refuses `count` items of `item_bytes` each (`what`, e.g. "the trajectory's position
/// grid") when they exceed the machine's memory; the error names `key`, the setting that
/// sets the size.
pub fn check(key: &str, what: &str, count: f64, item_bytes: usize) -> Result<(), DynamicsError> {
    let needed = count * item_bytes as f64;
    let total = total_bytes();
    if needed.is_finite() && needed <= total {
        return Ok(());
    }
    Err(DynamicsError::Config {
        key: key.to_owned(),
        message: format!(
            "{what} would need {} of memory ({count:.3e} values), more than this machine's {}: \
             expected a smaller size",
            human(needed),
            human(total)
        ),
    })
}
