"""Signal analysis: filters and generated signals, FRFs and their inverse, discrepancy metrics, ISO 2631 comfort."""
