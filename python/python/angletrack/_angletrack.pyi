"""Type stubs of the compiled extension ``angletrack._angletrack``."""

import os
from collections.abc import Iterable, Sequence
from typing import Any, Literal, Optional, Protocol, TypedDict, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str

_Samples = Union[npt.NDArray[np.float32], npt.NDArray[np.float64], Sequence[float]]
#: Samples an observer accepts: floats, or raw ADC counts (int16, uint16, int32) scaled
#: exactly (minus ``adc_mid_scale``, divided by ``adc_counts_per_unit``; see ``Observer``).
_Signal = Union[
    _Samples, npt.NDArray[np.int16], npt.NDArray[np.uint16], npt.NDArray[np.int32], npt.NDArray[np.int64]
]
_CalibrationMode = Optional[Literal["learn", "frozen", "off"]]
_DType = Union[type[np.float32], type[np.float64], np.dtype, Literal["float32", "float64"], None]
_SinCos = Optional[Literal["fast", "exact"]]
#: The float type of the constants written for firmware.
_FloatType = Literal["float32", "float64"]
_Language = Literal["c", "rust"]
_SensorParameters = tuple[float, float, float, float, float]

class _FixedConstants(TypedDict):
    """The fixed-point constants of a design (``Design.fixed_constants()``)."""

    multiplier: list[int]
    acceleration_shift: int
    quantised_gains: list[float]
    sample_period_s: float

class _LearnedCalibration(TypedDict):
    """An angle calibration as the extension gives it (``_CaptureCalibrator.finish``, a
    calibration file): the sensor's ``(offset_c, offset_s, amplitude_c, amplitude_s, quadrature_rad)``,
    the angle error's ``cos`` and ``sin`` coefficients (8 each, rad) and what the learning
    saw (NaN where unknown): the method, each order's quality and the warnings."""

    sensor: _SensorParameters
    cos: list[float]
    sin: list[float]
    speed_rad_s: float
    turns: float
    error_rms_rad: float
    residual_rms_rad: float
    method: str
    orders: list[_OrderQuality]
    warnings: list[str]

class _OrderQuality(TypedDict):
    """One harmonic order of a learned angle error: its amplitude (rad), the standard
    deviation of each of its coefficients (rad) and whether it was learned."""

    order: int
    amplitude_rad: float
    uncertainty_rad: float
    status: str

class Gains:
    """Discrete gains ``(l1, l2[, l3])`` of the scaled-state recursion and the sample
    period (s), checked against the stability region of the discrete loop."""

    def __init__(self, gains: Sequence[float], sample_period_s: float) -> None: ...
    @staticmethod
    def from_loop_polynomial(coefficients: Sequence[float], sample_period_s: float) -> Gains: ...
    @property
    def gains(self) -> list[float]:
        """The discrete gains (dimensionless)."""
    @property
    def loop_polynomial(self) -> list[float]:
        """Closed-loop characteristic polynomial in ``s = z - 1``, lowest first, monic."""
    @property
    def sample_period_s(self) -> float:
        """Sample period (s)."""
    @property
    def sample_rate_hz(self) -> float:
        """Sample rate (Hz)."""
    @property
    def order(self) -> int:
        """2 (angle, speed) or 3 (angle, speed, acceleration)."""
    def __eq__(self, other: object) -> bool: ...

class ConfigError(ValueError):
    """An argument the extension refused (its value, range, shape or length, or an unknown
    name); the message starts with the argument's name."""

    parameter: str
    """The argument's name as the caller spelled it (``"sample_period_s"``, ``"gains"``)."""

class _SelectedEstimates:
    """What a batch run with ``outputs=`` returns (an ``Estimates`` at run time): the
    quantities named in ``outputs`` as arrays, the others ``None``. ``position`` is float64;
    the others have the input's dtype."""

    @property
    def angle(self) -> Optional[npt.NDArray[np.floating]]:
        """Angle (rad), wrapped to [-pi, pi)."""
    @property
    def position(self) -> Optional[npt.NDArray[np.float64]]:
        """Multi-turn position ``turns * 2 pi + angle`` (rad)."""
    @property
    def speed(self) -> Optional[npt.NDArray[np.floating]]:
        """Speed (rad/s)."""
    @property
    def acceleration(self) -> Optional[npt.NDArray[np.floating]]:
        """Acceleration (rad/s^2); 0 at order 2."""
    @property
    def phase_error(self) -> Optional[npt.NDArray[np.floating]]:
        """Normalised phase-detector output per sample (about the sine of the angle error)."""
    @property
    def faults(self) -> Optional[npt.NDArray[np.uint8]]:
        """Fault flags per sample (see ``angletrack.Faults``)."""
    @property
    def dtype(self) -> str:
        """'float32' or 'float64'."""
    @property
    def len(self) -> int:
        """Number of samples."""
    def __len__(self) -> int: ...

class Estimates(_SelectedEstimates):
    """Estimates of a run, one array per quantity. ``position`` is float64; the others
    have the input's dtype. Every array is present, except in what a batch run with
    ``outputs=`` returns (typed ``_SelectedEstimates``), where a quantity left out is
    ``None``."""

    @property
    def angle(self) -> npt.NDArray[np.floating]: ...
    @property
    def position(self) -> npt.NDArray[np.float64]: ...
    @property
    def speed(self) -> npt.NDArray[np.floating]: ...
    @property
    def acceleration(self) -> npt.NDArray[np.floating]: ...
    @property
    def phase_error(self) -> npt.NDArray[np.floating]: ...
    @property
    def faults(self) -> npt.NDArray[np.uint8]: ...

class Estimate:
    """The quantities of ``Estimates`` after the last sample, as Python scalars, with the
    whole ``turns`` counted since initialisation."""

    angle: float
    turns: int
    position: float
    speed: float
    acceleration: float
    phase_error: float
    faults: int

class _RunSettings:
    """What an ``Observer`` or an ``ObserverBatch`` runs with."""

    @property
    def gains(self) -> Gains: ...
    @property
    def dtype(self) -> Literal["float32", "float64"]: ...
    @property
    def sin_cos(self) -> Literal["fast", "exact"]: ...
    @property
    def order(self) -> int: ...
    @property
    def sample_period_s(self) -> float: ...

class SensorCalibration:
    """A sensor's calibration, ``y_c = offset_c + amplitude_c cos(theta)``,
    ``y_s = offset_s + amplitude_s sin(theta + quadrature_rad)``, in the observer's input
    units and radians; checked (``ConfigError`` naming the field: amplitudes positive,
    ``|quadrature_rad| < pi/4``, all finite)."""

    offset_c: float
    offset_s: float
    amplitude_c: float
    amplitude_s: float
    quadrature_rad: float
    def __init__(
        self, *, offset_c: float = 0.0, offset_s: float = 0.0, amplitude_c: float = 1.0,
        amplitude_s: float = 1.0, quadrature_rad: float = 0.0,
    ) -> None: ...
    @property
    def amplitude_ratio(self) -> float:
        """The gain imbalance ``amplitude_s / amplitude_c``."""
    def to_dict(self) -> dict[str, float]:
        """The five fields (for ``json.dumps``)."""
    @staticmethod
    def from_dict(d: dict[str, float]) -> SensorCalibration:
        """From a dict holding the five fields, checked as the constructor."""
    def __eq__(self, other: object) -> bool: ...

