//! Test scenarios, deterministic from a seed: a motion profile of the shaft and a sensor
//! model, sampled into the true angle, speed and acceleration beside `y_c` and `y_s`.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

use super::{Kinematics, MotionProfile, SensorModel};
use crate::error::{Argument, ArgumentError, Error, positive};

/// Largest number of samples of one scenario (the seven series then take 5.6 GB).
pub const MAX_SAMPLES: usize = 100_000_000;

/// One sample of a scenario as [`Scenario::stream`] draws it: the shaft's state and
/// `(y_c, y_s)`.
pub(crate) type ScenarioSample = (Kinematics, (f64, f64));

/// A sampled scenario: the truth beside the sensor signals, one value per sample.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Scenario {
    /// Sample period (s).
    pub sample_period_s: f64,
    /// Sample times `k Ts` (s).
    pub time_s: Vec<f64>,
    /// True angle (rad, unwrapped).
    pub angle_rad: Vec<f64>,
    /// True speed (rad/s).
    pub speed_rad_s: Vec<f64>,
    /// True acceleration (rad/s^2).
    pub acceleration_rad_s2: Vec<f64>,
    /// Cosine signal.
    pub y_c: Vec<f64>,
    /// Sine signal.
    pub y_s: Vec<f64>,
}

impl Scenario {
    /// Samples `profile` every `sample_period_s` through `sensor`; the noise is drawn from a
    /// ChaCha8 generator seeded with `seed`, so the same arguments give the same scenario on
    /// every machine. At most [`MAX_SAMPLES`] samples.
    ///
    /// ```
    /// use angletrack::{Motion, MotionProfile, Scenario, SensorModel};
    /// let profile = MotionProfile::new(0.0, 0.0).then(Motion::Trapezoidal {
    ///     distance_rad: 10.0, max_speed_rad_s: 50.0, max_acceleration_rad_s2: 500.0 });
    /// let scenario = Scenario::generate(&profile, &SensorModel::with_noise(0.01), 1e-4, 7)?;
    /// assert!((scenario.angle_rad.last().unwrap() - 10.0).abs() < 1e-9);
    /// assert_eq!(scenario, Scenario::generate(&profile, &SensorModel::with_noise(0.01), 1e-4, 7)?);
    /// # Ok::<(), angletrack::Error>(())
    /// ```
    pub fn generate(
        profile: &MotionProfile,
        sensor: &SensorModel,
        sample_period_s: f64,
        seed: u64,
    ) -> Result<Self, Error> {
        let (n, samples) = Self::stream(profile, sensor, sample_period_s, seed)?;
        let ts = sample_period_s;
        let mut scenario = Scenario {
            sample_period_s: ts,
            time_s: (0..n).map(|k| k as f64 * ts).collect(),
            angle_rad: Vec::with_capacity(n),
            speed_rad_s: Vec::with_capacity(n),
            acceleration_rad_s2: Vec::with_capacity(n),
            y_c: Vec::with_capacity(n),
            y_s: Vec::with_capacity(n),
        };
        for (state, (y_c, y_s)) in samples {
            scenario.angle_rad.push(state.angle_rad);
            scenario.speed_rad_s.push(state.speed_rad_s);
            scenario.acceleration_rad_s2.push(state.acceleration_rad_s2);
            scenario.y_c.push(y_c);
            scenario.y_s.push(y_s);
        }
        Ok(scenario)
    }

    /// The samples [`Scenario::generate`] stores, one at a time: their number, and each
    /// sample's true state and `(y_c, y_s)`. A study's run tracks them as they are drawn, so
    /// that it never holds its series (48 MB for 1e6 samples, allocated and page-faulted
    /// anew by every run).
    pub(crate) fn stream(
        profile: &MotionProfile,
        sensor: &SensorModel,
        sample_period_s: f64,
        seed: u64,
    ) -> Result<(usize, impl Iterator<Item = ScenarioSample>), Error> {
        let ts = positive(sample_period_s, Argument::SamplePeriod)?;
        sensor.validate()?;
        let (n, truth) = profile.sample(ts)?;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let normal = Normal::new(0.0, sensor.noise_std)
            .map_err(|_| Error::NotFinite(Argument::SensorNoiseStd))?;
        let sensor = *sensor;
        let samples = truth.map(move |state| {
            let (w_c, w_s) = (normal.sample(&mut rng), normal.sample(&mut rng));
            (state, sensor.signals(state.angle_rad, w_c, w_s))
        });
        Ok((n, samples))
    }

    /// A scenario of recorded samples: the true angle `angle_rad` (every sample's finite:
    /// the metrics compare each estimate with it), the signals `y_c`, `y_s` and, if known,
    /// the true speed, at `sample_period_s`; the speed unknown and the acceleration are NaN.
    /// Refuses, naming the argument, a sample period that is not finite and positive, an
    /// angle that is not finite and series of other lengths than the angle's.
    ///
    /// ```
    /// use angletrack::Scenario;
    /// let s = Scenario::from_arrays(1e-3, vec![0.0, 0.1], vec![1.0, 0.99], vec![0.0, 0.1], None)?;
    /// assert_eq!(s.time_s, [0.0, 1e-3]);
    /// let e = Scenario::from_arrays(1e-3, vec![0.0, f64::NAN], vec![1.0; 2], vec![0.0; 2], None);
    /// assert_eq!(e.unwrap_err().argument, "angle_rad");
    /// # Ok::<(), angletrack::ArgumentError>(())
    /// ```
    pub fn from_arrays(
        sample_period_s: f64,
        angle_rad: Vec<f64>,
        y_c: Vec<f64>,
        y_s: Vec<f64>,
        speed_rad_s: Option<Vec<f64>>,
    ) -> Result<Self, ArgumentError> {
        if !(sample_period_s.is_finite() && sample_period_s > 0.0) {
            return Err(ArgumentError::new(
                "sample_period_s",
                "must be finite and positive",
            ));
        }
        if let Some((k, v)) = angle_rad.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(ArgumentError::new(
                "angle_rad",
                format!(
                    "{v} at index {k} is not finite: the reference angle must be known at every sample"
                ),
            ));
        }
        let n = angle_rad.len();
        let lengths = [("y_c", y_c.len()), ("y_s", y_s.len())]
            .into_iter()
            .chain(speed_rad_s.as_ref().map(|v| ("speed_rad_s", v.len())));
        for (argument, len) in lengths {
            if len != n {
                return Err(ArgumentError::new(
                    argument,
                    format!("has {len} samples but angle_rad has {n}: they must be equal"),
                ));
            }
        }
        Ok(Scenario {
            sample_period_s,
            time_s: (0..n).map(|k| k as f64 * sample_period_s).collect(),
            angle_rad,
            speed_rad_s: speed_rad_s.unwrap_or_else(|| vec![f64::NAN; n]),
            acceleration_rad_s2: vec![f64::NAN; n],
            y_c,
            y_s,
        })
    }

    /// The number of samples.
    pub fn len(&self) -> usize {
        self.time_s.len()
    }

    /// `true` without samples.
    pub fn is_empty(&self) -> bool {
        self.time_s.is_empty()
    }
}
