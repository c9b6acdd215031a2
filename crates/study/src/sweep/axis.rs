//! The swept key as a figure's axis, in words and display units.

/// The swept key as a figure's axis: its path in words, in the unit engineers quote, and
/// the factor from the key's unit to it. Angles (`_rad`) are shown in degrees, as the study
/// files' comments and docs speak of them; a list index counts from 1.
///
/// ```
/// use navkf_study::sweep::axis;
/// let (words, factor) = axis("truth.initial_tilt.azimuth_rad");
/// assert_eq!(words, "truth: initial tilt: azimuth (deg)");
/// assert!((factor - 57.29577951308232).abs() < 1e-12);
/// assert_eq!(axis("trajectory.segment[1].to").0, "trajectory: segment 2: to");
/// assert_eq!(axis("noise.gps_m"), ("noise: gps (m)".to_string(), 1.0));
/// ```
pub fn axis(key: &str) -> (String, f64) {
    const UNITS: [(&str, &str, f64); 7] = [
        ("_rad", "deg", 180.0 / std::f64::consts::PI),
        ("_deg", "deg", 1.0),
        ("_m_s", "m/s", 1.0),
        ("_hz", "Hz", 1.0),
        ("_m", "m", 1.0),
        ("_s", "s", 1.0),
        ("_psd", "PSD, SI", 1.0),
    ];
    let mut parts: Vec<String> = Vec::new();
    for comp in key.split('.') {
        let (name, indices) = match comp.split_once('[') {
            Some((n, rest)) => (n, Some(rest)),
            None => (comp, None),
        };
        parts.push(name.replace('_', " "));
        for index in indices.into_iter().flat_map(|r| r.split('[')) {
            let n = index
                .trim_end_matches(']')
                .parse::<usize>()
                .map_or(0, |n| n + 1);
            if let Some(last) = parts.last_mut() {
                *last = format!("{last} {n}");
            }
        }
    }
    let leaf = key.rsplit('.').next().unwrap_or(key);
    let (unit, factor) = UNITS
        .iter()
        .find(|(suffix, _, _)| leaf.ends_with(suffix))
        .map_or((None, 1.0), |(suffix, unit, factor)| {
            if let Some(last) = parts.last_mut() {
                let words = suffix.trim_start_matches('_').replace('_', " ");
                *last = last.trim_end_matches(&format!(" {words}")).to_string();
            }
            (Some(*unit), *factor)
        });
    let words = parts.join(": ");
    match unit {
        Some(u) => (format!("{words} ({u})"), factor),
        None => (words, factor),
    }
}
