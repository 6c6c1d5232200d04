"""On-robot training: one robot, wall-clock control, the learner updating while the robot walks. `interface`
is the robot protocol (the only thing the loop knows about a robot), `adapters` the robots by name, `simulated` the HB40
behind it in native MuJoCo, `estimation` the velocity estimator, `safety` the monitor, `scheduling` the control thread's
priority and memory lock. `loop.run` is a run: `config` its settings, `control` the jitted tick and the 40 Hz episodes,
`learner` the concurrent learner on `host_replay`, `session_checkpoint` stop and resume, `report` the results document
and trace (their schema), `view` the live numbers, `figure` the run's figure, `memory` what it needs. `operator` holds
the operator's states and buttons, `operating` what the robot does in them, `console` (and `console.html`) serves them
to a browser. The robot behind a link: `link_schema` its messages, `linked_robot` the learner's side, `robot_server`
the robot's side with its watchdog, `link_keys` CURVE; `onboard` (with `onboard_estimator`, no JAX) runs an exported
policy, `test_drive` walks the robot with it; `launch` starts a run or a server. It may import learning and below;
experiments beside it is independent of it."""
