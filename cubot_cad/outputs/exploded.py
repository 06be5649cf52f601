"""Exploded-view renders of the robots for ``docs/assembly.md`` (lengths in mm).

Every printed part the robot places (:attr:`Robot.placed`) and the bought parts a maker fits in
the same steps (wheels, drive motors, caster balls, the twist servo) are moved apart along the
direction they go on in, and each assembly step of ``docs/assembly.md`` gets a numbered callout.
The plan is data (:data:`PLANS`, one list of :class:`Step` per robot, in assembly order), so the
renders, the step table in the docs (:func:`steps_markdown`) and the tests read the same order.

How a part moves: its step gives a translation ``offset_mm`` (robot frame) and, for stacks of
plates, a ``spread`` factor along the step's axis: a part whose inner face lies ``s`` mm further out
along the axis than the step's innermost part moves ``spread * s`` mm further, so a stack of 3 mm
plates opens up in its own order, and a part that sits in another (the grooved pins in plate b)
moves with it. ``axis="radial"`` (Cube Robot) takes, per part, the horizontal robot axis its
centre lies furthest along, so the four connector faces explode outward on their own sides.

The connector stacks are lifted out of the open top of the body because that is how they go in
(they are screwed to the inside of the walls), and the cover is lifted highest, last.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from cubot_cad.outputs.render import DEFAULT_SIZE_PX, Label, render_shapes

Selector = Callable[[str, str], bool]  # (part or component name, role) -> bool


def names(*prefixes: str) -> Selector:
    """Select parts (or components) whose name starts with one of ``prefixes``."""
    return lambda name, role: name.startswith(prefixes)


def roles(*rs: str) -> Selector:
    """Select parts by role (``_side`` suffix ignored, as in the role colours)."""
    return lambda name, role: role.removesuffix("_side") in rs


@dataclass(frozen=True)
class Step:
    """One assembly step: ``number`` as in docs/assembly.md, ``title`` (short), which printed parts
    (``parts``) and bought stand-ins (``components``, by component key) it fits, and how they move
    in the exploded view: ``offset_mm`` (x, y, z mm), ``spread`` along ``axis`` (a unit vector, or
    ``"radial"``; see the module docstring), ``side_mm``: moved outward along the dominant
    horizontal axis of each item's own centre until its inner face is this far outside the first
    step's printed parts (the body: wheels and rails go off to their sides, clear of it whatever
    the dimensions).
    ``letters``: one callout per distinct part of the block nearest the camera, lettered by the
    part name's ``_a_``..``_e_`` (``5a``..``5e``), instead of one callout for the step."""

    number: str
    title: str
    parts: Selector | None = None
    components: tuple[str, ...] = ()
    offset_mm: tuple[float, float, float] = (0.0, 0.0, 0.0)
    axis: tuple[float, float, float] | str = (1.0, 0.0, 0.0)
    spread: float = 0.0
    side_mm: float = 0.0
    letters: bool = False


