"""The rates a bushing has, their units and plausible ranges: one schema for the vehicle file's
``[<axle>.bushings.<joint>]`` tables (rig/vehicle/suspensions/bushings.py) and the ``bushing_compliance`` cause's
section (rig/causes/bushing_compliance.py)."""

TRANSLATION = ("radial", "axial")    # N/m; left out of a table: rigid
ROTATION = ("conical", "torsional")  # N m/rad; left out of a table: free
RATES = TRANSLATION + ROTATION
UNITS = {"radial": "N/m", "axial": "N/m", "conical": "N m/rad", "torsional": "N m/rad"}
RANGES = {"radial": (1e3, 1e10), "axial": (1e3, 1e10), "conical": (0.0, 1e7), "torsional": (0.0, 1e7)}
