//! Numbers as CSV text: the shortest decimal that reads back as the same `f64`, in
//! scientific notation where plain digits would be long (`1e-300`, not 302 characters).
//! Used by every CSV writer ([`super::files`], [`super::ensemble`]).
//!
//! Formatting is a large part of writing a profile CSV (about 390 000 numbers at 10⁴ cells
//! and three times); the `zmij` crate does it about three times faster than `std`'s
//! `Display` and never writes hundreds of digits for an extreme value.

/// Appends the shortest round-trip decimal of `x` (e.g. `0.95`, `1.0`, `2.5e-7`, `1e+300`).
/// Non-finite values are written as `NaN`, `inf` and `-inf` (the writers refuse them before
/// formatting; see [`super::finite`]).
///
/// ```
/// use celltissue::output::number::push_f64;
/// let mut s = String::new();
/// for x in [0.95, 1.0, 2.5e-7, 1e-300] {
///     push_f64(&mut s, x);
///     s.push(',');
/// }
/// assert_eq!(s, "0.95,1.0,2.5e-7,1e-300,");
/// assert_eq!("1e-300".parse::<f64>(), Ok(1e-300)); // reads back exactly
/// ```
pub fn push_f64(out: &mut String, x: f64) {
    out.push_str(zmij::Buffer::new().format(x));
}

#[cfg(test)]
mod tests {
    use super::push_f64;

    #[test]
    fn every_number_reads_back_as_the_same_bits() {
        let mut s = String::new();
        let values = [
            0.0,
            -0.0,
            1.0,
            0.1 + 0.2,
            1e-300,
            5e-324,
            f64::MAX,
            -123_456_789.125,
            0.949_871_234_567_89,
        ];
        for x in values {
            s.clear();
            push_f64(&mut s, x);
            let back: f64 = s.parse().unwrap();
            assert_eq!(back.to_bits(), x.to_bits(), "{x:e} written as {s}");
            assert!(s.len() <= 24, "{x:e} written as {s}");
        }
    }
}
