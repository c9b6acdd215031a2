//! Where a result came from: the command that made it and the machine it ran on, written
//! into every report and results-folder marker so numbers can be traced and compared.

/// This process's command line, for the reports' "Command:" line. Arguments that are not
/// UTF-8 are shown with U+FFFD in place of the bad bytes (`std::env::args` would panic).
pub fn command_line() -> String {
    std::env::args_os()
        .map(|a| a.to_string_lossy().into_owned())
        .collect::<Vec<_>>()
        .join(" ")
}

/// The CPU this process runs on, for the step-cost note: the model name Linux reports and the
/// logical cores the process may use (`unknown CPU` where `/proc/cpuinfo` is not readable).
pub fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, v)| v.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".to_string());
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    format!("{cpu} ({cores} logical cores)")
}
