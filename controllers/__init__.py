"""Drive-signal tuners and controllers for the rig (RPC iteration, inverse-model drive estimation, policies)."""
