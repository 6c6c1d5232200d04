"""The memory the on-robot loop needs, its replay buffer and trace in host memory, checked before it starts."""

from mjx_badger.learning.memory import GIB, OVERHEAD_BYTES, host_available, host_total
from mjx_badger.realtime.report import TRACE
from mjx_badger.sim.env import EnvConfig, HB40Env


def estimate(config) -> int:
    """Bytes of the on-robot loop: its host replay buffer and trace of `config.steps`, and the process."""
    env = HB40Env(config.approach, config.make_task(), EnvConfig(control_hz=config.hz, protocol=config.protocol_spec),
                  config.robot_spec, config.approach_params)
    row = 4 * (2 * env.observation_size + env.action_size + 2)  # float32 obs, action, reward, next obs, discount
    return OVERHEAD_BYTES + config.steps * (row + 8 * len(TRACE))  # the trace is float64


def check(config) -> None:
    """ValueError unless the on-robot loop's replay and trace fit in the host memory available."""
    need = estimate(config)
    free, total = host_available(), host_total()
    if need > free:
        raise ValueError(f"the run does not fit: ~{need / GIB:.1f} GiB estimated for {config.steps} steps of replay "
                         f"and trace; this machine has {free / GIB:.1f} GiB memory available of {total / GIB:.1f} GiB; "
                         "choose fewer --steps")
