"""The ground as MJCF: a flat floor or cobblestones (an MJX height field), either on a slope.

MJX collides a height field only with spheres, capsules, boxes and meshes (its collision table
refuses other pairs at `put_model`), and each pair's cost grows with (geom size / cell)^2,
since it tests every grid cell under the geom's bounding sphere. On cobblestones only the
parts in `Ground.contacts` touch the ground, by default the feet, spheres of 2 cm, 9 cells
each at a 2 cm grid (a calf capsule would cost 169 cells, the trunk box 324). The safety
monitor ends an episode on a tilt well before the trunk or a knee would reach the stones.
"""

import dataclasses
import math

import mujoco
import numpy as np

HFIELD_COLLIDES_WITH = {mujoco.mjtGeom.mjGEOM_SPHERE: "sphere", mujoco.mjtGeom.mjGEOM_CAPSULE: "capsule",
                        mujoco.mjtGeom.mjGEOM_BOX: "box", mujoco.mjtGeom.mjGEOM_MESH: "mesh"}
"""Geom types MJX can collide with a height field (mjx/_src/collision_driver.py)."""
SEED = 0
"""The stones are drawn once, from this seed: every run walks the same pavement."""


@dataclasses.dataclass(frozen=True)
class Ground:
    """The floor the robot walks on."""

    terrain: str = "flat"
    """'flat' (a plane) or 'cobblestones' (a height field of rounded stones)."""
    friction: tuple = (1.1, 1.1)
    """Sliding friction of the feet on it, drawn per episode uniformly from [low, high] (sim: the model's 1.1)."""
    incline_deg: float = 0.0
    """Slope of the ground, rising along the robot's forward (+x) direction."""
    stone_m: float = 0.10
    """Cobblestones: the stones' pitch (centre to centre), a typical setts pavement (assumed; the thesis shows photos)."""
    relief_m: float = 0.02
    """Cobblestones: the height from a joint between stones to a stone's crown (assumed)."""
    cell_m: float = 0.02
    """Cobblestones: the height field's grid spacing; MJX's cost grows with (geom radius / cell)^2."""
    half_extent_m: float = 8.0
    """Cobblestones: the field spans +-this around the start (a 10 s episode at 0.8 m/s stays within it)."""
    contacts: tuple = ("foot",)
    """Cobblestones: the robot's parts that collide with them (of RobotSpec.floor_contacts; MJX: spheres, capsules,
    boxes and meshes only)."""
    impratio: float | None = None
    """The contact solver's frictional-to-normal impedance ratio on this ground; None keeps the robot model's (the
    released model's 100)."""

    def impratio_with(self, model_impratio: float) -> float:
        """The impratio the physics runs with on this ground, for a robot model whose own is `model_impratio`."""
        return model_impratio if self.impratio is None else self.impratio

    def validate(self) -> None:
        if self.terrain not in ("flat", "cobblestones"):
            raise ValueError(f"unknown terrain {self.terrain!r}; choose from flat, cobblestones")
        if len(self.friction) != 2:
            raise ValueError(f"ground friction {self.friction}: give one number or a range (low, high)")
        low, high = self.friction
        if not 0 < low <= high:
            raise ValueError(f"ground friction range {self.friction} must satisfy 0 < low <= high")
        if not -30 <= self.incline_deg <= 30:
            raise ValueError(f"incline of {self.incline_deg} degrees: choose within -30..30")
        parts = ("trunk", "thigh", "calf", "foot")
        if not self.contacts or set(self.contacts) - set(parts):
            raise ValueError(f"ground contacts {self.contacts}: choose one or more of {', '.join(parts)}")
        if self.impratio is not None and not 1.0 <= self.impratio <= 1000.0:
            raise ValueError(f"ground impratio {self.impratio}: choose within 1..1000, or None for the robot model's")
        for name in ("stone_m", "relief_m", "cell_m", "half_extent_m"):
            if not getattr(self, name) > 0:
                raise ValueError(f"ground {name} must be positive, not {getattr(self, name)}")

    @property
    def incline_rad(self) -> float:
        return math.radians(self.incline_deg)


