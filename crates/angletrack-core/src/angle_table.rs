//! The angle correction as a table over the electrical turn (`docs/theory.md §15`): the
//! sensor's angle error `d(theta)` at `L` equally spaced angles, read at the observer's
//! predicted angle by linear interpolation, and the sample rotated by `-d` there, as
//! [`AngleCorrection`] does from its harmonics. A table costs the same whatever the error's
//! shape or order: an index, two loads and a multiply-add, then the rotation.
//! Generated from learned harmonics ([`AngleCorrectionTable::from_harmonics`]) or from a
//! measured error curve ([`AngleCorrectionTable::from_curve`]); in fixed point
//! ([`FixedAngleCorrectionTable`]) indexed by the binary angle's top bits.
//!
//! The entries hold `t = tan d`, not `d`: the rotation by `-d` is then
//! `(y_c + t y_s, y_s - t y_c)`, which is `(y_c, y_s)` rotated by exactly `-d` and scaled by
//! `1 / cos d` (5e-5 for `d` = 10 mrad, 3 % at the largest `d`, 0.25 rad), a scale the
//! loop's normalised phase detector removes: two multiply-adds instead of the series of
//! `sin d` and `cos d`. With the linear interpolation of a smooth error (within
//! `h^2 max|t''| / 8`, `h = 2 pi / L`: 1.7e-7 rad for a 4 mrad error at the 3rd harmonic
//! and `L = 1024`, as [`AngleCorrectionTable::from_harmonics`]' example asserts), the
//! correction is as good as the harmonics'.

use crate::angle_correction::AngleCorrection;
use crate::error::{ConfigError, Parameter};
use crate::real::Float;
use crate::real::saturate::saturate_i16;

/// The sensor's angle error `d` (rad) at the `L` angles `-pi + 2 pi k / L` of one electrical
/// turn (`L` a power of two, 4 to 4096), removed inside the phase detector as
/// [`AngleCorrection`] is: each sample is rotated by `-d(p)`, `d` interpolated linearly at
/// the observer's predicted angle `p`. `Copy`: firmware keeps it in flash.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AngleCorrectionTable<T, const L: usize> {
    /// Per entry `k`: `t_k = tan d_k` and the step to the next entry, `t_{k+1} - t_k`
    /// (periodic), side by side, so that the interpolation loads both from one address.
    pub(crate) segments: [[T; 2]; L],
}

impl<T: Float, const L: usize> AngleCorrectionTable<T, L> {
    /// `L` as a float: entries per turn.
    pub(crate) const LENGTH_IS_A_POWER_OF_TWO: () = assert!(
        L.is_power_of_two() && L >= 4 && L <= 4096,
        "the table's length L must be a power of two from 4 to 4096"
    );

