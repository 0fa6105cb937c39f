"""Benchmarks: `python -m bench.NAME [--json]` prints a table (or one JSON object of figures)."""