def incline_euler(ground) -> str:
    """The floor's orientation attribute: rising along +x by the incline (about y by minus the angle); none if level."""
    return f' euler="0 {-ground.incline_rad:.6g} 0"' if ground.incline_deg else ""


def floor_xml(ground) -> tuple[str, str]:
    """(asset, geom) MJCF of the floor named 'floor'."""
    if ground.terrain == "flat":
        return "", f'<geom name="floor" type="plane" size="0 0 0.05"{incline_euler(ground)} rgba="0.8 0.8 0.8 1"/>'
    n = grid_size(ground)
    half = ground.half_extent_m
    asset = (f'<asset><hfield name="cobblestones" nrow="{n}" ncol="{n}" '
             f'size="{half:g} {half:g} {ground.relief_m:g} 0.05"/></asset>')
    geom = (f'<geom name="floor" type="hfield" hfield="cobblestones"{incline_euler(ground)} '
            f'rgba="0.62 0.58 0.52 1"/>')
    return asset, geom


def grid_size(ground) -> int:
    """Rows (and columns) of the height field."""
    return int(round(2 * ground.half_extent_m / ground.cell_m)) + 1


def cobblestones(ground) -> np.ndarray:
    """(rows, cols) heights in [0, 1] (times relief_m): rounded stones in running bond, each crown a little higher or
    lower than the next (+-25 %), joints at 0 between them. Rows run along y, columns along x (MuJoCo's layout)."""
    n = grid_size(ground)
    coordinates = np.linspace(-ground.half_extent_m, ground.half_extent_m, n)
    x, y = np.meshgrid(coordinates, coordinates)  # x varies along columns
    pitch = ground.stone_m
    row = np.floor(y / pitch)
    shifted = x / pitch + 0.5 * (row % 2)  # every other row half a stone along: running bond
    column = np.floor(shifted)
    u, v = shifted - column - 0.5, y / pitch - row - 0.5  # -0.5..0.5 within a stone
    crown = np.clip(1.0 - (2 * np.abs(u)) ** 4 - (2 * np.abs(v)) ** 4, 0.0, 1.0) ** 0.5
    rng = np.random.default_rng(SEED)
    stones = rng.uniform(0.75, 1.0, size=(int(2 * np.max(np.abs(row))) + 3, int(2 * np.max(np.abs(column))) + 3))
    scale = stones[(row - row.min()).astype(int), (column - column.min()).astype(int)]
    return crown * scale


def set_heights(model: mujoco.MjModel, ground) -> mujoco.MjModel:
    """Fill the model's height field with the cobblestones (a no-op on flat ground)."""
    if ground.terrain == "cobblestones":
        model.hfield_data[:] = cobblestones(ground).reshape(-1)
    return model


def height_at(ground, x, xp=np):
    """The floor's height (m) under the plane position x along the slope (the stones' relief left out)."""
    return x * math.tan(ground.incline_rad) if ground.incline_deg else 0.0 * x


def check_collisions(model: mujoco.MjModel) -> None:
    """ValueError naming a geom paired with the height field that MJX cannot collide with it, before anything compiles."""
    if not model.nhfield:
        return
    floor = model.geom("floor").id
    for i in range(model.npair):
        geom1, geom2 = int(model.pair_geom1[i]), int(model.pair_geom2[i])
        other = geom2 if geom1 == floor else geom1 if geom2 == floor else None
        if other is None:
            continue
        kind = mujoco.mjtGeom(model.geom_type[other])
        if kind not in HFIELD_COLLIDES_WITH:
            raise ValueError(f"geom {model.geom(other).name!r} is a {kind.name[len('mjGEOM_'):].lower()}: MJX collides "
                             f"a height field only with {', '.join(HFIELD_COLLIDES_WITH.values())}; take it out of the "
                             f"ground's contacts or make it one of those")
