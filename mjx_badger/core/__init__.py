"""The ground floor: atomic file writes (safe_io), input validation with one-line refusals (validation), one
writer per output (locks), graceful stops on SIGINT/SIGTERM (stops), how a failed command ends (faults), command-line
option helpers (options), several processes through jax.distributed (cluster), the compile cache (cache) and where a
clone keeps its committed files (paths). It imports nothing of mjx_badger."""
