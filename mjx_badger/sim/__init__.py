"""The simulated HB40: the MJX environment with pure reset/step (env, with its observation and termination),
the same env stepped on native MuJoCo (native), the deterministic evaluation runs inside training (evaluation), gait
measures (gait), videos (render) and the Gymnasium and brax adapters (gym_env, brax_compat). It may import control
and below; it never imports an agent."""
