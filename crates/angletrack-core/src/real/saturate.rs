//! The fixed-point path's saturation of a 32-bit result to 16 bits, in the form each core
//! runs in the fewest instructions, both forms the same function: a Cortex-M3/M4/M7 (and a
//! host) clamps (one `SSAT` on a Cortex-M4); ARMv6-M (Cortex-M0/M0+, no `SSAT` and no
//! conditional select) tests whether the value already fits, three instructions (`SXTH`,
//! `CMP`, `BNE`) and no constant for a value in range, against two compares, two branches and
//! the two limits kept in registers for a clamp, and saturates out of line. ARMv6-M is told
//! apart as in `fixed/multiply.rs` (the Arm architecture without 32-bit atomics).

/// `v` saturated to `i16`, as an `i32`: where the value fits, `v` itself, which the
/// caller's next operations use without a sign extension.
#[inline(always)]
pub(crate) fn saturated(v: i32) -> i32 {
    #[cfg(any(not(target_arch = "arm"), target_has_atomic = "32"))]
    {
        i32::from(clamped(v))
    }
    #[cfg(not(any(not(target_arch = "arm"), target_has_atomic = "32")))]
    {
        if v >> 15 == v >> 31 {
            v
        } else {
            i32::from(out_of_range(v))
        }
    }
}

/// `v` saturated to `i16` (`v.clamp(-32768, 32767)`).
#[inline(always)]
pub(crate) fn saturate_i16(v: i32) -> i16 {
    #[cfg(any(not(target_arch = "arm"), target_has_atomic = "32"))]
    {
        clamped(v)
    }
    #[cfg(not(any(not(target_arch = "arm"), target_has_atomic = "32")))]
    {
        tested(v)
    }
}

/// The clamp.
#[cfg_attr(
    all(target_arch = "arm", not(target_has_atomic = "32")),
    allow(dead_code)
)]
#[inline(always)]
fn clamped(v: i32) -> i16 {
    v.clamp(-32768, 32767) as i16
}

/// The test of a value in range, the clamp out of line.
#[cfg_attr(
    not(all(target_arch = "arm", not(target_has_atomic = "32"))),
    allow(dead_code)
)]
#[inline(always)]
fn tested(v: i32) -> i16 {
    if v >> 15 == v >> 31 {
        v as i16
    } else {
        out_of_range(v)
    }
}

/// The clamp of a value out of range (rare: out of line).
#[cfg_attr(
    not(all(target_arch = "arm", not(target_has_atomic = "32"))),
    allow(dead_code)
)]
#[cold]
#[inline(never)]
fn out_of_range(v: i32) -> i16 {
    clamped(v)
}

#[cfg(test)]
mod tests {
    use super::{clamped, saturate_i16, saturated, tested};

    #[test]
    fn both_forms_saturate_to_i16() {
        let edges = [
            i32::MIN,
            i32::MIN + 1,
            -65_536,
            i32::MAX - 1,
            i32::MAX,
            65_535,
        ];
        let near = (-33_000..=33_000).step_by(1);
        for v in edges.into_iter().chain(near) {
            let expected = i16::try_from(v).unwrap_or(if v < 0 { i16::MIN } else { i16::MAX });
            assert_eq!(clamped(v), expected, "{v}");
            assert_eq!(tested(v), expected, "{v}");
            assert_eq!(saturate_i16(v), expected, "{v}");
            assert_eq!(saturated(v), i32::from(expected), "{v}");
        }
    }
}
