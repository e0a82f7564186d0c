"""Station-keeping controllers (paper Section 5) and arm commands; chosen by name from a registry."""