class Observer(_RunSettings):
    """An observer whose state persists between calls: chunked input gives exactly the
    result of one call.

    Integer samples (int16, uint16, int32, int64) are raw ADC counts: minus ``adc_mid_scale``
    and divided by ``adc_counts_per_unit`` (default 1), exactly; nothing is read from the
    samples, which depend on the chunks. Without ``adc_mid_scale``: int16 and int32 counts
    (or any with ``adc_signed=True``) are signed, mid-scale 0; uint16 counts (or any with
    ``adc_signed=False``) are a ``ConfigError`` naming ``adc_mid_scale``; int64 counts without
    ``adc_signed`` are a ``ConfigError`` naming it. The ADC arguments apply to counts only:
    float samples with any given are refused (``ConfigError`` naming it), not tracked
    unscaled. ``fault_thresholds=None``: the defaults, those of amplitude 1 in the observer's
    units (floats of amplitude about 1, or counts over ``adc_counts_per_unit``, their
    amplitude in counts); raw counts in counts without thresholds are a ``ConfigError``
    naming ``fault_thresholds``: state ``FaultThresholds(nominal_amplitude=A)``, ``A`` in
    counts (``capture_fault_thresholds`` measures it on a capture's first samples). ``calibration``: ``None`` (off), ``"learn"`` (correct
    and learn offsets, gain imbalance and quadrature while tracking, from
    ``initial_calibration`` if given) or ``"frozen"`` (apply ``initial_calibration``);
    ``initial_calibration`` with the calibration off is a ``ConfigError`` naming it.
    ``adc_range=(min, max)`` (the samples' units, counts for integer samples): a sample at
    or beyond it in either channel is flagged ``Faults.FRONT_END``, one clipped in both is
    coasted through; ``measure_adc_range=True`` (without ``adc_range``): the same against the
    rails measured as the samples come (an extreme held flat over ``HELD_RAIL_SAMPLES``
    samples while the other channel moves, the samples piled up there; the core's
    ``HeldRailCheck``). ``winding_amplitude``: the windings' nominal envelope amplitude (1 for
    demodulated pairs), against which a winding open or shorted is flagged and coasted
    through."""

    def __init__(
        self, gains: Gains, *, dtype: _DType = None, sin_cos: _SinCos = None,
        fault_thresholds: Optional[FaultThresholds] = None,
        calibration: _CalibrationMode = None,
        initial_calibration: Optional[SensorCalibration] = None,
        adc_mid_scale: Optional[int] = None,
        adc_counts_per_unit: Optional[float] = None,
        adc_signed: Optional[bool] = None,
        adc_range: Optional[tuple[float, float]] = None,
        measure_adc_range: bool = False,
        winding_amplitude: Optional[float] = None,
    ) -> None: ...
    def update(self, y_c: _Signal, y_s: _Signal,
               front_end_faults: Optional[npt.NDArray[np.uint8]] = None) -> Estimates:
        """Runs over 1-D samples of the observer's dtype, or raw counts of one integer
        dtype; GIL released. ``front_end_faults`` (one per sample, the bits of
        ``DemodulatedPairs.faults``): the observer coasts through samples whose faults
        invalidate them (loss of excitation, a winding open or shorted)."""
    @property
    def latched_front_end_faults(self) -> int:
        """The front-end faults latched (bits of ``DemodulatedPairs.faults``; 16 a winding)."""
    @property
    def estimate(self) -> Estimate: ...
    def reset(self) -> None: ...
    def initialise(self, y_c: float, y_s: float) -> None:
        """Angle from one sample; ``ConfigError`` if a value is not finite."""
    def set_state(self, angle_rad: float, speed_rad_s: float = 0.0, acceleration_rad_s2: float = 0.0) -> None:
        """Starts from a known state; ``ConfigError`` naming a value that is not finite, an
        angle of 2^31 turns or more, a speed beyond ``pi / sample_period_s``, an
        acceleration beyond ``pi / sample_period_s**2`` or any but 0 at order 2."""
    @property
    def is_initialised(self) -> bool: ...
    @property
    def latched_faults(self) -> int: ...
    def clear_faults(self) -> int: ...
    @property
    def fault_thresholds(self) -> Optional[FaultThresholds]:
        """The thresholds the observer runs with (given, or the defaults)."""
    @property
    def amplitude(self) -> float:
        """The magnitude ``sqrt(y_c^2 + y_s^2)`` the loop normalises by (input units)."""
    @property
    def calibration(self) -> SensorCalibration:
        """The calibration applied (learned so far, or given)."""
    @property
    def calibration_mode(self) -> Literal["off", "learn", "frozen"]: ...
    @property
    def calibration_turns_learned(self) -> int: ...
    @property
    def calibration_status(self) -> Literal["finding-centre", "centred", "stalled"]: ...
    def set_calibration(
        self, calibration: _CalibrationMode, initial_calibration: Optional[SensorCalibration] = None
    ) -> None:
        """As the constructor's arguments (``initial_calibration`` refused with ``"off"`` or
        ``None``); the state is kept."""

def track(
    gains: Gains, y_c: _Signal, y_s: _Signal, *, sin_cos: _SinCos = None,
    fault_thresholds: Optional[FaultThresholds] = None,
    adc_mid_scale: Optional[int] = None,
    adc_counts_per_unit: Optional[float] = None,
    adc_signed: Optional[bool] = None,
    adc_range: Optional[tuple[float, float]] = None,
) -> Estimates:
    """Runs a fresh observer over the whole capture in the samples' own dtype (float32 or
    float64; float64 for raw counts, scaled as ``Observer`` does, except that what is not
    stated is read from the whole capture by the crate's ``capture_counts``: uint16 counts
    or ``adc_signed=False`` lose the offset-binary mid-scale of the largest sample; int64
    counts are signed with a negative sample, unsigned when both channels swing about one
    offset-binary mid-scale, else a ``ConfigError`` naming ``adc_signed``). An ADC argument
    with float samples is a ``ConfigError`` naming it. ``fault_thresholds=None`` scales the
    diagnostics to the capture's amplitude (``capture_fault_thresholds``)."""

def capture_fault_thresholds(y_c: _Samples, y_s: _Samples, *, pole_pairs: int = 1) -> FaultThresholds:
    """The thresholds of a capture whose first samples these are:
    ``FaultThresholds(nominal_amplitude=A)``, ``A`` the median ``sqrt(y_c^2 + y_s^2)`` of
    its first 4096 samples (the defaults when not positive), ``tracking_error`` above
    their angle noise (8 times it, at least 0.05), the roundness check on the circle they
    show; with ``pole_pairs`` (a motor's) the angle-error levels divided by them. What
    ``track`` measures, and what a caller feeding the capture to an ``Observer`` in chunks
    states."""

#: Samples the fixed-point observer accepts: int16 counts (mid-scale removed), or integers
#: within int16 (a list); no other dtype is converted.
_Counts = Union[npt.NDArray[np.int16], npt.NDArray[np.int64], npt.NDArray[np.int32], Sequence[int]]

class FixedEstimate:
    """What a ``FixedObserver`` knows after its last sample: the firmware's integers and the
    same in physical units."""

    angle: int
    """Binary angle (2^32 per turn, -2^31 is -pi)."""
    turns: int
    """Whole turns since initialisation: the position is ``turns + angle / 2^32`` turns."""
    speed: int
    """Speed (2^-32 turn per sample)."""
    acceleration: int
    """Acceleration (2^-63 turn per sample^2); 0 for a 2nd-order observer."""
    phase_error: int
    """Normalised phase error (Q15: 2^15 is 1)."""
    faults: int
    """Fault flags of the monitor's last window (bits, see ``Faults``)."""
    position_rad: float
    """Multi-turn position (rad)."""
    speed_rad_s: float
    """Speed (rad/s)."""
    acceleration_rad_s2: float
    """Acceleration (rad/s^2)."""

