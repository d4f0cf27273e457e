//! The estimates of a run written out one column per quantity, only the quantities the
//! caller asked for: what a single channel, a [`ChannelBatch`](crate::ChannelBatch) and the
//! Python binding write into.

use angletrack_core::{Estimate, Real};

/// One quantity of an [`Estimate`] a run can write out, by the name the Python API and the
/// command line give it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Output {
    /// Estimated angle (rad), wrapped to [-pi, pi).
    Angle,
    /// Multi-turn position `turns * 2 pi + angle` (rad), in `f64`.
    Position,
    /// Estimated speed (rad/s).
    Speed,
    /// Estimated acceleration (rad/s^2); 0 at order 2.
    Acceleration,
    /// Normalised phase-detector output.
    PhaseError,
    /// Fault bits ([`Faults`](angletrack_core::Faults)).
    Faults,
}

impl Output {
    /// Every output, in the order of [`Estimate`]'s fields.
    pub const ALL: [Output; 6] = [
        Output::Angle,
        Output::Position,
        Output::Speed,
        Output::Acceleration,
        Output::PhaseError,
        Output::Faults,
    ];

    /// Its name: `angle`, `position`, `speed`, `acceleration`, `phase_error` or `faults`.
    pub const fn name(self) -> &'static str {
        match self {
            Output::Angle => "angle",
            Output::Position => "position",
            Output::Speed => "speed",
            Output::Acceleration => "acceleration",
            Output::PhaseError => "phase_error",
            Output::Faults => "faults",
        }
    }

    /// The output named `name` (as [`Output::name`] spells it), `None` for any other name.
    ///
    /// ```
    /// use angletrack::Output;
    /// assert_eq!(Output::from_name("speed"), Some(Output::Speed));
    /// assert_eq!(Output::from_name("velocity"), None);
    /// ```
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|output| output.name() == name)
    }

    /// The bytes one sample of it takes in a run of float type `T` (the position is `f64`,
    /// the faults one byte).
    pub const fn bytes_per_sample<T>(self) -> usize {
        match self {
            Output::Position => core::mem::size_of::<f64>(),
            Output::Faults => 1,
            _ => core::mem::size_of::<T>(),
        }
    }
}

/// The outputs a caller asked for (the Python `outputs=`): a set of [`Output`]s.
///
/// ```
/// use angletrack::{Output, OutputSet};
/// let set = OutputSet::from_names(["speed", "faults"]).unwrap();
/// assert!(set.has(Output::Speed) && !set.has(Output::Angle));
/// assert_eq!(set.bytes_per_sample::<f32>(), 5);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutputSet([bool; 6]);

impl OutputSet {
    /// Every output.
    pub const ALL: Self = Self([true; 6]);

    /// The outputs `names` (as [`Output::name`] spells them); an unknown name is refused,
    /// the message naming it and the known names.
    pub fn from_names<'a>(names: impl IntoIterator<Item = &'a str>) -> Result<Self, String> {
        let mut selected = [false; 6];
        for name in names {
            let output = Output::from_name(name).ok_or_else(|| {
                let known: Vec<&str> = Output::ALL.iter().map(|o| o.name()).collect();
                format!(
                    "unknown output '{name}': expected some of {}",
                    known.join(", ")
                )
            })?;
            selected[output as usize] = true;
        }
        Ok(Self(selected))
    }

    /// Whether `output` is in the set.
    pub fn has(self, output: Output) -> bool {
        self.0[output as usize]
    }

    /// The bytes one sample of the outputs in the set takes in a run of float type `T`.
    pub fn bytes_per_sample<T>(self) -> usize {
        Output::ALL
            .iter()
            .filter(|&&o| self.has(o))
            .map(|o| o.bytes_per_sample::<T>())
            .sum()
    }
}

/// Where a run writes its estimates: one slice per quantity, `None` for a quantity nobody
/// asked for (neither computed beyond need nor written). Element `i` of every column
/// belongs to sample `i` of the run (for a batch: channel `c`, sample `k` at
/// `c * samples + k`).
#[derive(Debug, Default)]
pub struct EstimateColumns<'a, T> {
    /// Estimated angle (rad), wrapped to [-pi, pi).
    pub angle: Option<&'a mut [T]>,
    /// Multi-turn position `turns * 2 pi + angle` (rad).
    pub position: Option<&'a mut [f64]>,
    /// Estimated speed (rad/s).
    pub speed: Option<&'a mut [T]>,
    /// Estimated acceleration (rad/s^2); 0 at order 2.
    pub acceleration: Option<&'a mut [T]>,
    /// Phase-detector output.
    pub phase_error: Option<&'a mut [T]>,
    /// Fault bits ([`Faults::bits`](angletrack_core::Faults::bits)).
    pub faults: Option<&'a mut [u8]>,
}

