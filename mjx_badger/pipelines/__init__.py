"""Work that runs, draws and scores in one go: `reproduce` (plan a profile's runs, run them, draw and
score) and the claims scoreboards with their figure (scoreboards). It may import outputs and below."""