class FixedEstimates:
    """The estimates of ``FixedObserver.update``, one array per quantity, one element per
    sample: the firmware's integers and the same in physical units (float64)."""

    angle: npt.NDArray[np.int32]
    """Binary angle (2^32 per turn, -2^31 is -pi)."""
    turns: npt.NDArray[np.int64]
    """Whole turns since initialisation."""
    speed: npt.NDArray[np.int32]
    """Speed (2^-32 turn per sample)."""
    acceleration: npt.NDArray[np.int64]
    """Acceleration (2^-63 turn per sample^2); 0 for a 2nd-order observer."""
    phase_error: npt.NDArray[np.int32]
    """Normalised phase error (Q15: 2^15 is 1)."""
    faults: npt.NDArray[np.uint8]
    """Fault flags of the monitor's window each sample ends in (bits, see ``Faults``)."""
    position_rad: npt.NDArray[np.float64]
    """Multi-turn position ``2 pi (turns + angle / 2^32)`` (rad)."""
    speed_rad_s: npt.NDArray[np.float64]
    """Speed (rad/s)."""
    acceleration_rad_s2: npt.NDArray[np.float64]
    """Acceleration (rad/s^2)."""
    def __len__(self) -> int: ...

class _AngleCalibrationLike(Protocol):
    """What ``FixedObserver`` reads of a ``harmonics.Calibration``."""

    @property
    def sensor(self) -> tuple[float, float, float, float, float]: ...
    @property
    def cos(self) -> Sequence[float]: ...
    @property
    def sin(self) -> Sequence[float]: ...

class FixedObserver:
    """The core's fixed-point observer (docs/theory.md §14): bit for bit what a Cortex-M0/M4
    firmware running ``FixedGains::update`` computes, on int16 samples (counts, mid-scale
    removed), its state kept between calls (chunks give exactly one call's result).

    ``design`` (a ``Design`` or ``Gains``) is quantised by the core (``ConfigError`` naming
    the gain). ``nominal_amplitude`` (counts, 16384 to 46341) sets the monitor's
    thresholds; ``None`` turns it off. The chain's stages, in integers: ``mid_scale_counts``
    removed and the counts shifted left by ``input_shift`` bits (``AdcCounts``), then
    ``calibration`` (learned in float on the counts before the shift): a
    ``SensorCalibration`` (``FixedCalibration``), or a ``harmonics.Calibration`` (also its
    harmonics as the core's 256-entry ``FixedAngleCorrectionTable``). ``adc_range=(min, max)``
    (integer codes as the samples come): a sample at or beyond it in either channel is
    flagged ``Faults.FRONT_END``, one clipped in both coasted through; or
    ``measure_adc_range=True``: the same against the rails measured as the samples come (the
    core's ``HeldRailCheck``, as the C chain)."""

    def __init__(
        self,
        design: Union[Design, Gains],
        *,
        nominal_amplitude: Optional[float] = 16384.0,
        calibration: Union[None, SensorCalibration, _AngleCalibrationLike] = None,
        mid_scale_counts: int = 0,
        input_shift: int = 0,
        adc_range: Optional[tuple[int, int]] = None,
        measure_adc_range: bool = False,
    ) -> None: ...
    @staticmethod
    def from_constants(
        constants: _FixedConstants,
        sample_period_s: float,
        *,
        nominal_amplitude: Optional[float] = 16384.0,
        calibration: Union[None, SensorCalibration, _AngleCalibrationLike] = None,
        mid_scale_counts: int = 0,
        input_shift: int = 0,
        adc_range: Optional[tuple[int, int]] = None,
        measure_adc_range: bool = False,
    ) -> FixedObserver:
        """The observer of the integers a firmware embeds: the dict ``Design.fixed_constants()``
        returns (``multiplier``, ``acceleration_shift``; other keys ignored), checked again
        (``ConfigError``, parameter ``constants``, naming the gain)."""
    def update(self, y_c: _Counts, y_s: _Counts) -> FixedEstimates:
        """Runs over the int16 samples (1-D, equal lengths; an array of another integer
        dtype, such as numpy's default int64, is read as int16 when every value fits;
        ``TypeError`` for floats, ``ConfigError`` for a value outside int16 or unequal
        lengths) and returns the estimates of every sample."""
    @property
    def latched_front_end_faults(self) -> int:
        """The front-end faults latched (4: a sample clipped)."""
    @property
    def estimate(self) -> FixedEstimate:
        """The estimate after the last sample."""
    def reset(self) -> None:
        """Forgets the state: the next sample sets the angle from its ``atan2``."""
    @property
    def constants(self) -> _FixedConstants:
        """The integer constants (as ``Design.fixed_constants()``)."""
    @property
    def gains(self) -> list[float]:
        """The gains the integers represent (the loop that runs)."""
    @property
    def sample_period_s(self) -> float:
        """The sample period (s)."""
    @property
    def order(self) -> int:
        """The observer order: 2 or 3."""
    @property
    def latched_faults(self) -> int:
        """The faults latched since they were last cleared (bits, see ``Faults``)."""
    def clear_faults(self) -> int:
        """Returns the latched faults (bits) and clears them."""

def measured_adc_range(y_c: _Samples, y_s: _Samples) -> Optional[tuple[float, float]]:
    """The ADC range measured on the samples: each extreme of both channels that is a rail
    (held flat over ``HELD_RAIL_SAMPLES`` consecutive samples of a channel, and reached by
    more than four times the samples of the half-percent band just inside it); an extreme
    that is not is put one span beyond. ``None`` when neither is a rail."""

#: Consecutive samples of a channel at an extreme that make it a rail.
HELD_RAIL_SAMPLES: int

class WindingsPlan:
    """How a capture of raw windings is demodulated (``plan_windings``)."""

    adc_rate_hz: float
    samples_per_period: float
    carrier_amplitude_counts: float
    adc_min_code: float
    adc_max_code: float
    adc_range_source: str
    """``"stated"``, ``"measured: extremes held flat"`` or ``"guessed"``."""

def plan_windings(
    first_c: _Samples,
    first_s: _Samples,
    *,
    carrier_hz: float,
    capture_hz: Optional[float] = None,
    samples_per_period: Optional[float] = None,
    carrier_amplitude_counts: Optional[float] = None,
    adc_range: Optional[tuple[float, float]] = None,
) -> WindingsPlan:
    """The ADC rate, samples per period, amplitude and ADC range of a capture of raw windings
    from its first samples, as stated or measured; a ratio the time column contradicts (1 %)
    or a carrier 2 % from the one measured is refused, naming both values. ``ConfigError``
    for unequal lengths (``first_s``), an amplitude not a positive number of counts up to
    2^31, or a range not two finite numbers in order."""

class CountsExtremes:
    """Each channel's extremes of a capture of whole counts, gathered chunk by chunk: what
    ``capture_counts`` reads of the whole capture."""

    def __init__(self) -> None: ...
    def add(self, y_c: _Samples, y_s: _Samples) -> None:
        """Adds a chunk (1-D arrays of equal lengths; non-finite samples left out)."""
    @property
    def channels(self) -> list[Optional[tuple[float, float]]]:
        """``y_c``'s and ``y_s``'s ``(lowest, highest)``, ``None`` for a channel without a sample."""