#: The assembly order of each robot (matches the numbered steps of docs/assembly.md).
PLANS: dict[str, list[Step]] = {
    "cubot": [
        Step("1", "body (heat-set inserts in the corner bosses)", names("cubot_body")),
        Step("2", "caster seats and balls", names("caster_seat"), ("caster_ball",), offset_mm=(0, 0, -45)),
        Step("3", "drive motors and wheels", None, ("drive_motor", "wheel"), offset_mm=(0, 0, -20), side_mm=25),
        Step("4.1", "twist key", names("twist_key"), offset_mm=(0, 0, -70)),
        Step("4.2", "key bearing ring", names("key_bearing"), offset_mm=(0, 0, -110)),
        Step("4.4", "twist servo", None, ("twist_servo",), offset_mm=(0, 0, 95)),
        Step("5", "front connectors: grooved pins in plate b, stack d-c-b-a", roles("pin", "pinset"),
             offset_mm=(30, 0, 95), axis=(1, 0, 0), spread=4.0, letters=True),
        Step("6", "rear connectors: latch stack a-b-c-(d)-e", roles("latchset", "blade"),
             offset_mm=(-30, 0, 95), axis=(-1, 0, 0), spread=4.0, letters=True),
        Step("6.1", "latch servos onto their frames (tabs screwed on), couplers onto the D-shafts", None,
             ("latch_servo",), offset_mm=(0, 0, 80)),
        Step("7", "side rails", roles("rail"), side_mm=40, offset_mm=(0, 0, 0)),
        Step("9", "cover, then the locking key", names("cover_cross_hole"), offset_mm=(0, 0, 175)),
        Step("9 key", "locking key (after docking)", names("locking_key"), offset_mm=(0, 0, 215)),
    ],
    "octbot": [
        Step("0", "body", names("octbot_body")),
        Step("1", "caster seats and balls", names("caster_seat"), ("caster_ball",), offset_mm=(0, 0, -35)),
        Step("2", "drive motors and wheels", None, ("drive_motor", "wheel"), offset_mm=(0, 0, -10), side_mm=20),
        Step("3", "ring on the rear wall", names("octbot_ring"), offset_mm=(-45, 0, 0)),
        Step("4", "capturer housing on the front wall", names("octbot_capturer_housing"), offset_mm=(40, 0, 0)),
        Step("4.1", "cam disc dropped into its slot from above", names("octbot_finger_cam_disc"),
             offset_mm=(40, 0, 55)),
        Step("4.2", "worm gearmotor slid into its pocket, worm first (from +y)", None, ("worm_motor", "worm"),
             offset_mm=(40, 55, 0)),
        Step("4.3", "fingers into the housing's slots, pegs in the disc's spirals", roles("finger"),
             offset_mm=(85, 0, 0)),
        Step("4.4", "finger retainer over the hooks, two M2 countersunk screws", roles("retainer"),
             offset_mm=(130, 0, 0)),
    ],
    "cube-robot": [
        Step("1", "wheel block, wheels, motors and battery", names("cube_wheel_block"),
             ("wheel", "drive_motor", "battery")),
        Step("2", "connector cuboid", names("cube_connector_cuboid"), offset_mm=(0, 0, 70)),
        Step("2 blocks", "connector blocks: pins front/right, latches rear/left", roles("pin", "pinset", "latchset",
                                                                                      "blade"),
             offset_mm=(0, 0, 70), axis="radial", spread=4.5, side_mm=25, letters=True),
        Step("2.1", "latch servos onto their frames (tabs screwed on); couplers, or the corner block's gear pair",
             None, ("latch_servo", "latch_servo_left", "latch_gear_blade", "latch_gear_servo"),
             offset_mm=(0, 0, 115)),
        Step("3", "sensor cylinder", names("cube_sensor_cylinder"), offset_mm=(0, 0, 200)),
    ],
}

#: The camera of each robot's exploded view (elevation, azimuth in degrees, as in :mod:`render`).
VIEWS: dict[str, tuple[float, float]] = {"cubot": (24, -58), "octbot": (28, -58), "cube-robot": (24, -50)}


def _centre(shape) -> np.ndarray:
    b = shape.BoundingBox()
    return np.array([b.center.x, b.center.y, b.center.z])


def _bounds(shape) -> tuple[np.ndarray, np.ndarray]:
    b = shape.BoundingBox()
    return np.array([b.xmin, b.ymin, b.zmin]), np.array([b.xmax, b.ymax, b.zmax])


def _side_axis(c: np.ndarray) -> np.ndarray:
    """The horizontal robot axis (unit, signed) the point ``c`` lies furthest along."""
    return np.array([np.sign(c[0]) or 1.0, 0, 0]) if abs(c[0]) >= abs(c[1]) else np.array([0, np.sign(c[1]) or 1.0, 0])


def _inner(shape, axis: np.ndarray) -> float:
    """How far along ``axis`` the part's inner face (the side facing against the axis) lies (mm)."""
    lo, hi = _bounds(shape)
    return float(np.where(axis > 0, lo, -hi) @ np.abs(axis)) if np.count_nonzero(axis) == 1 else \
        float(min(np.asarray(lo) @ axis, np.asarray(hi) @ axis))


def _letter(name: str) -> str:
    m = re.match(r"(?:pinset|latchset)_([a-e])_", name)
    return m.group(1) if m else ""


def self_letter(it) -> str:
    """The letter of a connector-block part (``pinset_b_...`` -> ``b``), as in its file name."""
    return _letter(it.name)


@dataclass(frozen=True)
class Item:
    """One thing in the exploded view: its name, role, shape (moved, robot frame, mm), colour and step."""

    name: str
    role: str
    shape: object
    colour: tuple[float, float, float]
    step: Step
    offset_mm: tuple[float, float, float]


def plan(robot) -> list[Step]:
    """The assembly steps of ``robot`` (by :attr:`Robot.name`); KeyError names the robots with a plan."""
    try:
        return PLANS[robot.name]
    except KeyError:
        raise KeyError(f"no exploded-view plan for {robot.name!r} (have: {', '.join(PLANS)})") from None


