"""Training: what a run is (spec, config), the pure `train(key)` program where env and agent meet
(train), its compiled programs (programs), the host loop that runs it chunk by chunk (runner, documents, progress,
checkpoints, tensorboard), sweeps of numeric parameters (sweep), the memory a run needs (memory) and a saved run
loaded again (saved_run). It may import records and below."""