def capture_counts(extremes: CountsExtremes, *, signed: Optional[bool] = None, bits: Optional[int] = None,
                   unsigned_type: bool = False,
                   state_with: str = "give adc_signed=True or adc_signed=False") -> tuple[bool, int]:
    """``(signed, mid_scale)`` of a whole capture of counts by the crate's rule: the
    signedness stated, else unsigned for an unsigned type, signed for a negative sample
    anywhere, unsigned when both channels swing about one offset-binary mid-scale; else
    ``ConfigError`` (parameter ``adc_signed``, the message ending with ``state_with``).
    Unsigned counts are centred on ``2^(bits-1)``, else on the offset-binary mid-scale of
    the largest sample (``angletrack::offset_binary_mid_scale``) (``ConfigError`` naming ``capture`` for counts no ADC gives, naming
    ``adc_bits`` outside 2 to 53)."""

#: The estimates a batch may be asked for (``outputs=``).
_OutputName = Literal["angle", "position", "speed", "acceleration", "phase_error", "faults"]
_Outputs = Union[_OutputName, Iterable[_OutputName], None]

_ChannelSamples = Union[npt.NDArray[np.float32], npt.NDArray[np.float64], Sequence[Sequence[float]]]

class ObserverBatch(_RunSettings):
    """Many observers on one gain set, run 8 at a time side by side; 2-D arrays
    (channels x samples). Each channel equals an ``Observer`` with
    ``FaultThresholds.disabled()`` (bad samples rejected, no fault monitor); the state
    persists between calls. The samples are floats of amplitude about 1: one of magnitude
    ``sqrt(y_c^2 + y_s^2)`` above 4 (``max_input_amplitude``) is rejected as
    ``BAD_SAMPLE``. Raw ADC counts (an integer dtype) are a ``TypeError``: scale them
    first, ``(counts - mid_scale) / amplitude``."""

    def __init__(
        self, gains: Gains, channels: int, *, dtype: _DType = None, sin_cos: _SinCos = None,
    ) -> None: ...
    @overload
    def update(self, y_c: _ChannelSamples, y_s: _ChannelSamples, *, outputs: None = None) -> Estimates: ...
    @overload
    def update(
        self, y_c: _ChannelSamples, y_s: _ChannelSamples, *, outputs: _Outputs
    ) -> _SelectedEstimates:
        """Runs over 2-D samples (channels x samples) of the batch's dtype; GIL released.
        The arrays of the result have the inputs' shape. ``outputs`` (e.g. ``("angle",
        "speed")``, default all) names the estimates computed and returned; the others are
        ``None``. An unknown name is a ``ConfigError`` naming ``outputs``."""
    @property
    def channels(self) -> int: ...

@overload
def track_batch(
    gains: Gains, y_c: _ChannelSamples, y_s: _ChannelSamples, *, sin_cos: _SinCos = None,
    outputs: None = None,
) -> Estimates: ...
@overload
def track_batch(
    gains: Gains, y_c: _ChannelSamples, y_s: _ChannelSamples, *, sin_cos: _SinCos = None,
    outputs: _Outputs,
) -> _SelectedEstimates:
    """Runs a fresh ``ObserverBatch`` over 2-D samples (channels x samples) in their own
    dtype (float32 or float64, amplitude about 1, as ``ObserverBatch`` takes); the result's arrays have the inputs' shape. Only the estimates named in
    ``outputs`` (e.g. ``("angle", "speed")``, default all) are computed and allocated, the
    others are ``None``: ask for what you use, the run's memory traffic follows."""

# ----------------------------------------------------------------- diagnostics

FAULT_BITS: list[tuple[str, int]]
FRONT_END_FAULT_BITS: list[tuple[str, int]]

class FaultThresholds:
    """Diagnostics thresholds (defaults for ``nominal_amplitude``)."""

    def __init__(
        self,
        *,
        nominal_amplitude: float = 1.0,
        max_input_amplitude: Optional[float] = None,
        loss_of_signal: Optional[float] = None,
        degradation_low: Optional[float] = None,
        degradation_high: Optional[float] = None,
        loss_of_tracking: Optional[float] = None,
        tracking_error: Optional[float] = None,
        max_speed_rad_s: Optional[float] = None,
        filter_factor: Optional[float] = None,
        false_lock: Optional[float] = None,
        monitor: bool = True,
        re_acquire: bool = True,
        magnitude_tolerance: Optional[float] = None,
    ) -> None: ...
    @staticmethod
    def disabled() -> FaultThresholds:
        """The bare loop: input check only, no flags, no re-acquisition."""
    nominal_amplitude: float
    max_input_amplitude: float
    loss_of_signal: float
    degradation_low: float
    degradation_high: float
    loss_of_tracking: float
    tracking_error: float
    max_speed_rad_s: Optional[float]
    filter_factor: float
    false_lock: float
    monitor: bool
    re_acquire: bool
    magnitude_tolerance: Optional[float]

# ----------------------------------------------------------------- design

_Discretisation = Literal["pole_matching", "forward_euler", "tustin"]

LARGE_STEP_RAD: float
SETTLING_BAND: float
MAX_POLE_TIMES_PERIOD: float

class StepResponse:
    overshoot: float
    """Overshoot, fraction of the step."""
    settling_time_s: float
    """2 % settling time (s)."""

class KalmanSolution:
    process_noise_q: float
    measurement_noise_r: float
    predicted_covariance: list[list[float]]
    covariance: list[list[float]]
    angle_floor_rad: float
    speed_floor_rad_s: float

class PredictedError:
    angle_rms_rad: float
    speed_rms_rad_s: float

class DesignReport:
    """The design's datasheet; ``repr``/``str`` render it as a table."""

    method: str
    discretisation: Optional[str]
    order: int
    sample_period_s: float
    gains: list[float]
    discrete_poles: list[complex]
    continuous_equivalent_poles: list[complex]
    design_poles: list[complex]
    pole_shift: Optional[float]
    bandwidth_hz: Optional[float]
    acceleration_constant_per_s2: Optional[float]
    continuous_acceleration_constant_per_s2: Optional[float]
    error_per_unit_jerk_s3: Optional[float]
    continuous_error_per_unit_jerk_s3: Optional[float]
    sensor_noise_std: float
    angle_error_rms_rad: float
    speed_error_rms_rad_s: float
    kalman_angle_floor_rad: Optional[float]
    kalman_speed_floor_rad_s: Optional[float]
    linear_step: StepResponse
    continuous_step: Optional[StepResponse]
    large_step: StepResponse
    large_step_with_diagnostics: StepResponse
    large_step_final_rad: float
    max_speed_rad_s: float
    acquisition_speed_rad_s: float

class Design:
    """A designed gain set (float64) with what it was designed from."""

    @staticmethod
    def from_gains(gains: Gains) -> Design: ...
    gains: Gains
    method: str
    discretisation: Optional[str]
    continuous_poles: list[complex]
    continuous_gains: Optional[list[float]]
    """``(k_a, k_b[, k_c])``, in the order of ``gains`` (angle first)."""
    continuous_loop_polynomial: Optional[list[float]]
    """The continuous loop polynomial, lowest power first, monic (``continuous_gains`` reversed)."""
    kalman: Optional[KalmanSolution]
    sample_period_s: float
    order: int
    def report(self, sensor_noise_std: float = 0.0) -> DesignReport: ...
    def fixed_constants(self) -> _FixedConstants: ...

