//! The fixed-point constants of a design (`docs/theory.md §14`): its gains quantised for the
//! core's fixed-point observer ([`FixedGains`]), checked for a gain that rounds to zero and
//! for the stability of the quantised loop, and the integers a firmware embeds.

use angletrack_core::fixed::FixedConstants;
use angletrack_core::{FixedGains, Order, SupportedOrder};

use super::designs::{AnyDesign, Design};
use crate::error::Error;

impl<const N: usize> Design<N>
where
    Order<N>: SupportedOrder,
{
    /// The design's gains quantised for the fixed-point observer: refused
    /// ([`Error::Gains`], naming the gain) if one rounds to zero or does not fit its format,
    /// or if the quantised loop leaves the stability region.
    ///
    /// ```
    /// use angletrack::paper::ComparedObserver;
    /// use angletrack::AnyDesign;
    /// let AnyDesign::Third(design) = ComparedObserver::Kalman.design()? else { unreachable!() };
    /// let fixed = design.fixed_gains()?;
    /// for (q, l) in fixed.gains().iter().zip(design.gains.gains()) {
    ///     assert!((q / l - 1.0).abs() <= 2f64.powi(-16));
    /// }
    /// # Ok::<(), angletrack::Error>(())
    /// ```
    pub fn fixed_gains(&self) -> Result<FixedGains<N>, Error> {
        Ok(FixedGains::new(self.gains.gains(), self.sample_period())?)
    }
}

/// The fixed-point constants of a design of either order, for export (C, Rust, JSON):
/// [`FixedConstants`] as vectors, with the gains they represent and the sample period.
#[derive(Debug, Clone, PartialEq)]
pub struct FixedDesignConstants {
    /// The gains' multipliers (1 to 2^31 - 1), `l1` first: `l_i = multiplier_i 2 pi / 2^s_i`,
    /// `s = (33, 33, 48 - acceleration_shift)`.
    pub multiplier: Vec<i32>,
    /// The left shift of the phase error in the acceleration's correction (1 to 15; 0 for a
    /// 2nd-order observer).
    pub acceleration_shift: u32,
    /// The gains the constants represent (what runs: within half a unit of each
    /// multiplier of the design's).
    pub quantised_gains: Vec<f64>,
    /// The sample period (s).
    pub sample_period_s: f64,
}

impl FixedDesignConstants {
    /// The constants of the fixed-point gains `gains` (of either order), as
    /// [`AnyDesign::fixed_constants`] gives a design's.
    ///
    /// ```
    /// use angletrack::FixedDesignConstants;
    /// use angletrack_core::FixedGains;
    /// let gains = FixedGains::<2>::new([0.05, 0.0012], 1e-4)?;
    /// let constants = FixedDesignConstants::of(&gains);
    /// assert_eq!(constants.multiplier, gains.constants().multiplier.to_vec());
    /// assert_eq!(constants.acceleration_shift, 0);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn of<const N: usize>(gains: &FixedGains<N>) -> Self {
        let FixedConstants {
            multiplier,
            acceleration_shift,
        } = gains.constants();
        Self {
            multiplier: multiplier.to_vec(),
            acceleration_shift,
            quantised_gains: gains.gains().to_vec(),
            sample_period_s: gains.sample_period(),
        }
    }
}

impl AnyDesign {
    /// The fixed-point constants of the design ([`Design::fixed_gains`]).
    ///
    /// ```
    /// use angletrack::paper::ComparedObserver;
    /// let constants = ComparedObserver::SecondOrder.design()?.fixed_constants()?;
    /// assert_eq!(constants.multiplier.len(), 2);
    /// assert!(constants.multiplier.iter().all(|&m| m >= 1 << 16));
    /// # Ok::<(), angletrack::Error>(())
    /// ```
    pub fn fixed_constants(&self) -> Result<FixedDesignConstants, Error> {
        Ok(match self {
            AnyDesign::Second(d) => FixedDesignConstants::of(&d.fixed_gains()?),
            AnyDesign::Third(d) => FixedDesignConstants::of(&d.fixed_gains()?),
        })
    }
}

#[cfg(test)]
mod tests {
    use angletrack_core::{ConfigError, Parameter};

    use super::*;
    use crate::paper::{ComparedObserver, OVERSHOOT_SAMPLE_PERIOD_S, PaperSetting};
    use crate::{Discretisation, Gains};

    /// Every paper design quantises within half a unit of each multiplier (each keeping at
    /// least 13 bits), and its constants give the same fixed-point gains back through the
    /// core's check.
    #[test]
    fn paper_designs_quantise_and_round_trip() {
        let mut designs: Vec<AnyDesign> = ComparedObserver::ALL
            .iter()
            .map(|o| o.design().unwrap())
            .collect();
        designs.extend(PaperSetting::ALL.iter().map(|s| {
            s.design(OVERSHOOT_SAMPLE_PERIOD_S, Discretisation::PoleMatching)
                .unwrap()
        }));
        for design in designs {
            let constants = design.fixed_constants().unwrap();
            let pairs = constants.quantised_gains.iter().zip(design.gains());
            for ((q, l), m) in pairs.zip(&constants.multiplier) {
                assert!(
                    (q / l - 1.0).abs() <= 0.5 / f64::from(*m) + 1e-15,
                    "{q} vs {l}"
                );
                // The smallest multiplier here, about 13,600 (l2 of the 2nd-order Butterworth
                // setting at 100 kHz), keeps 13 bits: within 2^-14 of the gain.
                assert!(*m >= 1 << 13, "{m}");
            }
            if let AnyDesign::Third(d) = &design {
                let fixed = d.fixed_gains().unwrap();
                let back = FixedGains::<3>::from_constants(fixed.constants(), d.sample_period());
                assert_eq!(back, Ok(fixed));
            }
        }
    }

    /// A gain too small for the format is refused with the core's error naming it.
    #[test]
    fn a_gain_that_rounds_to_zero_is_refused_by_name() {
        let design = Design::<2> {
            gains: Gains::new([0.05, 1e-24], 1e-4).unwrap(),
            ..crate::design::second_order_butterworth(2e-3, 1e-4, Discretisation::PoleMatching)
                .unwrap()
        };
        assert_eq!(
            design.fixed_gains().unwrap_err(),
            Error::Gains(ConfigError::OutOfRange(Parameter::SpeedGain))
        );
    }
}
