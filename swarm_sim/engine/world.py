"""World geometry (cm): robot bodies, ground sensors, the void band, walls and obstacles.

All functions are vectorised over robots. The void is the vertical band
``x0 < x < x1`` spanning the arena height (``x0 = inf`` when there is none).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from swarm_sim.params import Params


@dataclass(frozen=True)
class World:
    """The static arena, precomputed from :class:`Params`."""

    w_cm: float
    h_cm: float
    x0_cm: float
    x1_cm: float
    length_cm: float
    width_cm: float
    shape: str
    detect_cm: float
    avoid_cm: float
    obstacles: np.ndarray  # (k, 3) x, y, r
    target_x_cm: float
    target_y_cm: float
    target_found_cm: float

    @classmethod
    def from_params(cls, p: Params, void: bool = True) -> World:
        obs = np.array(p.obstacles, dtype=np.float64).reshape(-1, 3)
        return cls(p.arena_w_cm, p.arena_h_cm, p.void_x0_cm if void else math.inf,
                   p.void_x1_cm if void else math.inf, p.robot_length_cm, p.robot_width_cm,
                   p.shape, p.void_detect_cm, p.avoid_cm, obs, p.target_x_cm, p.target_y_cm,
                   p.target_found_cm)

    @cached_property
    def without_obstacles(self) -> World:
        """The same arena with no obstacles: where the structure and a robot docking into it
        stand (the thesis's assumption 13: the moving structure ignores obstacles)."""
        return replace(self, obstacles=np.zeros((0, 3)))

    @cached_property
    def body_radius_cm(self) -> float:
        """Circumscribed radius of the body (half diagonal of the square)."""
        if self.shape == "octagon":
            return 0.5 * self.length_cm / math.cos(math.pi / 8)
        return 0.5 * math.hypot(self.length_cm, self.width_cm)

    def body_local(self) -> np.ndarray:
        """Body vertices in the robot frame (x forward), shape (V, 2)."""
        hl, hw = 0.5 * self.length_cm, 0.5 * self.width_cm
        if self.shape == "octagon":
            r = hl / math.cos(math.pi / 8)
            a = np.pi / 8 + np.arange(8) * np.pi / 4
            return np.stack([r * np.cos(a), r * np.sin(a)], axis=1)
        return np.array([[hl, hw], [hl, -hw], [-hl, -hw], [-hl, hw]])

    # ------------------------------------------------------------------ bodies
    def half_extents(self, h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Half extents (x, y) of each rotated body (cm); closed form for the square."""
        c, s = np.abs(np.cos(h)), np.abs(np.sin(h))
        if self.shape == "square":
            hl, hw = 0.5 * self.length_cm, 0.5 * self.width_cm
            return hl * c + hw * s, hl * s + hw * c
        loc = self.body_local()
        hc, hs = np.cos(h), np.sin(h)
        vx = hc[:, None] * loc[None, :, 0] - hs[:, None] * loc[None, :, 1]
        vy = hs[:, None] * loc[None, :, 0] + hc[:, None] * loc[None, :, 1]
        return vx.max(axis=1), vy.max(axis=1)

    def x_extent(self, x: np.ndarray, h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """min and max x of each body (cm)."""
        ex, _ = self.half_extents(h)
        return x - ex, x + ex

    def y_extent(self, y: np.ndarray, h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        _, ey = self.half_extents(h)
        return y - ey, y + ey

    def over_void(self, x: np.ndarray, h: np.ndarray) -> np.ndarray:
        """True where any part of the body is over the void."""
        lo, hi = self.x_extent(x, h)
        return (hi > self.x0_cm + 1e-9) & (lo < self.x1_cm - 1e-9)

    def pose_ok(self, x: np.ndarray, y: np.ndarray, h: np.ndarray) -> np.ndarray:
        """True where a free robot may stand: inside the walls, off the void, off obstacles."""
        ex, ey = self.half_extents(h)
        ok = (x - ex >= 0) & (x + ex <= self.w_cm) & (y - ey >= 0) & (y + ey <= self.h_cm)
        ok &= ~((x + ex > self.x0_cm + 1e-9) & (x - ex < self.x1_cm - 1e-9))
        if len(self.obstacles):
            r = self.body_radius_cm
            for ox, oy, orad in self.obstacles:
                ok &= (x - ox) ** 2 + (y - oy) ** 2 > (orad + r) ** 2
        return ok

    def pose_ok1(self, x: float, y: float, h: float) -> bool:
        """Scalar :meth:`pose_ok` (one robot)."""
        if self.shape != "square":
            return bool(self.pose_ok(np.array([x]), np.array([y]), np.array([h]))[0])
        c, s = abs(math.cos(h)), abs(math.sin(h))
        hl, hw = 0.5 * self.length_cm, 0.5 * self.width_cm
        ex, ey = hl * c + hw * s, hl * s + hw * c
        if x - ex < 0 or x + ex > self.w_cm or y - ey < 0 or y + ey > self.h_cm:
            return False
        if x + ex > self.x0_cm + 1e-9 and x - ex < self.x1_cm - 1e-9:
            return False
        r = self.body_radius_cm
        return all((x - ox) ** 2 + (y - oy) ** 2 > (orad + r) ** 2 for ox, oy, orad in self.obstacles)

    # ------------------------------------------------------------------ sensors
    def void_ahead(self, x: np.ndarray, y: np.ndarray, h: np.ndarray) -> np.ndarray:
        """Ground sensors (centre-front and under each front connector) see the void
        within ``detect_cm`` ahead of them."""
        if not math.isfinite(self.x0_cm):
            return np.zeros(x.shape, dtype=bool)
        c, s = np.cos(h), np.sin(h)
        hl, q = 0.5 * self.length_cm, 0.25 * self.width_cm
        reach = self.detect_cm * c
        hit = np.zeros(x.shape, dtype=bool)
        for lat in (0.0, q, -q):
            px = x + hl * c - lat * s
            a, b = np.minimum(px, px + reach), np.maximum(px, px + reach)
            hit |= (b > self.x0_cm) & (a < self.x1_cm)
        return hit

    def wall_ahead(self, x: np.ndarray, y: np.ndarray, h: np.ndarray) -> np.ndarray:
        """A wall (or an obstacle) within ``avoid_cm`` in the direction of travel."""
        c, s = np.cos(h), np.sin(h)
        px, py = x + self.avoid_cm * c, y + self.avoid_cm * s
        hit = (px < 0) | (px > self.w_cm) | (py < 0) | (py > self.h_cm)
        for ox, oy, orad in self.obstacles:
            dx, dy = ox - x, oy - y
            hit |= (dx * dx + dy * dy < (orad + self.avoid_cm) ** 2) & (dx * c + dy * s > 0)
        return hit

    def side_of(self, x: np.ndarray) -> np.ndarray:
        """-1 initial side (left of the void), +1 target side, 0 over the void (by centre)."""
        out = np.zeros(x.shape, dtype=np.int8)
        out[x <= self.x0_cm] = -1
        out[x >= self.x1_cm] = 1
        return out


def wrap(a: np.ndarray) -> np.ndarray:
    """Angle to [-pi, pi); angles already in range are returned unchanged (bit for bit)."""
    a = np.asarray(a, dtype=np.float64)
    return np.where((a >= -np.pi) & (a < np.pi), a, (a + np.pi) % (2 * np.pi) - np.pi)