def predicted_error(gains: Gains, sensor_noise_std: float, process_noise_q: float = 0.0) -> PredictedError: ...
def predicted_error_on_kalman_model(
    gains: Gains, sensor_noise_std: float, process_noise_q: float
) -> Optional[PredictedError]:
    """The errors on the Kalman ATO's model (noise and random jerk); ``None`` for a 2nd-order loop."""
def closed_loop_response(
    gains: Gains, frequencies_hz: Union[Sequence[float], npt.NDArray[np.float64]]
) -> npt.NDArray[np.complex128]:
    """``H(z) = X1_e / Theta`` of the discrete loop at ``z = exp(j 2 pi f Ts)`` for each
    frequency (Hz): 1 at 0 Hz, ``|H| = 1/sqrt(2)`` at the report's ``bandwidth_hz``."""
def max_trackable_speed_rad_s(sample_period_s: float) -> float:
    """``pi / Ts`` (docs/theory.md §9)."""
def second_order_from_tracking_error_sampled(
    max_error_rad: float, acceleration_rad_s2: float, overshoot: float, sample_period_s: float
) -> Design:
    """The sampled loop has exactly that error at that acceleration, and that overshoot."""
def second_order_from_tracking_error(
    max_error_rad: float, acceleration_rad_s2: float, damping: float, sample_period_s: float,
    discretisation: _Discretisation = "pole_matching",
) -> Design: ...
def second_order_from_bandwidth(
    bandwidth_hz: float, damping: float, sample_period_s: float, discretisation: _Discretisation = "pole_matching"
) -> Design: ...
def second_order_butterworth(
    time_constant_s: float, sample_period_s: float, discretisation: _Discretisation = "pole_matching"
) -> Design: ...
def second_order_bandwidth_ratio(damping: float) -> float: ...
def third_order_from_poles(
    pole_ratio: float, pole_time_constant_s: float, pole_frequency_ratio: float, sample_period_s: float,
    discretisation: _Discretisation = "pole_matching",
) -> Design: ...
def third_order_butterworth(
    time_constant_s: float, sample_period_s: float, discretisation: _Discretisation = "pole_matching"
) -> Design: ...
def third_order_from_overshoot(
    overshoot: float, settling_time_s: float, pole_frequency_ratio: float, sample_period_s: float,
    discretisation: _Discretisation = "pole_matching",
) -> Design: ...
def kalman(process_noise_q: float, measurement_noise_r: float, sample_period_s: float) -> Design: ...
def kalman_from_jerk_std(jerk_std_rad_s3: float, sensor_noise_std: float, sample_period_s: float) -> Design: ...
def kalman_from_jerk_density(jerk_density_rad2_s5: float, sensor_noise_std: float, sample_period_s: float) -> Design: ...
def design_from_capture(
    y_c: npt.NDArray[np.float64],
    y_s: npt.NDArray[np.float64],
    sample_period_s: float,
    *,
    reference_angle_rad: Optional[npt.NDArray[np.float64]] = None,
    quantisation_step: Optional[float] = None,
    max_overshoot: Optional[float] = None,
    min_bandwidth_hz: Optional[float] = None,
    speed_step_rad_s: Optional[float] = None,
    number_type: str = "f32",
    grid_points: int = 31,
) -> dict[str, Any]:
    """The observer chosen from a capture (docs/guide/design-from-capture.md): the sensor
    noise and the motion estimated from ``y_c``, ``y_s`` (and the reference angle if
    given), the design of least predicted RMS angle error over the 2nd-order, 3rd-order and
    Kalman observers and ``grid_points`` bandwidths each, under the constraints. Returns
    ``design`` (a :class:`Design`), ``tracker_json`` (its tracker file, with
    ``predicted_error_rms_rad``), ``predicted_error_rms_rad``, ``chosen``, ``runners_up``
    and ``candidates`` (dicts: ``observer``, ``bandwidth_hz``, ``gains``,
    ``predicted_error_rms_rad``, ``noise_rad``, ``lag_rad``, ``number_type_rad``,
    ``refused_by``), ``noise`` and ``motion`` (the estimates, each uncertain one as
    ``{"value", "std"}``; the jerk used, the jerk by third differences and whether the
    autocovariance least-squares one was used), ``als`` (the autocovariance least-squares
    estimate of the Kalman model's jerk and noise from a first-pass loop's innovations, with
    that loop's bandwidth and the lags fitted; ``None`` when the noise is coloured) and
    ``spectra`` (``frequency_hz``, ``noise_rad2_per_hz``,
    ``motion_rad2_per_hz``). A capture that cannot support the estimates (too short, at
    standstill, too few turns) raises ``ValueError`` saying which."""

# ----------------------------------------------------------------- the paper

PAPER_FIVE_PERCENT_DAMPING: float
PAPER_BUTTERWORTH_DAMPING: float
PAPER_POLE_RATIO: float
PAPER_POLE_FREQUENCY_RATIO: float
PAPER_OVERSHOOT_SAMPLE_PERIOD_S: float
PAPER_COMPARISON_SAMPLE_PERIOD_S: float
PAPER_COMPARISON_BANDWIDTH_HZ: float
PAPER_COMPARISON_SENSOR_NOISE_STD: float

class PaperSetting:
    """One of the four settings whose step-response overshoot the paper quotes."""

    name: str
    paper_overshoot_percent: float
    design: Design

def paper_settings(
    sample_period_s: float = ..., discretisation: _Discretisation = "pole_matching"
) -> list[PaperSetting]:
    """The paper's four settings, in its order (by default at 100 kHz)."""
def paper_compared_observers() -> list[tuple[str, Design]]:
    """The 2nd-order, 3rd-order and Kalman ATOs the report compares, ``(name, design)``."""
def paper_benchmark_gains() -> list[Gains]:
    """The benchmarks' 10 kHz gains of the 2nd-order, 3rd-order and Kalman ATOs."""

# ----------------------------------------------------------------- scenarios and metrics

class MotionProfile:
    def __init__(self, initial_angle_rad: float = 0.0, initial_speed_rad_s: float = 0.0) -> None: ...
    def constant_speed(self, speed_rad_s: float, duration_s: float) -> MotionProfile: ...
    def constant_acceleration(self, acceleration_rad_s2: float, duration_s: float) -> MotionProfile: ...
    def step(self, step_rad: float, duration_s: float) -> MotionProfile: ...
    def trapezoidal(self, distance_rad: float, max_speed_rad_s: float, max_acceleration_rad_s2: float) -> MotionProfile: ...
    def s_curve(
        self, distance_rad: float, max_speed_rad_s: float, max_acceleration_rad_s2: float, max_jerk_rad_s3: float
    ) -> MotionProfile: ...
    def speed_ripple(self, ripple_rad_s: float, frequency_hz: float, duration_s: float) -> MotionProfile: ...
    def reversal(self, acceleration_rad_s2: float) -> MotionProfile: ...
    def concat(self, other: MotionProfile) -> MotionProfile: ...
    initial_angle_rad: float
    initial_speed_rad_s: float
    def __len__(self) -> int: ...

