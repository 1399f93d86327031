//! Small statistics the broad phase, the crosscheck report and the benchmark share.

/// The median of `v` (for an even count, the upper of the two middle values, as v sorted by
/// [`f64::total_cmp`] at index len / 2); `None` for no values.
pub fn median(mut v: Vec<f64>) -> Option<f64> {
    median_of(&mut v)
}

/// [`median`] in place (`v` is reordered).
pub fn median_of(v: &mut [f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let middle = v.len() / 2;
    let (_, m, _) = v.select_nth_unstable_by(middle, f64::total_cmp);
    Some(*m)
}