def exploded_items(robot) -> list[Item]:
    """Every printed part of ``robot`` and its stepped bought parts, moved apart (robot frame, mm).

    Each placed part belongs to the first step that selects it; a printed part no step selects is
    an error (the plan must cover the robot: a new part has to be put in the assembly order)."""
    import cadquery as cq

    from cubot_cad.robots.base import role_colour

    steps = plan(robot)
    chosen: list[tuple[Step, str, str, object, tuple]] = []
    missing = []
    for p in robot.placed:
        st = next((s for s in steps if s.parts is not None and s.parts(p.part.name, p.role)), None)
        if st is None:
            missing.append(p.part.name)
            continue
        chosen.append((st, p.part.name, p.role, p.shape, role_colour(p.role)))
    if missing:
        raise ValueError(f"{robot.name}: no assembly step selects {sorted(set(missing))} (add them to PLANS)")
    comps = {c.key: c for c in robot.components()}
    for st in steps:
        for key in st.components:
            if key in comps:
                for s in comps[key].solids():
                    chosen.append((st, key, comps[key].role, s, tuple(comps[key].colour)))
    # the innermost face of each step's group along its axis (per side for radial steps)
    ref: dict[tuple, float] = {}
    axes = []
    for st, _n, _r, shape, _c in chosen:
        c = _centre(shape)
        ax = _side_axis(c) if st.axis == "radial" else np.asarray(st.axis, dtype=float)
        ax = ax / np.linalg.norm(ax)
        axes.append(ax)
        k = (id(st), tuple(ax))
        ref[k] = min(ref.get(k, np.inf), _inner(shape, ax))
    # the base (the first step's printed parts): side moves clear its bounding box
    base = [_bounds(shape) for st, _n, _r, shape, _c in chosen if st is steps[0] and st.parts is not None]
    base_lo = np.min([b[0] for b in base], axis=0)
    base_hi = np.max([b[1] for b in base], axis=0)
    out = []
    for (st, name, role, shape, col), ax in zip(chosen, axes, strict=True):
        c = _centre(shape)
        off = np.asarray(st.offset_mm, dtype=float).copy()
        if st.spread:
            off += ax * st.spread * (_inner(shape, ax) - ref[(id(st), tuple(ax))])
        if st.side_mm:
            sa = _side_axis(c)
            lo, hi = _bounds(shape)
            # where the spread put the inner face, and where the base's outer face is, along sa
            inner = float(np.where(sa > 0, lo, -hi) @ np.abs(sa)) + float(off @ sa)
            outer = float(np.where(sa > 0, base_hi, -base_lo) @ np.abs(sa))
            off += sa * (max(0.0, outer - inner) + st.side_mm)
        moved = shape.translate(cq.Vector(*map(float, off)))
        out.append(Item(name, role, moved, col, st, tuple(float(v) for v in off)))
    return out


