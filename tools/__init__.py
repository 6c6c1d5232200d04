"""Maintainers' tools (profile timing, rerun-and-compare, hashes, ETA replay), each run as `python -m tools.x`."""
