"""The robot itself: its description (every figure of the HB40 and the first version's, their poses and limits),
leg kinematics, the MuJoCo model built from the description on a ground (mjcf, terrain), the motors' PD gains and the
safety rule that stops them. It may import core only; agents and tasks beside it are independent of it."""
