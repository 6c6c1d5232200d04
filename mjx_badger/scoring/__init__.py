"""The thesis's findings scored: a claim and its verdict (verdicts), the fifteen simulation claims (claims),
the real-world findings (real_world), the scoreboards (scoreboard) and the one-factor swaps that attribute claims to
departures (attribution). It may import experiments, realtime and below."""
