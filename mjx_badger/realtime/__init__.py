"""On-robot training: one robot, wall-clock control, the learner updating while the robot walks.

`interface` is the robot protocol (the only thing the loop knows about a robot), `simulated`
the HB40 behind it in native MuJoCo, `estimation` the velocity estimator, `safety` the
monitor, `loop` the 40 Hz control loop with its concurrent learner.
"""
