"""Driving one robot one step (cm, rad): the differential-drive primitives the structure's
robots use (the free robots' walk is vectorised in :mod:`swarm_sim.behaviour.explore`).

A robot turns by at most ``turn_max_rad`` per step, then drives ``speed_cm_s * dt_s``; it
never takes a pose that :meth:`World.pose_ok1` refuses (off the walls, the void, the
obstacles). :func:`drive_along` follows a planned path (:mod:`swarm_sim.engine.navigation`).
"""

from __future__ import annotations

import math

import numpy as np

from swarm_sim.engine.navigation import CostField
from swarm_sim.engine.world import World, wrap
from swarm_sim.params import Params


def goto(x, y, h, tx, ty, p: Params, world: World, final_heading: float | None = None,
         align_h: float | None = None):
    """Drive one robot one step towards (tx, ty): turn (limited), then drive; stays off hazards.
    Returns (x, y, heading, arrived)."""
    dist = p.speed_cm_s * p.dt_s
    dx, dy = tx - x, ty - y
    r = math.hypot(dx, dy)
    if r < 1e-9:
        if final_heading is None:
            return x, y, h, True
        d = float(wrap(np.array(final_heading - h)))
        nh = h + max(-p.turn_max_rad, min(p.turn_max_rad, d))
        return x, y, nh, abs(d) <= p.turn_max_rad
    want = math.atan2(dy, dx)
    d = float(wrap(np.array(want - h)))
    nh = h + max(-p.turn_max_rad, min(p.turn_max_rad, d))
    if abs(d) > p.turn_max_rad + 1e-12:
        if world.pose_ok1(x, y, nh):
            return x, y, nh, False
        return slide_off(x, y, h, dist, world)
    step = min(dist, r)
    # straight at the goal, else skirt an obstacle/edge at 45 or 90 degrees
    for off in (0.0, math.pi / 4, -math.pi / 4, math.pi / 2, -math.pi / 2):
        a = want + off
        nx, ny = x + step * math.cos(a), y + step * math.sin(a)
        if world.pose_ok1(nx, ny, a):
            return nx, ny, a, False
    if world.pose_ok1(x, y, want):
        return x, y, want, False
    # cramped (wall or edge too close to turn): creep towards the goal keeping the heading,
    # standing for the small forward/back shuffles a differential drive makes
    headings = [h]
    if align_h is not None:
        da = float(wrap(np.array(align_h - h)))
        headings.insert(0, h + max(-p.turn_max_rad, min(p.turn_max_rad, da)))
    for hh in headings:
        nx, ny = x + step * dx / r, y + step * dy / r
        if world.pose_ok1(nx, ny, hh):
            return nx, ny, hh, False
        if world.pose_ok1(x, y, hh) and hh != h:
            return x, y, hh, False
    return slide_off(x, y, h, dist, world)


def slide_off(x, y, h, dist, world: World):
    """Edge reflex: too close to the void to turn: back away from the edge one step."""
    mid = 0.5 * (world.x0_cm + world.x1_cm)
    sx = x - dist if x < mid else x + dist
    if world.pose_ok1(sx, y, h):
        return sx, y, h, False
    return x, y, h, False


def drive_along(field: CostField, x, y, h, p: Params, world: World, final_heading: float,
                align_h: float | None = None):
    """One step along ``field``'s path to its goal point, arriving with ``final_heading``.
    Returns (x, y, heading, arrived) where arrived means at the goal point with that heading."""
    gx, gy = field.goal_x, field.goal_y
    if math.hypot(x - gx, y - gy) < 1e-9:
        _, _, nh, done = goto(gx, gy, h, gx, gy, p, world, final_heading=final_heading)
        return (gx, gy, final_heading, True) if done else (gx, gy, nh, False)
    wp = field.waypoint(x, y)
    if wp is None:  # no path (the robot stands where the grid has no way out): steer directly
        wp = (gx, gy)
    at_goal = wp == (gx, gy)
    nx, ny, nh, _ = goto(x, y, h, wp[0], wp[1], p, world, align_h=align_h if at_goal else None)
    if at_goal and math.hypot(nx - gx, ny - gy) < 1e-9:
        nx, ny = gx, gy
    return nx, ny, nh, False