class SensorModel:
    def __init__(
        self,
        *,
        amplitude: Optional[float] = None,
        offset_cos: Optional[float] = None,
        offset_sin: Optional[float] = None,
        amplitude_imbalance: Optional[float] = None,
        quadrature_error_rad: Optional[float] = None,
        third_harmonic: Optional[float] = None,
        angle_error_harmonics: Optional[Sequence[tuple[int, float, float]]] = None,
        noise_std: Optional[float] = None,
        adc_bits: Optional[int] = None,
        adc_full_scale: Optional[float] = None,
    ) -> None: ...
    amplitude: float
    offset_cos: float
    offset_sin: float
    amplitude_imbalance: float
    quadrature_error_rad: float
    third_harmonic: float
    angle_error_harmonics: list[tuple[int, float, float]]
    noise_std: float
    adc_bits: int
    adc_full_scale: float
    def calibration(self) -> SensorCalibration:
        """The ``SensorCalibration`` of this sensor (offsets, amplitudes ``A`` and
        ``A (1 + amplitude_imbalance)``, quadrature): what an online calibration learns."""

class Scenario:
    @staticmethod
    def generate(
        profile: MotionProfile, sensor: Optional[SensorModel] = None, *, sample_period_s: float, seed: int = 0
    ) -> Scenario: ...
    @staticmethod
    def from_arrays(
        *, sample_period_s: float, angle_rad: _Samples, y_c: _Samples, y_s: _Samples,
        speed_rad_s: Optional[_Samples] = None,
    ) -> Scenario:
        """A scenario of recorded arrays; ``ConfigError`` naming ``angle_rad`` if a reference
        angle is not finite."""
    sample_period_s: float
    time_s: npt.NDArray[np.float64]
    angle_rad: npt.NDArray[np.float64]
    speed_rad_s: npt.NDArray[np.float64]
    acceleration_rad_s2: npt.NDArray[np.float64]
    y_c: npt.NDArray[np.float64]
    y_s: npt.NDArray[np.float64]
    has_speed: bool
    len: int
    def __len__(self) -> int: ...

class ErrorStatistics:
    rms: float
    max: float
    mean: float

class Metrics:
    angle_error_rad: ErrorStatistics
    speed_error_rad_s: Optional[ErrorStatistics]
    samples: int
    overshoot: Optional[float]
    settling_time_s: Optional[float]
    time_to_lock_s: Optional[float]

def metrics(
    scenario: Scenario, estimates: Estimates, *, skip_s: float = 0.0, lock_tolerance_rad: float = 0.01,
    settling_band: float = 0.02,
) -> Metrics: ...

# ----------------------------------------------------------------------------- captures

class CaptureError(ValueError):
    """A capture that cannot be read, or estimates that cannot be written; the message is
    ``FILE:LINE:COLUMN: what is wrong``."""

    path: str
    """The file."""
    line: Optional[int]
    """The 1-based line of a text file (row of an array) at fault, or ``None``."""
    column: Optional[int]
    """The 1-based column at fault, or ``None``."""

_Columns = Union[str, dict[str, Union[str, int]], None]
_TimeUnit = Literal["s", "ms", "us", "ns"]

class CaptureChunk:
    """A chunk of a capture: float64 arrays of one length (time in seconds)."""

    first_sample: int
    """0-based index of the chunk's first sample in the capture."""
    time_s: Optional[npt.NDArray[np.float64]]
    y_c: npt.NDArray[np.float64]
    y_s: npt.NDArray[np.float64]
    reference_rad: Optional[npt.NDArray[np.float64]]
    excitation: Optional[npt.NDArray[np.float64]]
    """The resolver's excitation (counts), from a column mapped as ``excitation``, or ``None``."""
    def __len__(self) -> int: ...

class CaptureReader:
    """A capture read chunk by chunk in constant memory (iterate for ``CaptureChunk``s):
    delimited text (any delimiter, sniffed; decimal points or commas, sniffed; header or
    not; an instrument's metadata lines before it, sniffed or ``skip_rows``; UTF-8, Latin-1
    or UTF-16 with its byte-order mark; an oscilloscope's (x, y) column pairs, whose time
    columns must agree), NumPy ``.npy`` (2-D, rows x columns; or a 1-D record array, its
    fields by name) or ``.npz`` (named 1-D arrays,
    streamed). ``columns``: ``"y_c=cos,y_s=sin,time=t"`` or a dict; each value a header
    name, else a 0-based index, or ``"-"`` to ignore a time or reference column; one column
    per role; roles left out get their usual names. ``sample_rate_hz`` states the true rate
    and skips the time column's spacing check (rounded, repeated stamps pass). Raises
    ``CaptureError`` naming the file, line and column of malformed input."""

    def __init__(
        self, path: Union[str, os.PathLike], *, columns: _Columns = None, delimiter: Optional[str] = None,
        decimal: Optional[Literal[".", ","]] = None, skip_rows: int = 0, time_unit: _TimeUnit = "s",
        sample_rate_hz: Optional[float] = None, chunk_rows: int = 65536,
    ) -> None: ...
    def __iter__(self) -> CaptureReader: ...
    def __next__(self) -> CaptureChunk: ...
    @property
    def sample_rate_hz(self) -> Optional[float]:
        """The stated rate, else the time column's mean spacing so far (Hz), else ``None``."""
    @property
    def rows(self) -> int:
        """Samples read so far."""
    @property
    def sample_dtype(self) -> str:
        """The samples' type as stored: ``int16`` (arrays), ``int64`` (whole numbers in text:
        raw ADC counts), ``float64``..."""
    @property
    def columns(self) -> dict[str, str]:
        """``{role: column name}`` of the columns used."""
    @property
    def format(self) -> str:
        """``npy``, ``npz`` or ``text, delimiter X``."""
    @property
    def path(self) -> str: ...
    @property
    def progress_bytes(self) -> tuple[int, int]:
        """(bytes read, file size)."""

class Capture:
    """A whole capture: float64 arrays and what was learnt reading it."""

    path: str
    rows: int
    time_s: Optional[npt.NDArray[np.float64]]
    y_c: npt.NDArray[np.float64]
    y_s: npt.NDArray[np.float64]
    reference_rad: Optional[npt.NDArray[np.float64]]
    sample_rate_hz: Optional[float]
    """The stated rate, else the time column's mean (Hz); ``None`` without either."""
    sample_dtype: str
    columns: dict[str, str]
    format: str
    def __len__(self) -> int: ...

def read_capture(
    path: Union[str, os.PathLike], *, columns: _Columns = None, delimiter: Optional[str] = None,
    decimal: Optional[Literal[".", ","]] = None, skip_rows: int = 0, time_unit: _TimeUnit = "s",
    sample_rate_hz: Optional[float] = None,
) -> Capture:
    """Reads a whole capture (the checks of ``CaptureReader``)."""

def estimate_columns(dtype: _DType = None) -> list[tuple[str, str]]:
    """The columns ``(name, dtype)`` of estimates of the float type ``dtype`` (float32 or
    float64): what ``angletrack.EstimatesWriter`` writes through a ``TableWriter``."""

