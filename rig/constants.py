"""Constants shared across stages: one place each."""

#: Hz: the band models are compared and drives iterated in (Nurhadiyanto's RPC band, 0.5-50 Hz): measurement
#: noise and drift outside it say nothing about the model
ANALYSIS_BAND = (0.5, 50.0)

#: Hz: the sample rate of records the product makes itself (track runs, demos, synthetic tests)
DEFAULT_RATE = 512.0
