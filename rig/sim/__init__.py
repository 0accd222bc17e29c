"""Simulation: rollouts in C, replays and track runs, the measurement chain, drive limits, the virtual rig, IRI."""
