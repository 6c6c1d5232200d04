"""The thesis's experiments: the registry of experiments and the smoke, quick and full profiles they run
at (registry), the time a profile has left (eta) and the learned estimator's dataset walked by a trained policy
(estimator_data). It may import learning and below; realtime beside it is independent of it."""
