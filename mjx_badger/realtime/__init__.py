"""On-robot training: one robot, wall-clock control, the learner updating while the robot walks. `interface`
is the robot protocol (the only thing the loop knows about a robot), `adapters` the robots by name, `simulated` the HB40
behind it in native MuJoCo, `estimation` the velocity estimator, `safety` the monitor, `scheduling` the control thread's
priority and memory lock. `loop.run` is a run: `config` its settings, `control` the jitted tick and the 40 Hz episodes,
`learner` the concurrent learner on `host_replay`, `session_checkpoint` stop and resume, `report` the results document
and trace (their schema), `view` the live terminal line, `figure` the run's figure, `memory` what it needs. It may
import learning and below; experiments beside it is independent of it."""