impl<T: Real> EstimateColumns<'_, T> {
    /// Whether the columns hold `output`.
    pub fn has(&self, output: Output) -> bool {
        match output {
            Output::Angle => self.angle.is_some(),
            Output::Position => self.position.is_some(),
            Output::Speed => self.speed.is_some(),
            Output::Acceleration => self.acceleration.is_some(),
            Output::PhaseError => self.phase_error.is_some(),
            Output::Faults => self.faults.is_some(),
        }
    }

    /// Whether every column present holds exactly `len` elements.
    pub fn all_of_len(&self, len: usize) -> bool {
        let fits = |column: Option<usize>| column.is_none_or(|n| n == len);
        fits(self.angle.as_deref().map(<[T]>::len))
            && fits(self.position.as_deref().map(<[f64]>::len))
            && fits(self.speed.as_deref().map(<[T]>::len))
            && fits(self.acceleration.as_deref().map(<[T]>::len))
            && fits(self.phase_error.as_deref().map(<[T]>::len))
            && fits(self.faults.as_deref().map(<[u8]>::len))
    }

    /// The length of the shortest column present, `None` when none is.
    fn shortest(&self) -> Option<usize> {
        [
            self.angle.as_deref().map(<[T]>::len),
            self.position.as_deref().map(<[f64]>::len),
            self.speed.as_deref().map(<[T]>::len),
            self.acceleration.as_deref().map(<[T]>::len),
            self.phase_error.as_deref().map(<[T]>::len),
            self.faults.as_deref().map(<[u8]>::len),
        ]
        .into_iter()
        .flatten()
        .min()
    }

    /// Writes the quantities the columns hold of each estimate in turn, from element 0 on,
    /// and returns how many estimates it took. It takes no more than the shortest column
    /// present holds (all of them when no column is present), so a lazy iterator (an
    /// observer's update per sample) runs exactly over the samples written; the caller
    /// checks the lengths first ([`EstimateColumns::all_of_len`]) when every sample must
    /// be written.
    ///
    /// ```
    /// use angletrack::EstimateColumns;
    /// use angletrack_core::{Estimate, Faults};
    /// let (mut angle, mut speed) = ([0.0_f32; 2], [0.0_f32; 2]);
    /// let columns = EstimateColumns {
    ///     angle: Some(&mut angle), speed: Some(&mut speed), ..Default::default()
    /// };
    /// let estimates = (1..=3).map(|k| Estimate::new(0.5 * k as f32, 0, 60.0, 0.0, 0.0, Faults::NONE));
    /// assert_eq!(columns.write(estimates), 2); // the third estimate is not even computed
    /// assert_eq!((angle, speed), ([0.5, 1.0], [60.0, 60.0]));
    /// ```
    #[inline]
    pub fn write(self, estimates: impl IntoIterator<Item = Estimate<T>>) -> usize {
        let limit = self.shortest().unwrap_or(usize::MAX);
        let mut angle = self.angle.map(|c| c.iter_mut());
        let mut position = self.position.map(|c| c.iter_mut());
        let mut speed = self.speed.map(|c| c.iter_mut());
        let mut acceleration = self.acceleration.map(|c| c.iter_mut());
        let mut phase_error = self.phase_error.map(|c| c.iter_mut());
        let mut faults = self.faults.map(|c| c.iter_mut());
        let mut written = 0;
        for e in estimates.into_iter().take(limit) {
            // Each column holds at least `limit` elements: every `next` below is `Some`.
            put(&mut angle, || e.angle);
            put(&mut position, || e.position());
            put(&mut speed, || e.speed);
            put(&mut acceleration, || e.acceleration);
            put(&mut phase_error, || e.phase_error);
            put(&mut faults, || e.faults.bits());
            written += 1;
        }
        written
    }
}

/// Writes `value()` into the next element of `column`, if the column is present (the
/// value is computed only then).
#[inline(always)]
fn put<'a, E: 'a>(column: &mut Option<impl Iterator<Item = &'a mut E>>, value: impl FnOnce() -> E) {
    if let Some(slot) = column.as_mut().and_then(Iterator::next) {
        *slot = value();
    }
}