    /// The table of `errors` (rad) at the angles `-pi + 2 pi k / L`. Refuses a non-finite
    /// entry or one beyond [`AngleCorrection::max_total_rad`] (0.25 rad), naming
    /// `angle_correction`.
    ///
    /// ```
    /// use angletrack_core::{AngleCorrectionTable, Parameter};
    /// let table = AngleCorrectionTable::<f32, 4>::new([0.0, 0.01, 0.0, -0.01])?;
    /// // Linear between the entries: -pi/4 lies half-way between -pi/2 and 0.
    /// assert!((table.error_at(-core::f32::consts::FRAC_PI_4) - 0.005).abs() < 1e-6);
    /// let err = AngleCorrectionTable::<f32, 4>::new([0.0, 0.3, 0.0, 0.0]).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::AngleCorrection);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn new(errors: [T; L]) -> Result<Self, ConfigError> {
        let () = Self::LENGTH_IS_A_POWER_OF_TWO;
        for d in errors {
            if !d.is_finite() {
                return Err(ConfigError::NotFinite(Parameter::AngleCorrection));
            }
            if !(d.abs() <= AngleCorrection::<T>::max_total_rad()) {
                return Err(ConfigError::OutOfRange(Parameter::AngleCorrection));
            }
        }
        Ok(Self::of_errors(&errors))
    }

    /// The table of checked `errors`.
    fn of_errors(errors: &[T; L]) -> Self {
        let mut table = Self {
            segments: [[T::ZERO; 2]; L],
        };
        for (segment, &d) in table.segments.iter_mut().zip(errors) {
            segment[0] = tangent(d);
        }
        table.set_steps();
        table
    }

    /// Each entry's step to the next (periodic), from the entries.
    fn set_steps(&mut self) {
        for k in 0..L {
            self.segments[k][1] = self.segments[(k + 1) % L][0] - self.segments[k][0];
        }
    }

    /// The table of a harmonic correction: its error at each of the `L` angles.
    ///
    /// ```
    /// use angletrack_core::{AngleCorrection, AngleCorrectionTable};
    /// let mut b = [0.0; 8];
    /// b[2] = 0.004; // 4 mrad at the 3rd harmonic
    /// let harmonics = AngleCorrection::<f64>::new([0.0; 8], b)?;
    /// let table = AngleCorrectionTable::<f64, 1024>::from_harmonics(&harmonics);
    /// let worst = (0..1000)
    ///     .map(|i| -core::f64::consts::PI + 6.28e-3 * i as f64)
    ///     .map(|a| (table.error_at(a) - harmonics.error_at(a)).abs())
    ///     .fold(0.0, f64::max);
    /// assert!(worst < 2e-7, "{worst}");
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn from_harmonics(harmonics: &AngleCorrection<T>) -> Self {
        let () = Self::LENGTH_IS_A_POWER_OF_TWO;
        // Every entry is within the harmonics' checked total. Built in place: a firmware's
        // stack holds one table, not two.
        let mut table = Self {
            segments: [[T::ZERO; 2]; L],
        };
        for (k, segment) in table.segments.iter_mut().enumerate() {
            segment[0] = tangent(harmonics.error_at(Self::angle_of(k)));
        }
        table.set_steps();
        table
    }

    /// The table of a measured error curve: `curve[j]` (rad) at the angle
    /// `-pi + 2 pi j / curve.len()`, at least 2 points over one electrical turn (an
    /// encoder's error against a reference, binned by angle), resampled to `L` entries by
    /// periodic linear interpolation. Refuses a curve of fewer than 2 points (naming
    /// `curve`) and entries as [`AngleCorrectionTable::new`] does.
    ///
    /// ```
    /// use angletrack_core::AngleCorrectionTable;
    /// let curve = [0.0, 0.002, 0.0, -0.002]; // rad at -pi, -pi/2, 0, pi/2
    /// let table = AngleCorrectionTable::<f32, 8>::from_curve(&curve)?;
    /// assert!((table.error_at(-core::f32::consts::FRAC_PI_2) - 0.002).abs() < 1e-7);
    /// assert!((table.error_at(-3.0 * core::f32::consts::FRAC_PI_4) - 0.001).abs() < 1e-7);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn from_curve(curve: &[T]) -> Result<Self, ConfigError> {
        Self::new(Self::entries_of_curve(curve)?)
    }

    /// The `L` entries (rad) [`AngleCorrectionTable::from_curve`] makes of `curve`: the
    /// errors [`AngleCorrectionTable::new`] then takes (a firmware's `const` table is made
    /// of them). Refuses a curve of fewer than 2 points, naming `curve`.
    pub fn entries_of_curve(curve: &[T]) -> Result<[T; L], ConfigError> {
        let () = Self::LENGTH_IS_A_POWER_OF_TWO;
        let points = curve.len();
        if points < 2 {
            return Err(ConfigError::OutOfRange(Parameter::AngleErrorCurve));
        }
        let mut errors = [T::ZERO; L];
        for (k, d) in errors.iter_mut().enumerate() {
            // The curve's position of entry k, in points: k points / L, exact in any float.
            let position =
                T::from_i32(k as i32) * T::from_i32(points as i32) / T::from_i32(L as i32);
            let j = position.floor_to_i32().max(0) as usize % points;
            let fraction = position - T::from_i32(j as i32);
            let (a, b) = (curve[j], curve[(j + 1) % points]);
            *d = a + (b - a) * fraction;
        }
        Ok(errors)
    }

    /// The angle of entry `k` (rad): `-pi + 2 pi k / L`.
    fn angle_of(k: usize) -> T {
        -T::PI + T::TAU * T::from_i32(k as i32) / T::from_i32(L as i32)
    }

    /// The entries (rad), at the angles `-pi + 2 pi k / L` (from their tangents: within a
    /// rounding of the errors the table was made of).
    pub fn errors(&self) -> [T; L] {
        let mut errors = [T::ZERO; L];
        for (d, segment) in errors.iter_mut().zip(&self.segments) {
            *d = segment[0].atan2(T::ONE);
        }
        errors
    }

    /// The error `d` (rad) at `angle` (rad, in [-pi, pi); any other angle is wrapped into
    /// the table by its index), from its tangent interpolated linearly between the two
    /// nearest entries.
    pub fn error_at(&self, angle: T) -> T {
        self.tangent_at(angle).atan2(T::ONE)
    }

    /// `tan d` at `angle` (see [`AngleCorrectionTable::error_at`]).
    #[inline(always)]
    fn tangent_at(&self, angle: T) -> T {
        // The position in entries from -pi, plus one turn so that it stays positive (and
        // its truncation is its floor) for any angle above -3 pi: one multiply-add, in
        // [L, 2 L) for an angle in [-pi, pi); the mask below removes the turn.
        let entries_per_rad = T::from_i32(L as i32) * T::FRAC_1_TAU;
        let position = angle * entries_per_rad + T::from_i32(3 * (L as i32) / 2);
        let whole = position.truncate_to_i32();
        let fraction = position - T::from_i32(whole);
        // Masked: a power of two, so the index is always in the table (no bounds check).
        let [t, step] = self.segments[whole as usize & (L - 1)];
        t + step * fraction
    }

    /// The sample `(y_c, y_s)` rotated by `-d(p)` at the predicted angle `p` (rad, in
    /// [-pi, pi)) and scaled by `1 / cos d(p)`, which the loop's normalised phase detector
    /// removes: `(y_c + t y_s, y_s - t y_c)` with `t = tan d(p)`.
    #[inline(always)]
    pub fn rotate(&self, p: T, y_c: T, y_s: T) -> (T, T) {
        let t = self.tangent_at(p);
        (y_c + t * y_s, y_s - t * y_c)
    }
}

