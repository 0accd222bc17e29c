"""The model: vehicle files, rig configuration, the MJCF builder, static ride height, the analytic ride model."""
