"""Presentation: plots, validation and diagnosis reports, Rerun review. Takes results and records; never simulates."""