/// An [`AngleCorrectionTable`] in the fixed-point observer's integers: the error's tangent
/// in Q15 (2^-15, 3e-5 rad) at `L` angles, indexed by the top bits of the predicted binary
/// angle and interpolated by the next 15; the same rotation `(y_c + t y_s, y_s - t y_c)`
/// (exactly `-d`, scaled by `1 / cos d`), rounded and saturated to `i16`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FixedAngleCorrectionTable<const L: usize> {
    /// `tan d_k` in Q15, entry `k` at `(k + L / 2) mod L`: from the angle 0, so that the
    /// binary angle's top bits index it as they are (no half turn added per sample). One
    /// value per entry, not the float table's pair: a Cortex-M0 has 16 KiB of RAM, and the
    /// step to the next entry is one load and one subtraction.
    tangents_q15: [i16; L],
}

impl<const L: usize> FixedAngleCorrectionTable<L> {
    /// The table's index bits: `L = 2^BITS`.
    const BITS: u32 = {
        assert!(
            L.is_power_of_two() && L >= 4 && L <= 4096,
            "the table's length L must be a power of two from 4 to 4096"
        );
        L.trailing_zeros()
    };

    /// The table of the entries `errors_q15` (Q15 rad, at the angles `-pi + 2 pi k / L`),
    /// each within 0.25 rad (8192), else refused naming `angle_correction`; `const`, for a
    /// table kept in flash.
    ///
    /// ```
    /// use angletrack_core::{FixedAngleCorrectionTable, Parameter};
    /// const TABLE: FixedAngleCorrectionTable<4> =
    ///     match FixedAngleCorrectionTable::new([0, 328, 0, -328]) {
    ///         Ok(table) => table,
    ///         Err(_) => panic!("an entry beyond 0.25 rad"),
    ///     };
    /// assert_eq!(TABLE.error_at(i32::MIN / 2), 328); // -pi/2
    /// let err = FixedAngleCorrectionTable::new([0, 8193, 0, 0]).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::AngleCorrection);
    /// ```
    pub const fn new(errors_q15: [i16; L]) -> Result<Self, ConfigError> {
        let _ = Self::BITS;
        let mut tangents_q15 = [0; L];
        let mut k = 0;
        while k < L {
            if errors_q15[k].unsigned_abs() > 8192 {
                return Err(ConfigError::OutOfRange(Parameter::AngleCorrection));
            }
            tangents_q15[(k + L / 2) & (L - 1)] = tangent_q15(errors_q15[k]);
            k += 1;
        }
        Ok(Self { tangents_q15 })
    }

