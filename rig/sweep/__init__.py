"""Design sweeps and Monte-Carlo scatter: many variants of a car, run in chunks, each chunk batched in C.

``design`` says which points to run (a full grid, or Latin-hypercube / Monte-Carlo samples with scatter),
``evaluate`` runs one chunk of points and measures them, ``run`` writes finished chunks atomically and
assembles the table (the local engine: chunks one after another, each a threaded rollout), ``ray_engine``
hands chunks to Ray tasks (imported only when asked for), ``results`` holds the table and what is computed
from it (Pareto front, PSD scatter band).
"""
