"""Roads: ISO 8608 and seed roads, measured profiles, OpenCRG surfaces."""
