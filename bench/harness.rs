// The pieces the standalone timing harnesses (bench/batch, bench/unseen) share, included by
// both with `include!`.

/// Hands a result to `black_box`: by value (the default; the copy reads the returned value),
/// or by reference with the including crate's `by-ref` feature (`BY_REF=1`). The single calls'
/// times depend on it (see bench/README.md). A macro, so that the value is not moved into a
/// function first (which changed the single calls' times again).
macro_rules! consume {
    ($e:expr) => {{
        #[cfg(not(feature = "by-ref"))]
        black_box($e);
        #[cfg(feature = "by-ref")]
        black_box(&$e);
    }};
}

/// The median of `v`.
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// Seeded uniform numbers in [−1, 1) (a 64-bit linear congruential generator's top 53 bits),
/// the same sequence on every run.
fn uniform() -> impl FnMut() -> f64 {
    let mut s = 0x1234_5678u64;
    move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}