    /// The integers of a float table (rad, within 0.25 rad: within `i16` in Q15), each
    /// rounded to the nearest 2^-15 rad.
    ///
    /// ```
    /// use angletrack_core::{AngleCorrectionTable, FixedAngleCorrectionTable};
    /// let table = AngleCorrectionTable::<f64, 4>::new([0.0, 0.01, 0.0, -0.01])?;
    /// let fixed = FixedAngleCorrectionTable::from_table(&table);
    /// assert_eq!(fixed.errors_q15(), [0, 328, 0, -328]);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn from_table(table: &AngleCorrectionTable<f64, L>) -> Self {
        Self::of_tangents(|k| table.segments[k][0])
    }

    /// The table of a harmonic correction in integers, each entry its error at the angle
    /// `-pi + 2 pi k / L` rounded to Q15: as [`AngleCorrectionTable::from_harmonics`]
    /// then [`FixedAngleCorrectionTable::from_table`], with no float table in between.
    ///
    /// ```
    /// use angletrack_core::{AngleCorrection, AngleCorrectionTable, FixedAngleCorrectionTable};
    /// let mut b = [0.0; 8];
    /// b[2] = 0.004;
    /// let harmonics = AngleCorrection::<f64>::new([0.0; 8], b)?;
    /// let direct = FixedAngleCorrectionTable::<256>::from_harmonics(&harmonics);
    /// let through_floats =
    ///     FixedAngleCorrectionTable::from_table(&AngleCorrectionTable::from_harmonics(&harmonics));
    /// assert_eq!(direct, through_floats);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn from_harmonics(harmonics: &AngleCorrection<f64>) -> Self {
        Self::of_tangents(|k| {
            tangent(harmonics.error_at(AngleCorrectionTable::<f64, L>::angle_of(k)))
        })
    }

    /// The table of the tangents `tangent(k)` (of errors within 0.25 rad: within 0.2554),
    /// each rounded to Q15.
    fn of_tangents(tangent: impl Fn(usize) -> f64) -> Self {
        let _ = Self::BITS;
        let mut tangents_q15 = [0; L];
        for (k, q) in tangents_q15.iter_mut().enumerate() {
            // |t| <= tan 0.25: at most 8368 in Q15. Slot k holds entry k + L / 2.
            *q = libm::round(tangent((k + L / 2) & (L - 1)) * 32768.0) as i16;
        }
        Self { tangents_q15 }
    }

    /// The entries: the errors (Q15 rad) whose tangents the table holds (each the error the
    /// table was made of, for a table made of errors in Q15: test
    /// `angle_table::tests::fixed_tangents_round_trip_every_error`).
    pub fn errors_q15(&self) -> [i16; L] {
        let mut errors_q15 = [0; L];
        for (k, d) in errors_q15.iter_mut().enumerate() {
            *d = arctangent_q15(self.tangents_q15[(k + L / 2) & (L - 1)]);
        }
        errors_q15
    }

    /// The error `d` in Q15 rad at the binary angle `angle` (2^32 per turn, `i32::MIN` is
    /// -pi), from its tangent interpolated linearly.
    pub fn error_at(&self, angle: i32) -> i32 {
        let t = self.tangent_at(angle);
        // |t| <= 8368: within i16.
        i32::from(arctangent_q15(t as i16))
    }

    /// `tan d` in Q15 at the binary angle `angle`, interpolated linearly.
    #[inline(always)]
    fn tangent_at(&self, angle: i32) -> i32 {
        // The angle as an unsigned turn from 0 (the table's first slot): the index is its
        // top bits, the fraction the next 15.
        let turn = angle as u32;
        let k = (turn >> (32 - Self::BITS)) as usize & (L - 1);
        let fraction = ((turn << Self::BITS) >> 17) as i32;
        let t = i32::from(self.tangents_q15[k]);
        let step = i32::from(self.tangents_q15[(k + 1) & (L - 1)]) - t;
        // |step| <= 2^15, fraction < 2^15: the product is below 2^30.
        t + ((step * fraction) >> 15)
    }

    /// The sample rotated by `-d` at the predicted binary angle `angle` and scaled by
    /// `1 / cos d` (see [`AngleCorrectionTable::rotate`]), rounded and saturated to `i16`.
    /// With `|t| <= 8368` and `|y| <= 2^15`, every product is below 2^29: no overflow.
    #[inline(always)]
    pub fn rotate(&self, angle: i32, y_c: i16, y_s: i16) -> (i16, i16) {
        let t = self.tangent_at(angle);
        let (c, s) = (i32::from(y_c), i32::from(y_s));
        let c_out = c + ((s * t + (1 << 14)) >> 15);
        let s_out = s - ((c * t + (1 << 14)) >> 15);
        (saturate_i16(c_out), saturate_i16(s_out))
    }
}