class TrackerRun:
    """A tracker file's chain (the Rust crate's ``TrackerRun``: the core's ``Tracker`` built
    by the rules of the firmware's export), fed a capture chunk by chunk: what
    ``Tracker.track`` and ``angletrack track`` hold. ``ValueError`` naming ``file`` and the
    field on a setting the chain cannot run."""

    def __init__(self, text: str, file: str, y_c: npt.NDArray[np.float64], y_s: npt.NDArray[np.float64],
                 mid_scale: Optional[int] = None) -> None: ...
    def track(self, y_c: npt.NDArray[np.float64], y_s: npt.NDArray[np.float64]) -> dict[str, npt.NDArray[Any]]:
        """The estimates of the next samples (float64, equal lengths): ``angle_rad``,
        ``position_rad``, ``speed_rad_s``, ``acceleration_rad_s2``, ``phase_error``,
        ``faults``, ``front_end_faults`` and, for fixed point, ``angle_binary``."""
    @property
    def latched_faults(self) -> tuple[int, int]:
        """The observer's and the front end's faults latched since the start."""
    @property
    def learning(self) -> Optional[tuple[_SensorParameters, int, str]]:
        """What the online calibration learned: calibration, turns learned, status."""

class TableWriter:
    """A table of named numeric columns written chunk by chunk, the format from the
    extension: ``.csv`` (the names as header, floats as the
    shortest decimal that reads back, integers as digits), ``.npy`` (a structured array,
    one field per column) or ``.npz`` (one array per column). ``columns``: ``(name, dtype)``
    in file order, names of letters, digits and underscores, each once; dtypes float64,
    float32, uint8 or int32. Written beside ``path`` and renamed to it by ``close()``; after
    an exception in a ``with`` block the file is discarded."""

    def __init__(self, path: Union[str, os.PathLike], columns: Sequence[tuple[str, npt.DTypeLike]]) -> None: ...
    def write(self, arrays: Sequence[npt.NDArray[Any]]) -> None:
        """Appends a chunk: one contiguous 1-D array per column, of its dtype, one length."""
    def close(self) -> int:
        """Finishes the file; returns the rows written."""
    def __enter__(self) -> TableWriter: ...
    def __exit__(self, exc_type: object, _exc_value: object, _traceback: object) -> bool: ...

class OutputFile:
    """An output written all or nothing: write ``temporary_path`` (beside ``path``); the end
    of the ``with`` block renames it over ``path``, an exception removes it."""

    def __init__(self, path: Union[str, os.PathLike]) -> None: ...
    @property
    def temporary_path(self) -> str: ...
    def commit(self) -> None:
        """Renames the temporary file over the target."""
    def discard(self) -> None:
        """Removes the temporary file; the target stays as it was."""
    def __enter__(self) -> OutputFile: ...
    def __exit__(self, exc_type: object, _exc_value: object, _traceback: object) -> bool: ...

def check_outputs(
    outputs: dict[str, Union[str, os.PathLike]], inputs: dict[str, Union[str, os.PathLike]]
) -> None:
    """Refuses (``CaptureError``) an output that is one of the inputs or another output
    (any spelling: symbolic or hard link, ``..``), before anything is written."""

def write_output(path: Union[str, os.PathLike], data: Union[bytes, str]) -> None:
    """Writes ``data`` to ``path`` all or nothing (a temporary file beside it, renamed)."""

# ----------------------------------------------------------------------------- resolver front end

class DemodulatedPairs:
    """The pairs of one ``Demodulator.push``: one element per carrier period."""

    time_s: npt.NDArray[np.float64]
    """The time (s) at which each pair holds (its window's samples weighted by their share of the pair),
    from the first ADC sample."""
    y_c: npt.NDArray[np.float64]
    y_s: npt.NDArray[np.float64]
    quadrature_c: npt.NDArray[np.float64]
    quadrature_s: npt.NDArray[np.float64]
    window: npt.NDArray[np.uint64]
    faults: npt.NDArray[np.uint8]
    """Front-end faults: 1 loss of excitation, 2 carrier phase drift, 4 clipping, 8 weak excitation,
    32 excitation reference (the recorded excitation unusable: ``FrontEndFaults``)."""
    half_turn_unresolved: npt.NDArray[np.bool_]
    """Whether each pair's half turn rests on nothing stated (no ``expected_delay_rad``, or the
    excitation unusable in its window): not a fault; the angle is right or half a turn off."""
    def __len__(self) -> int: ...

class Demodulator:
    """The demodulator of a resolver front end (float64): the carrier tracked, any ADC rate of at
    least 4 samples per period, optionally the excitation's samples."""

    def __init__(
        self,
        *,
        carrier_hz: float,
        carrier_amplitude_counts: float,
        adc_rate_hz: Optional[float] = None,
        samples_per_period: Optional[float] = None,
        adc_min_code: float = 0.0,
        adc_max_code: float = 4095.0,
        expected_delay_rad: Optional[float] = None,
        startup_periods: Optional[int] = None,
        phase_drift_bound_rad: Optional[float] = None,
        loss_of_excitation: Optional[float] = None,
        weak_excitation: Optional[float] = None,
        carrier_loop_bandwidth: Optional[float] = None,
        max_carrier_error: Optional[float] = None,
        measure_adc_range: bool = False,
    ) -> None: ...
    def push(self, raw_c: _Samples, raw_s: _Samples, excitation: Optional[_Samples] = None) -> DemodulatedPairs: ...
    @property
    def samples_per_period(self) -> float: ...
    @property
    def pair_period_s(self) -> float: ...
    @property
    def centre_to_end_s(self) -> float: ...
    @property
    def tracked_carrier_hz(self) -> float: ...
    @property
    def has_excitation(self) -> bool: ...
    @property
    def is_delay_stated(self) -> bool: ...
    @property
    def is_delay_ready(self) -> bool: ...
    @property
    def carrier_delay_rad(self) -> float: ...
    @property
    def startup_delay_rad(self) -> float: ...
    @property
    def latched_faults(self) -> int: ...
    @property
    def measured_adc_range(self) -> Optional[tuple[float, float]]: ...
    @property
    def clipped_samples(self) -> int: ...

class ResolverModel:
    """A carrier-excited resolver sampled by an ADC clocked with the excitation."""

    def __init__(
        self,
        *,
        carrier_hz: Optional[float] = None,
        samples_per_period: Optional[int] = None,
        carrier_delay_rad: Optional[float] = None,
        excitation_amplitude_counts: Optional[float] = None,
        transformation_ratio: Optional[float] = None,
        winding_imbalance: Optional[float] = None,
        common_mode_counts: Optional[float] = None,
        adc_bits: Optional[int] = None,
        noise_std_counts: Optional[float] = None,
    ) -> None: ...
    carrier_hz: float
    samples_per_period: int
    carrier_delay_rad: float
    excitation_amplitude_counts: float
    transformation_ratio: float
    winding_imbalance: float
    common_mode_counts: float
    adc_bits: int
    noise_std_counts: float
    @property
    def amplitude_counts(self) -> float: ...
    @property
    def adc_sample_period_s(self) -> float: ...
    @property
    def mid_scale_counts(self) -> float: ...

def resolver_windings(profile: MotionProfile, model: Optional[ResolverModel] = None, *, seed: int = 0) -> Scenario: ...

class DriveAngles:
    """The drive's outputs of one ``DriveOutputs.update``, one element per estimate."""

    electrical_angle_rad: npt.NDArray[np.float64]
    electrical_speed_rad_s: npt.NDArray[np.float64]
    mechanical_angle_rad: npt.NDArray[np.float64]
    mechanical_turns: npt.NDArray[np.int64]
    mechanical_speed_rad_s: npt.NDArray[np.float64]

class DriveOutputs:
    """The angle a drive needs: electrical, at the PWM update instant, with the speed filtered."""

    def __init__(
        self,
        *,
        sample_period_s: float,
        pole_pairs: int = 1,
        speed_ratio: int = 1,
        latency_s: float = 0.0,
        speed_cutoff_hz: Optional[float] = None,
    ) -> None: ...
    def update(self, estimates: Estimates) -> DriveAngles: ...
    @property
    def latency_s(self) -> float: ...