def exploded_labels(robot, items: list[Item], elev: float, azim: float) -> list[Label]:
    """Callouts: one per step at its largest item nearest the camera, or with ``letters`` one per
    lettered part of the block nearest the camera (``5a``..``5e``; the pins are ``e``)."""
    from cubot_cad.outputs.render import camera_axes

    eye, _, _ = camera_axes(elev, azim)
    labels = []
    for st in plan(robot):
        its = [i for i in items if i.step is st]
        if not its:
            continue
        if st.letters:
            # one block: its stack axis faces the camera and lies as much across the view as can be
            # (so the plates spread out on the screen), and of those the one nearest the camera; a
            # block's parts lie within 25 mm of each other across the stack axis (blocks: 36 mm
            # wide and further apart)
            lettered = [(self_letter(it), it) for it in its]
            lettered = [(let, it) for let, it in lettered if let]
            if not lettered:
                continue

            def stack_axis(it, st=st):
                a = _side_axis(_centre(it.shape)) if st.axis == "radial" else np.asarray(st.axis, dtype=float)
                return a / np.linalg.norm(a)

            def view_score(li):
                a, c = stack_axis(li[1]), _centre(li[1].shape)
                return (bool(a @ eye > 0), -round(abs(float(a @ eye)), 2), float(c @ eye))

            _, near = max(lettered, key=view_score)
            c0 = _centre(near.shape)
            ax = stack_axis(near)

            def across(it, c0=c0, ax=ax):
                d = _centre(it.shape) - c0
                return float(np.linalg.norm(d - (d @ ax) * ax))

            by_letter: dict[str, Item] = {}
            for let, it in lettered:
                if across(it) > 25.0:
                    continue
                best = by_letter.get(let)
                if best is None or _centre(it.shape) @ eye > _centre(best.shape) @ eye + 1e-6:
                    by_letter[let] = it
            for let in sorted(by_letter):
                lo, hi = _bounds(by_letter[let].shape)
                top = ((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, hi[2])  # the top edge shows over the stack
                labels.append(Label(f"{st.number.split()[0]}{let}", top))
        else:
            def size(it):
                lo, hi = _bounds(it.shape)
                return float(np.prod(np.maximum(hi - lo, 1.0)))

            big = max(size(i) for i in its)
            cand = [i for i in its if size(i) >= 0.5 * big]
            it = max(cand, key=lambda i: _centre(i.shape) @ eye)
            labels.append(Label(st.number, tuple(_centre(it.shape))))
    return labels


def exploded_view(robot, path: str | os.PathLike, size_px: tuple[int, int] = DEFAULT_SIZE_PX) -> Path:
    """Render ``robot`` exploded along its assembly directions with a numbered callout per step of
    docs/assembly.md (:data:`PLANS`) to the PNG ``path`` (written atomically); returns the path."""
    elev, azim = VIEWS.get(robot.name, (24, -58))
    items = exploded_items(robot)
    labels = exploded_labels(robot, items, elev, azim)
    title = f"{robot.title}: exploded view, callouts = assembly steps in docs/assembly.md"
    return render_shapes([([i.shape], i.colour) for i in items], path, title, elev=elev, azim=azim,
                         size_px=size_px, labels=labels)


def steps_markdown(robot) -> str:
    """The step table docs/assembly.md shows beside the exploded view (callout, what, parts)."""
    items = exploded_items(robot)
    rows = ["| callout | step | parts |", "|---|---|---|"]
    for st in plan(robot):
        names_ = sorted({i.name for i in items if i.step is st})
        if st.letters:
            by: dict[str, list[str]] = {}
            for n in names_:
                if _letter(n):
                    by.setdefault(_letter(n), []).append(f"`{n}`")
            what = ", ".join(f"{k}: {' / '.join(v)}" for k, v in sorted(by.items()))
        else:
            what = ", ".join(f"`{n}`" for n in names_)
        n = st.number.split()[0]
        callout = f"{n}a-{n}e" if st.letters else st.number
        rows.append(f"| {callout} | {st.title} | {what} |")
    return "\n".join(rows) + "\n"


#: Robots with an exploded view in docs/assembly.md, and the markers round each generated block.
DOC_ROBOTS = ("cubot", "octbot", "cube-robot")


def _markers(name: str) -> tuple[str, str]:
    return f"<!-- exploded:{name} (generated: python -m cubot_cad.outputs.exploded) -->", f"<!-- /exploded:{name} -->"


def doc_block(robot) -> str:
    """The generated block of docs/assembly.md for ``robot``: the image and its callout table."""
    start, end = _markers(robot.name)
    return (f"{start}\n![{robot.title} exploded: each part moved out along the way it goes on, callouts = the steps "
            f"below](img/{robot.name}-exploded.png)\n\n{steps_markdown(robot)}{end}")


def update_docs(md_path: str | os.PathLike, robots_: dict) -> bool:
    """Replace each robot's generated block in ``md_path`` (between its markers); returns whether
    the file changed. A robot whose markers are missing is an error (put them where it belongs)."""
    from cubot_cad.atomic import write_text

    p = Path(md_path)
    text = old = p.read_text(encoding="utf-8")
    for name, robot in robots_.items():
        start, end = _markers(name)
        i, j = text.find(start), text.find(end)
        if i < 0 or j < i:
            raise ValueError(f"{p}: no generated block for {name} (markers {start!r} ... {end!r})")
        text = text[:i] + doc_block(robot) + text[j + len(end):]
    if text != old:
        write_text(p, text)
    return text != old


def main(argv: list[str] | None = None) -> int:
    """``python -m cubot_cad.outputs.exploded [--docs docs/assembly.md] [--img docs/img] [--no-images]``:
    render the exploded views and refresh their blocks in the assembly guide."""
    import argparse

    from cubot_cad.robots.registry import make_robot

    ap = argparse.ArgumentParser(prog="python -m cubot_cad.outputs.exploded", description=main.__doc__)
    ap.add_argument("--docs", default="docs/assembly.md")
    ap.add_argument("--img", default="docs/img")
    ap.add_argument("--no-images", action="store_true")
    a = ap.parse_args(argv)
    robots_ = {n: make_robot(n) for n in DOC_ROBOTS}
    if not a.no_images:
        for n, r in robots_.items():
            print(exploded_view(r, Path(a.img) / f"{n}-exploded.png"))
    print(f"{a.docs}: {'updated' if update_docs(a.docs, robots_) else 'up to date'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())


__all__ = ["DOC_ROBOTS", "doc_block", "main", "update_docs", "PLANS", "Step", "VIEWS", "exploded_items", "exploded_labels", "exploded_view", "plan", "steps_markdown"]
