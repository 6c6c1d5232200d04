"""What the robot is asked to do: the locomotion tasks and their registry (locomotion: forward,
forward-max, omni-random, omni-pdec), their reward terms (rewards) and the PDEC curriculum (curriculum), all pure JAX.
It may import core only; robot and agents beside it are independent of it."""