/// `tan d` in Q15 of `d` in Q15 rad (`|d| <= 8192`, 0.25 rad), rounded to the nearest: its
/// series to `d^7` (the next term is below 2^-20 rad there) in Q30 integers; `const`.
const fn tangent_q15(d: i16) -> i16 {
    let x = (d as i64) << 15;
    let x2 = (x * x) >> 30;
    let x3 = (x * x2) >> 30;
    let x5 = (x3 * x2) >> 30;
    let x7 = (x5 * x2) >> 30;
    // |x| <= 2^28: |x3| <= 2^24, |2 x5| <= 2^21, |17 x7| < 2^21, each below 2^32 / d.
    let t = x + quotient(x3, 3) + quotient(2 * x5, 15) + quotient(17 * x7, 315);
    round_q30_to_q15(t)
}

/// `n / d` truncated toward zero, for `|n| < 2^32 / d`, without a division: `|n|` times
/// `m = ceil(2^32 / d)`, shifted down by 32. Exact: the product exceeds `2^32 |n| / d` by
/// `|n| (m d - 2^32) / d`, less than `2^32 / d` (as `m d - 2^32 < d`), too little to reach
/// the next multiple of `2^32`. A core without a divider then links no division routine
/// for a table made at run time; `d` a constant, `m` is one too.
#[inline(always)]
const fn quotient(n: i64, d: i64) -> i64 {
    let m = ((1 << 32) + d - 1) / d;
    let q = (n.abs() * m) >> 32;
    if n < 0 { -q } else { q }
}

/// The angle in Q15 rad of the tangent `t` in Q15 (`|t| <= 8368`), rounded to the
/// nearest: `atan t` by its series to `t^9` (the next term is below 2^-24 rad there).
fn arctangent_q15(t: i16) -> i16 {
    let x = i64::from(t) << 15;
    let x2 = (x * x) >> 30;
    let x3 = (x * x2) >> 30;
    let x5 = (x3 * x2) >> 30;
    let x7 = (x5 * x2) >> 30;
    let x9 = (x7 * x2) >> 30;
    round_q30_to_q15(x - x3 / 3 + x5 / 5 - x7 / 7 + x9 / 9)
}

/// A Q30 value (within `i16` once in Q15) rounded half away from zero to Q15.
const fn round_q30_to_q15(v: i64) -> i16 {
    let half = 1 << 14;
    let rounded = if v >= 0 {
        (v + half) >> 15
    } else {
        -((-v + half) >> 15)
    };
    rounded as i16
}

/// `tan d` in floats for `|d| <= 0.25` rad (a table's errors, at construction only): its
/// series to `d^11` (the next term is below 6e-11 rad there), in the table's own float (no
/// `f64` routine in an `f32` firmware).
fn tangent<T: Float>(d: T) -> T {
    let d2 = d * d;
    let coefficients = [
        1.0 / 3.0,
        2.0 / 15.0,
        17.0 / 315.0,
        62.0 / 2835.0,
        1382.0 / 155_925.0,
    ];
    // Horner's rule in d^2: d (1 + d^2 (1/3 + d^2 (2/15 + ...))).
    let mut sum = T::ZERO;
    for &c in coefficients.iter().rev() {
        sum = (sum + T::from_f64(c)) * d2;
    }
    d * (T::ONE + sum)
}

#[cfg(test)]
mod tests;
