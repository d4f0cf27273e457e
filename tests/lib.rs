//! Cross-crate tests that reproduce the paper's figures through the `angletrack` API; the
//! tests are the `[[test]]` targets of this package (`paper.rs`, `noise.rs`).
//!
//! The Rust examples of the README and of the user guide (`docs/guide/`) are this
//! library's doctests: each page below is the documentation of an empty module, so that
//! `cargo test --workspace` compiles and runs every ```rust block of it.

/// The repository's README.
#[doc = include_str!("../README.md")]
mod readme {}

/// `docs/guide/firmware.md`.
#[doc = include_str!("../docs/guide/firmware.md")]
mod guide_firmware {}

/// `docs/guide/resolvers.md`.
#[doc = include_str!("../docs/guide/resolvers.md")]
mod guide_resolvers {}

/// `docs/guide/calibration.md`.
#[doc = include_str!("../docs/guide/calibration.md")]
mod guide_calibration {}

/// `docs/guide/diagnostics.md`.
#[doc = include_str!("../docs/guide/diagnostics.md")]
mod guide_diagnostics {}
