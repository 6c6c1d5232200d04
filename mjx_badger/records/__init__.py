"""What a run leaves behind and the numbers read from it: the results files and their schema (results),
saved policies run with NumPy (policy), series, finals and summaries of a run (analysis) and the real-world
experiments' numbers (real_world). It may import sim and below."""
