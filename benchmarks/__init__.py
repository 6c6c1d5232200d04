"""Re-runnable benchmarks of this suite, each run from the repository root as `python -m benchmarks.bench_x`."""
