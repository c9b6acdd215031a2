//! Matrices that may hold NaN, through JSON, which has no NaN: a non-finite value is written
//! as `null` and read back as NaN.
//!
//! serde_json writes NaN as `null` by itself, then refuses `null` for an `f64` when reading
//! it back. The example run's truth is NaN for every state the truth model lacks (a filter
//! that models an effect the truth does not carry), so a shard holding it could not be merged.
//! Use as `#[serde(with = "navkf_report::json_nan")]` on a `Vec<Vec<f64>>`.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// Writes each value, `null` where it is not finite.
pub fn serialize<S: Serializer>(rows: &[Vec<f64>], s: S) -> Result<S::Ok, S::Error> {
    let rows: Vec<Vec<Option<f64>>> = rows
        .iter()
        .map(|r| r.iter().map(|v| v.is_finite().then_some(*v)).collect())
        .collect();
    rows.serialize(s)
}

/// Reads each value, NaN where it is `null`.
pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Vec<f64>>, D::Error> {
    let rows: Vec<Vec<Option<f64>>> = Vec::deserialize(d)?;
    Ok(rows
        .into_iter()
        .map(|r| r.into_iter().map(|v| v.unwrap_or(f64::NAN)).collect())
        .collect())
}

#[cfg(test)]
mod tests {
    #[derive(serde::Serialize, serde::Deserialize)]
    struct Rows(#[serde(with = "super")] Vec<Vec<f64>>);

    #[test]
    fn nan_goes_through_json_as_null_and_finite_values_unchanged() {
        let rows = Rows(vec![vec![1.5, f64::NAN], vec![-0.1, 3e-300]]);
        let json = serde_json::to_string(&rows).unwrap();
        assert_eq!(json, "[[1.5,null],[-0.1,3e-300]]");
        let back: Rows = serde_json::from_str(&json).unwrap();
        assert_eq!(back.0[0][0], 1.5);
        assert!(back.0[0][1].is_nan());
        assert_eq!(back.0[1], rows.0[1]);
    }
}
