"""Constants shared across stages, one place each, and the analysis band a record supports."""

#: Hz: the band models are compared and drives iterated in (Nurhadiyanto's RPC band, 0.5-50 Hz): measurement
#: noise and drift outside it say nothing about the model
ANALYSIS_BAND = (0.5, 50.0)

#: Hz: the sample rate of records the product makes itself (track runs, demos, synthetic tests)
DEFAULT_RATE = 512.0

#: the band's top as a share of the sample rate: 0.8 of the Nyquist frequency, the pass band of a DAQ's anti-alias
#: filter and the most a zero-phase Butterworth band-pass can keep
TOP_SHARE_OF_RATE = 0.4
#: periods of the band's lowest frequency a record must hold
LOWEST_PERIODS = 4.0
#: the narrowest band worth analysing, as the ratio of its top to its bottom (two octaves)
MIN_BAND_RATIO = 4.0


def analysis_band(rate: float, duration: float) -> tuple[float, float] | None:
    """The part of ANALYSIS_BAND a record sampled at ``rate`` Hz for ``duration`` s supports (Hz): the top lowered
    to 0.4 of the rate, the bottom raised to hold four periods; None when less than two octaves are left."""
    low = max(ANALYSIS_BAND[0], LOWEST_PERIODS / duration) if duration > 0 else float("inf")
    high = min(ANALYSIS_BAND[1], TOP_SHARE_OF_RATE * rate)
    return (low, high) if high >= MIN_BAND_RATIO * low else None


def narrowed_note(band: tuple[float, float], rate: float, seconds: float) -> str | None:
    """What a reader must be told when ``band`` (from ``analysis_band``) is narrower than ANALYSIS_BAND, else None."""
    if band == ANALYSIS_BAND:
        return None
    return (f"analysis band narrowed to {band[0]:.2f}-{band[1]:.1f} Hz: a part of {seconds:.1f} s at {rate:g} Hz "
            f"supports no more of {ANALYSIS_BAND[0]:g}-{ANALYSIS_BAND[1]:g} Hz")