# ----------------------------------------------------------- angle error calibration

class _CaptureCalibrator:
    """A calibration learned from a capture read twice in chunks (see
    ``angletrack.harmonics.calibrate_chunks``)."""

    def __init__(
        self, gains: Gains, *, lowest_order: Optional[int] = None, highest_order: int = 8,
        settle_fraction: float = 0.2, self_calibration: bool = False, own_loop: bool = True,
        min_significance: float = 3.0,
    ) -> None: ...
    def add_geometry(self, y_c: _Samples, y_s: _Samples) -> None: ...
    def start_fit(self, has_reference: bool) -> str: ...
    def add_fit(self, y_c: _Samples, y_s: _Samples, reference: Optional[_Samples] = None) -> None: ...
    def finish(self) -> _LearnedCalibration: ...

def _corrected_observer(
    gains: Gains, sensor: _SensorParameters, cos: Sequence[float],
    sin: Sequence[float], *, dtype: _DType = None, sin_cos: _SinCos = None,
    adc_range: Optional[tuple[float, float]] = None, measure_adc_range: bool = False,
    fault_thresholds: Optional[FaultThresholds] = None,
) -> Observer: ...

# ----------------------------------------------------------- firmware source (angletrack::export)

def gains_source(
    gains: Gains, language: _Language, *, name: str = "angletrack", dtype: _FloatType = "float32",
    description: str = "",
) -> str:
    """A C header (``language="c"``) with the gains, the sample period, the sample rate and the
    order in ``dtype``, or a block of Rust ``const`` (``"rust"``) for
    ``angletrack_core::Gains::new``; ``ConfigError`` naming ``language``, ``name`` (not an
    identifier), ``dtype`` or the value not finite in ``dtype``."""
def fixed_source(
    constants: _FixedConstants, language: _Language, *, name: str = "angletrack", description: str = ""
) -> str:
    """A C header (``"c"``) or a Rust ``const`` (``"rust"``) for
    ``angletrack_core::FixedGains::from_constants`` of ``Design.fixed_constants()``."""
def calibration_source(
    sensor: _SensorParameters, cos: Sequence[float], sin: Sequence[float], language: _Language, *,
    name: str = "angletrack", dtype: _FloatType = "float32",
) -> str:
    """A C header (``"c"``) or a block of Rust ``const`` (``"rust"``) with a sensor calibration
    and an angle correction (checked by the core)."""

# ----------------------------------------------------------- gains files (angletrack::export::GainsFile)

#: The ``format`` of a gains file (``angletrack design --format json``).
GAINS_FILE_FORMAT: str
#: The ``format`` of a fixed-point constants file (``angletrack design --dtype fixed --format json``).
FIXED_GAINS_FILE_FORMAT: str
#: The ``version`` both are written with, and the only one read.
GAINS_FILE_VERSION: int

def gains_file_json(gains: Gains, design_json: Optional[str] = None) -> str:
    """The gains file's JSON text: the gains and sample period in float64 (exact round trip),
    and the design (JSON text) under ``design``."""
def read_gains_file(text: str, file: str = "gains file") -> tuple[list[float], float]:
    """The gains and sample period of a gains file's text, checked by the core; ``ValueError``
    naming ``file`` and the field."""
def fixed_gains_file_json(constants: _FixedConstants, design_json: Optional[str] = None) -> str:
    """The fixed-point constants file's JSON text."""
def read_fixed_gains_file(text: str, file: str = "gains file") -> _FixedConstants:
    """The constants of a fixed-point constants file's text, checked by the core."""

# ----------------------------------------------------------- calibration files (angletrack::CalibrationFile)

#: The ``format`` of a sensor calibration file (``angletrack track --calibrate``).
SENSOR_CALIBRATION_FORMAT: str
#: The ``format`` of an angle calibration file (``angletrack calibrate``).
ANGLE_CALIBRATION_FORMAT: str

def sensor_calibration_to_json(
    calibration: SensorCalibration, *, turns_learned: Optional[int] = None, source: Optional[str] = None
) -> str:
    """The JSON text of a sensor calibration file."""
def angle_calibration_to_json(
    sensor: _SensorParameters, cos: Sequence[float], sin: Sequence[float], speed_rad_s: float, turns: float,
    error_rms_rad: float, residual_rms_rad: float, *, method: Optional[str] = None,
    orders: Optional[Sequence[tuple[int, float, float, str]]] = None,
) -> str:
    """The JSON text of an angle calibration file (the calibration checked by the core), with
    the method and each order's ``(order, amplitude_rad, uncertainty_rad, status)``."""
def calibration_from_json(text: str, file: str) -> Union[SensorCalibration, _LearnedCalibration]:
    """The calibration of a file's text of either format; ``ValueError`` naming ``file`` and
    the field at fault."""
def sensor_calibration_from_json(text: str, file: str) -> SensorCalibration:
    """The calibration of a sensor calibration file's text (or a bare object of its five
    fields)."""
def angle_calibration_from_json(text: str, file: str) -> _LearnedCalibration:
    """The calibration of an angle calibration file's text (another format is refused)."""

#: The ``format`` of a tracker file (``angletrack.Tracker``).
TRACKER_FILE_FORMAT: str
#: The ``version`` of a tracker file written, and the only one read.
TRACKER_FILE_VERSION: int

def checked_tracker_file(text: str, file: str) -> str:
    """A tracker file's text checked by the crate and written again as it writes it (every
    setting present); ``ValueError`` naming ``file`` and the field as written."""
def tracker_file_from_gains(gains_text: str, gains_file: str) -> str:
    """The tracker file's text of a gains file's, the other settings at their defaults."""
def tracker_file_with_calibration(tracker_text: str, tracker_file: str, calibration_text: str,
                                  calibration_file: str) -> str:
    """The tracker file's text with the calibration of a calibration file's text (either
    kind) in place of its own."""
def tracker_firmware_constants(text: str, file: str, language: _Language, name: str) -> str:
    """A tracker file's firmware constants: ``language`` ``"c"`` (a header) or ``"rust"``
    (``const`` items), identifiers prefixed by ``name``; ``ValueError`` naming a setting no
    generator writes, ``ConfigError`` naming ``name``."""

#: The ``format`` of a study's specification (``angletrack study``).
STUDY_FORMAT: str

def study_resolve(text: str, file: str, base_dir: Union[str, os.PathLike]) -> tuple[str, int]:
    """A study's JSON specification checked by the crate (``angletrack::study``), its tracker
    files read relative to ``base_dir`` and put inline: ``(resolved, runs)``; ``ValueError``
    naming ``file`` and the field as written."""

def study_runs(resolved: str, runs: list[int]) -> list[dict[str, Any]]:
    """The rows of the run ids ``runs`` of a resolved specification, one dict of named
    columns each (the crate's ``StudyRow::columns``), computed with the GIL released."""

def lot_outliers(values: list[float], spread_factor: float, low: Optional[float] = None,
                 high: Optional[float] = None) -> tuple[float, float, list[bool]]:
    """``(median, scaled MAD, flags)`` of a lot's ``values`` (``angletrack::lot::outliers``):
    flagged below ``low``, above ``high``, or further than ``spread_factor`` scaled MADs from
    the median; NaN never flagged."""
