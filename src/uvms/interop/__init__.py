"""Bridges to other rigid-body libraries, for cross-checks and benchmarks (optional dependencies)."""
