"""Force elements: what a vehicle is built from, below the vehicle and the causes (ARCHITECTURE.md).

The parameters of an element with units and plausible ranges (``parameters.py``); tendons between body and wheel:
the damper, a hidden spring beside the suspension, a clamped rate damper (``tendons.py``); a leaf spring's
inter-leaf friction (``leaf_spring.py``); an air spring's gas law (``air_spring.py``); a bushing's rates
(``bushing_rates.py``); a truck's frame as segments (``frame.py``) and bodies on mounts, its cab and driveline
(``mounted_body.py``). The suspension types build a vehicle from them and the causes change it with them; they import
nothing of either.
"""
