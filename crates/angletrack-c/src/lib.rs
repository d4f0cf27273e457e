//! The C API of `angletrack-core`: a static library (`libangletrack_c.a`) and its header
//! `include/angletrack.h` (generated from this crate by cbindgen, checked in), for firmware
//! written in C. Built for the host (`cargo build -p angletrack-c --release`), a
//! Cortex-M4F (`--target thumbv7em-none-eabihf`) or a Cortex-M0 (`thumbv6m-none-eabi`).
//!
//! Every struct is plain and sized, so that firmware can place it in static memory. Each
//! observer is a signal chain, the core's standard chain (`Tracker`) assembled by the core
//! from the stages given; the C API only converts. The float chain: `at_gains_f32` (the
//! observer's checked gains, order 2 or 3, with its fault thresholds
//! `at_fault_thresholds_f32`), `at_adc_f32` (the ADC stage, with its stated range of codes),
//! the plain stage settings `at_sensor_calibration_f32`, `at_calibration_settings_f32`,
//! `at_angle_correction_f32` and `at_angle_correction_table_f32`, `at_chain_f32` (the chain)
//! with its per-channel `at_chain_state_f32`, and the estimate `at_estimate_f32` (`chain`).
//! For cores without an FPU, the fixed-point chain: `at_fixed_gains`, the plain
//! `at_adc_counts` and `at_angle_table_fixed`, `at_chain_fixed` with its
//! `at_chain_state_fixed`, and `at_fixed_estimate` (`chain_fixed`). The synchronous
//! demodulator, `at_demodulator_f32` with its `at_demodulator_state_f32`, turns a
//! resolver's windings into the float chain's pairs, taken with their front-end faults
//! (`demodulator`). A front-end check (clipping against the ADC's stated range or its rails
//! measured, a demodulator's faults, a winding open or shorted) that invalidates a sample
//! is coasted through, and its estimate carries `AT_FAULT_FRONT_END`.
//! The structs made by a constructor hold the core's Rust values in private storage, sized
//! at compile time and checked against the Rust types on every target (`slot`); a zeroed
//! state is a fresh one, a zeroed configuration is refused. Each starts with a tag and a
//! layout word (the fingerprint of the build that wrote it: `AT_LAYOUT_VERSION`, the
//! crate's version, the struct's size, the target), so that a struct from another build is
//! refused (`AT_ERR_OTHER_BUILD`), never read.
//!
//! Calls that can fail return an `at_status` (`AT_OK` or an `AT_ERR_*` naming the refused
//! parameter, `at_status_message` its text); the per-sample updates never fail and return
//! an `at_estimate_f32` whose `faults` carry the `AT_FAULT_*` bits. No call panics: NULL
//! pointers give `AT_ERR_NULL_POINTER` (or `AT_FAULT_INVALID_ARGUMENT` from an update),
//! never undefined behaviour.
//!
//! Unsafe code is denied except at the boundary: the `ffi*` modules and `door` (the
//! `extern "C"` functions and their pointers) and `slot` (the Rust values in C memory), each unsafe block with its
//! safety argument. For a bare-metal target the library carries its panic handler (the C
//! program has none); no call reaches it (tests/firmware/c checks that the linked example
//! holds no panic code). On a host, std provides it.
#![no_std]
#![allow(non_camel_case_types)]

#[cfg(not(target_os = "none"))]
extern crate std;

mod adc;
mod calibration;
mod chain;
mod chain_fixed;
mod demodulator;
mod door;
mod faults;
mod ffi;
mod ffi_chain;
mod ffi_chain_fixed;
mod ffi_demodulator;
#[cfg(feature = "count-reference")]
mod firmware_test_reference;
mod gains;
mod mirror;
mod slot;
mod status;
mod table;

// The C API: every module's public items, as the header has them.
pub use {
    adc::*, calibration::*, chain::*, chain_fixed::*, demodulator::*, faults::*, ffi::*,
    ffi_chain::*, ffi_chain_fixed::*, ffi_demodulator::*, gains::*, slot::AT_LAYOUT_VERSION,
    status::*, table::*,
};

/// A bare-metal C program has no panic handler; the library's is never reached (no call
/// panics), and parks the core if it were.
#[cfg(all(target_os = "none", not(test)))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {
        core::hint::spin_loop();
    }
}

#[cfg(test)]
mod tests;
