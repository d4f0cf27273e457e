//! The estimates of a run of the core's fixed-point observer (`docs/theory.md §14`) written
//! out one column per quantity: its integers as the firmware holds them, and the same
//! estimates in physical units through the core's conversions. What the Python binding's
//! `FixedObserver.update` writes into.

use angletrack_core::{Chain, ChainState, FixedEstimate, FixedGains, FixedState, Stage};

/// Where a fixed-point run writes its estimates: one slice per quantity, element `i` of
/// every column for sample `i`.
#[derive(Debug)]
pub struct FixedColumns<'a> {
    /// Binary angle (2^32 per turn, `i32::MIN` is -pi).
    pub angle: &'a mut [i32],
    /// Whole turns since initialisation.
    pub turns: &'a mut [i64],
    /// Speed (2^-32 turn per sample).
    pub speed: &'a mut [i32],
    /// Acceleration (2^-63 turn per sample^2); 0 at order 2.
    pub acceleration: &'a mut [i64],
    /// Normalised phase error (Q15: 2^15 is 1).
    pub phase_error: &'a mut [i32],
    /// Fault bits ([`Faults::bits`](angletrack_core::Faults::bits)).
    pub faults: &'a mut [u8],
    /// Multi-turn position (rad), [`FixedGains::position_rad`].
    pub position_rad: &'a mut [f64],
    /// Speed (rad/s), [`FixedGains::speed_rad_s`].
    pub speed_rad_s: &'a mut [f64],
    /// Acceleration (rad/s^2), [`FixedGains::acceleration_rad_s2`].
    pub acceleration_rad_s2: &'a mut [f64],
}

impl FixedColumns<'_> {
    /// Runs `gains` from `state` over the samples `y_c`, `y_s` (counts), one
    /// [`Chain::update`](angletrack_core::Chain::update) of the bare observer per sample,
    /// writing each estimate into the columns; returns
    /// how many samples it ran: the fewest of the samples and of every column's elements
    /// (the caller gives them all of one length when every sample must run).
    ///
    /// ```
    /// use angletrack::FixedColumns;
    /// use angletrack_core::{FixedGains, FixedState};
    /// let gains = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6)?;
    /// let mut state = FixedState::new();
    /// let (mut angle, mut turns, mut speed, mut acceleration) = ([0; 2], [0; 2], [0; 2], [0; 2]);
    /// let (mut phase_error, mut faults) = ([0; 2], [0; 2]);
    /// let (mut position, mut speed_rad_s, mut acceleration_rad_s2) = ([0.0; 2], [0.0; 2], [0.0; 2]);
    /// let columns = FixedColumns {
    ///     angle: &mut angle,
    ///     turns: &mut turns,
    ///     speed: &mut speed,
    ///     acceleration: &mut acceleration,
    ///     phase_error: &mut phase_error,
    ///     faults: &mut faults,
    ///     position_rad: &mut position,
    ///     speed_rad_s: &mut speed_rad_s,
    ///     acceleration_rad_s2: &mut acceleration_rad_s2,
    /// };
    /// // (cos, sin) = (0, 1), then (-1, 0): a quarter turn, then half a turn.
    /// assert_eq!(columns.run(&gains, &mut state, &[0, -16384], &[16384, 0]), 2);
    /// assert!((angle[0] - (1 << 30)).abs() < 64);
    /// assert!((position[0] - std::f64::consts::FRAC_PI_2).abs() < 1e-6);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn run<const N: usize>(
        self,
        gains: &FixedGains<N>,
        state: &mut FixedState<N>,
        y_c: &[i16],
        y_s: &[i16],
    ) -> usize {
        let chain = Chain::new((), *gains);
        let mut chain_state = ChainState {
            front_end: (),
            observer: *state,
        };
        let count = self.run_with(gains, y_c, y_s, |c, s| {
            chain.update(&mut chain_state, (c, s))
        });
        *state = chain_state.observer;
        count
    }

    /// As [`FixedColumns::run`], through the fixed-point chain `chain` (its front end's
    /// stages, then its observer, [`Chain::update`] per sample) from `state`: the counts
    /// `y_c`, `y_s` are the chain's input, before its stages.
    pub fn run_chain<F: Stage<i16, (i16, i16)>, const N: usize>(
        self,
        chain: &Chain<F, FixedGains<N>>,
        state: &mut ChainState<F::State, FixedState<N>>,
        y_c: &[i16],
        y_s: &[i16],
    ) -> usize {
        self.run_with(&chain.observer, y_c, y_s, |c, s| {
            chain.update(state, (c, s))
        })
    }

    /// Writes the estimate `update(c, s)` of each sample, in physical units by `gains`.
    fn run_with<const N: usize>(
        self,
        gains: &FixedGains<N>,
        y_c: &[i16],
        y_s: &[i16],
        mut update: impl FnMut(i16, i16) -> FixedEstimate,
    ) -> usize {
        let Self {
            angle,
            turns,
            speed,
            acceleration,
            phase_error,
            faults,
            position_rad,
            speed_rad_s,
            acceleration_rad_s2,
        } = self;
        let integers = angle
            .iter_mut()
            .zip(turns)
            .zip(speed)
            .zip(acceleration)
            .zip(phase_error)
            .zip(faults);
        let physical = position_rad
            .iter_mut()
            .zip(speed_rad_s)
            .zip(acceleration_rad_s2);
        let mut count = 0;
        for (((c, s), integer), physical) in y_c.iter().zip(y_s).zip(integers).zip(physical) {
            let e = update(*c, *s);
            let (((((angle, turns), speed), acceleration), phase_error), faults) = integer;
            (*angle, *turns, *speed, *acceleration) = (e.angle, e.turns, e.speed, e.acceleration);
            (*phase_error, *faults) = (e.phase_error, e.faults.bits());
            let ((position_rad, speed_rad_s), acceleration_rad_s2) = physical;
            *position_rad = gains.position_rad(&e);
            *speed_rad_s = gains.speed_rad_s(&e);
            *acceleration_rad_s2 = gains.acceleration_rad_s2(&e);
            count += 1;
        }
        count
    }
}
