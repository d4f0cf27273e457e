//! Cross-crate tests that reproduce the paper's figures through the `angletrack` API; the
//! tests are the `[[test]]` targets of this package (`paper.rs`, `noise.rs`).
