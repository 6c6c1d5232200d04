"""What a reader looks at, drawn from results files only (nothing here trains): the figures of each
experiment (curves, overview, style), every figure and table of a profile (plots, tables, drawn), the real-world
tables and figure (real_world), videos (videos), the estimators' figures (estimator_figures) and the reference results
published into figures/data (publish). It may import scoring and below."""
