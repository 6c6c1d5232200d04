"""Robot adapters by name: what `realtime --robot-adapter NAME` trains on, each an `interface.Robot`.

An adapter is a factory `(config, **options) -> Robot` registered with `register(name, factory)`; `options`
are the command's robot settings (`reset_seconds`, `sensor_noise`), which an adapter that has no use for one
ignores. A real robot's adapter registers itself here the same way, so the command line reaches it by name.
"""

from typing import Callable

from mjx_badger.estimation import sensors
from mjx_badger.realtime.interface import Robot
from mjx_badger.realtime.simulated import SimulatedHB40

ADAPTERS: dict[str, Callable] = {}
"""Adapter name -> factory(config: RealtimeConfig, **options) -> interface.Robot."""


def register(name: str, factory: Callable) -> Callable:
    """Add `factory` to ADAPTERS under `name` (replacing one of the same name)."""
    ADAPTERS[name] = factory
    return factory


def check(name: str) -> None:
    """ValueError naming the registered adapters unless `name` is one of them."""
    if name not in ADAPTERS:
        raise ValueError(f"unknown robot adapter {name!r}; choose from {', '.join(ADAPTERS)}")


def make(name: str, config, **options) -> Robot:
    """The robot the adapter `name` gives for the run `config`."""
    check(name)
    return ADAPTERS[name](config, **options)


def simulated(config, reset_seconds: float = 2.0, sensor_noise: bool = True, **_) -> Robot:
    """The simulated HB40 (or the run's robot spec) under the run's conditions, with their sensors' noise."""
    on_robot = config.conditions_spec
    noise = on_robot.sensing.sensors if on_robot.sensing is not None else sensors.SensorModel()
    return SimulatedHB40(noise=noise if sensor_noise else None, reset_seconds=reset_seconds, seed=config.seed,
                         spec=config.robot_spec, conditions=on_robot)


register("simulated", simulated)
