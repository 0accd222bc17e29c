"""Validation and diagnosis of a model against a measured rig test."""
