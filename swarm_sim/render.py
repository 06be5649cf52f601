"""Pictures of a run in the style of the thesis's figures: top view (arena, void in black,
target in blue, obstacles in red, robots as squares coloured by state, the structure
highlighted and numbered, a clock) and a side-view strip of the structure over the void.

Frames are recorded during :func:`swarm_sim.runner.simulate` (``Recorder``, every
``every_s`` simulated seconds) and rendered afterwards with matplotlib (Agg), to MP4
through imageio-ffmpeg or to GIF through imageio, or as PNG snapshots.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from cubot_cad.atomic import atomic_path, write_via

from .errors import InputError
from .params import Params
from .state import Mode, SwarmState, thesis_state

#: legend and header names of the modes (the header counts the same modes the colours show)
MODE_NAMES = {
    Mode.EXPLORE: "exploring (-1)", Mode.SEED: "seed", Mode.RECRUIT: "recruit", Mode.MEMBER: "in structure",
    Mode.TARGET: "target search (-2)", Mode.RETREAT: "retreating (-3)", Mode.STOPPED: "stopped",
    Mode.PIER: "in a pier (-4)",
}

#: event captions; the events marked True are where snapshots are taken
CAPTIONS = {
    "seed": ("robot {r} found the edge: it is the seed", True),
    "aligned": ("the seed is aligned with the edge", False),
    "recruit": ("robot {r} called to the rear", False),
    "dock": ("robot {r} docked at the rear", False),
    "hand_over": ("recruit {r} made no progress: handed over", False),
    "far_ledge": ("the front reached the far ledge (landed)", True),
    "switch": ("switch to {level} ({lines} x {layers} per row)", True),
    "release_front": ("robot {r} released onto the target ground", True),
    "release_rear": ("robot {r} released at the rear", False),
    "retreat": ("retreat: {why}", True),
    "target_found": ("robot {r} found the target", True),
    "dissolved": ("the structure has dissolved", True),
    "stopped": ("the swarm stopped", False),
    "timeout": ("time limit reached", True),
    "fault": ("robot {r} failed ({mode})", True),
    "fault_detected": ("robot {r}'s failure detected ({how}, {delay_s:.1f} s)", False),
    "pushed_clear": ("failed robot {r} pushed clear", False),
    "pier_site": ("a pier is started beyond the front", True),
    "pier_lowered": ("failed robot {r} lowered onto the pier ({robots}/{needed})", True),
    "pier_complete": ("the pier is complete: the line spans on from it", True),
    "structure_abandoned": ("the structure is abandoned ({why})", True),
    "stranded": ("stranded: {why}", True),
}
CAPTION_S = 4.0  # simulated seconds an event's caption stays on screen


def caption(ev) -> str | None:
    """The one-line caption of an event ``(t_s, kind, robot, data)``; None for silent ones."""
    t, kind, r, data = ev
    if kind not in CAPTIONS:
        return None
    try:
        return CAPTIONS[kind][0].format(r=r, **data)
    except (KeyError, IndexError):
        return kind.replace("_", " ")


COLOURS = {  # by mode
    Mode.EXPLORE: "#2ca02c",   # -1 initial exploration: green
    Mode.SEED: "#d62728",      # seed: red
    Mode.RECRUIT: "#ff7f0e",   # recruit approaching: orange
    Mode.MEMBER: "#9467bd",    # in the structure: purple
    Mode.TARGET: "#1f77b4",    # -2 target exploration: blue
    Mode.RETREAT: "#8c564b",   # -3 retreat: brown
    Mode.STOPPED: "#7f7f7f",   # stopped: grey
    Mode.PIER: "#17becf",      # -4 stacked in a pier (failed robots): cyan
}


@dataclass
class Frame:
    t_s: float
    x: np.ndarray
    y: np.ndarray
    h: np.ndarray
    mode: np.ndarray
    state: np.ndarray
    members: tuple
    front_s_cm: float | None
    seed: int
    row_size: int = 1
    lines: int = 1
    layer: np.ndarray | None = None   # struct_layer (-1 free): top-view shade, side-view height
    shell: tuple = ()                 # robots in the feet of a tapering arch (OPEN = -1 slots)
    events: tuple = ()                # the events since the previous frame (t_s, kind, robot, data)
    captions: tuple = ()              # captions of the events of the last CAPTION_S seconds
    failed: np.ndarray | None = None  # robots that have failed (faults; drawn with a red rim)


@dataclass
class Recorder:
    """Keeps a frame every ``every_s`` simulated seconds (and the last one)."""

    every_s: float = 0.5
    frames: list = field(default_factory=list)
    _next: float = 0.0
    _seen: int = 0
    _recent: list = field(default_factory=list)

    def __call__(self, s: SwarmState) -> None:
        if s.t_s + 1e-9 >= self._next or s.phase >= 4:
            st = s.structure
            new = tuple(s.events[self._seen:])
            self._seen = len(s.events)
            self._recent = [(t, c) for t, c in self._recent if t >= s.t_s - CAPTION_S]
            self._recent += [(e[0], c) for e in new if (c := caption(e)) is not None]
            self.frames.append(Frame(s.t_s, s.x_cm.copy(), s.y_cm.copy(), s.heading_rad.copy(), s.mode.copy(),
                                     thesis_state(s), st.members if st else (), st.front_s_cm if st else None,
                                     s.seed_robot, st.lines * st.layers if st else 1, st.lines if st else 1,
                                     s.struct_layer.copy(), st.shell if st else (), new,
                                     tuple(f"t={t:.1f} s  {c}" for t, c in self._recent[-3:]),
                                     None if s.fault_flags is None else s.fault_flags != 0))
            self._next = s.t_s + self.every_s


def _rgb(hexcol: str) -> np.ndarray:
    return np.array([int(hexcol[i:i + 2], 16) / 255.0 for i in (1, 3, 5)])


def _robot_polys(f: Frame, p: Params) -> np.ndarray:
    hl, hw = 0.5 * p.robot_length_cm, 0.5 * p.robot_width_cm
    loc = np.array([[hl, hw], [hl, -hw], [-hl, -hw], [-hl, hw]])
    c, s = np.cos(f.h), np.sin(f.h)
    px = f.x[:, None] + c[:, None] * loc[None, :, 0] - s[:, None] * loc[None, :, 1]
    py = f.y[:, None] + s[:, None] * loc[None, :, 0] + c[:, None] * loc[None, :, 1]
    return np.stack([px, py], axis=2)


class Renderer:
    """A figure whose static parts (arena, void, target, obstacles, ground) are drawn once;
    :meth:`update` moves the robots, the structure, the labels and the clock."""

    def __init__(self, p: Params):
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.collections import PolyCollection
        from matplotlib.patches import Circle, Rectangle

        self.p = p
        self.Rectangle = Rectangle
        self.fig = fig = plt.figure(figsize=(10, 7.6), dpi=100, layout="constrained")
        gs = fig.add_gridspec(2, 1, height_ratios=[4, 1])
        self.ax = ax = fig.add_subplot(gs[0])
        ax.add_patch(Rectangle((0, 0), p.arena_w_cm, p.arena_h_cm, fill=False, lw=1.5, ec="k"))
        ax.add_patch(Rectangle((p.void_x0_cm, 0), p.void_width_cm, p.arena_h_cm, color="k"))
        ax.add_patch(Circle((p.target_x_cm, p.target_y_cm), p.target_radius_cm, color="b"))
        for ox, oy, r in p.obstacles:
            ax.add_patch(Circle((ox, oy), r, color="r"))
        self.robots = PolyCollection([], edgecolors="k", linewidths=0.4)
        self.outline = PolyCollection([], facecolors="none", edgecolors="gold", linewidths=1.6)
        ax.add_collection(self.robots)
        ax.add_collection(self.outline)
        ax.set_xlim(-5, p.arena_w_cm + 5)
        ax.set_ylim(-5, p.arena_h_cm + 5)
        ax.set_aspect("equal")
        ax.set_xlabel("x (cm)")
        ax.set_ylabel("y (cm)")
        self.title = ax.set_title(" ", fontsize=10, loc="left")
        self.caption = ax.text(0.99, 0.98, "", transform=ax.transAxes, ha="right", va="top", fontsize=9,
                               bbox={"boxstyle": "round", "fc": "white", "ec": "0.6", "alpha": 0.85})
        handles = [Rectangle((0, 0), 1, 1, color=c) for c in COLOURS.values()]
        fig.legend(handles, [MODE_NAMES[m] for m in COLOURS], fontsize=9, loc="outside lower center", ncol=4,
                   frameon=False)
        self.sv = sv = fig.add_subplot(gs[1])
        L = p.robot_length_cm
        self.H = 0.85 * L
        x0, x1 = p.void_x0_cm, p.void_x1_cm
        sv.add_patch(Rectangle((0, -3 * L), x0, 3 * L, color="#c8b48a"))
        sv.add_patch(Rectangle((x1, -3 * L), p.arena_w_cm - x1, 3 * L, color="#c8b48a"))
        if 0 < p.void_depth_cm < 3 * L:  # the void's floor, where piers stand (swarm_sim.behaviour.piers)
            sv.add_patch(Rectangle((x0, -3 * L), x1 - x0, 3 * L - p.void_depth_cm, color="#a8946a"))
        self.side = PolyCollection([], edgecolors="k", linewidths=0.5)
        sv.add_collection(self.side)
        self.free_dots = sv.scatter([], [], s=4)
        # the side strip looks at the void and a stretch of ground either side (feet, counterweight)
        reach = max(25 * L, p.void_width_cm)
        sv.set_xlim(max(-5, x0 - reach), min(p.arena_w_cm + 5, x1 + reach))
        sv.set_ylim(-3 * L, 3 * L)
        sv.set_aspect("equal")
        sv.set_yticks([])
        sv.set_xlabel("side view along the structure (cm)")
        self.texts: list = []
        # the fast path (:meth:`frame_rgba`): the positions a fresh figure starts from, the layout's
        # inputs it was last computed for, and the static parts drawn once for that layout
        self._pos0 = [(a, a.get_position(original=True).frozen()) for a in (ax, sv)]
        self._key = None
        self._bg = None

    def update(self, f: Frame):
        p, L, H = self.p, self.p.robot_length_cm, self.H
        polys = _robot_polys(f, p)
        layer = f.layer if f.layer is not None else np.zeros(len(f.x), dtype=int)
        # higher layers drawn last (on top), members shaded darker with each layer
        order = np.argsort(layer, kind="stable")
        self.robots.set_verts(polys[order])
        cols = np.array([_rgb(COLOURS[Mode(int(m))]) for m in f.mode])
        ins = (f.mode == Mode.MEMBER) & (layer > 0)
        cols[ins] = cols[ins] * (1.0 - 0.22 * np.minimum(layer[ins], 3))[:, None]
        self.robots.set_facecolors(cols[order])
        if f.failed is not None:  # failed robots: a thick red rim
            self.robots.set_edgecolors(np.where(f.failed[order, None], _rgb("#d62728"), _rgb("#000000")))
            self.robots.set_linewidths(np.where(f.failed[order], 1.6, 0.4))
        else:  # as drawn at the start (a reused figure keeps no rims of an earlier frame)
            self.robots.set_edgecolors("k")
            self.robots.set_linewidths(0.4)
        for t in self.texts:
            t.remove()
        self.texts = []
        ids = np.array(f.members, dtype=int)
        slots = np.flatnonzero(ids >= 0)  # open slots (-1) of a switch not yet filled
        shell = np.array([i for i in f.shell if i >= 0], dtype=int)
        self.outline.set_verts(polys[np.r_[ids[slots], shell]] if len(slots) + len(shell) else [])
        if 0 < len(ids) <= 40 * f.row_size:
            for m, i in enumerate(ids):
                if i >= 0 and (m % f.row_size) < f.lines:  # label the ground layer with the row number
                    self.texts.append(self.ax.text(f.x[i], f.y[i], str(m // f.row_size + 1), ha="center",
                                                   va="center", fontsize=6, color="w"))
        self.title.set_text(f"{p.preset}  N = {p.robots}  void {p.void_width} widths   t = {f.t_s:7.2f} s\n"
                            + header_counts(f.mode))
        self.caption.set_text("\n".join(f.captions))
        self.caption.set_visible(bool(f.captions))
        # side view: every structure robot at (x, layer); the taper and both feet show
        side, scol, top = [], [], 0
        x0, x1 = p.void_x0_cm, p.void_x1_cm
        inside = np.r_[ids[slots], shell].astype(int) if f.front_s_cm is not None else np.zeros(0, int)
        for i in inside:
            left, z = float(f.x[i]) - 0.5 * L, max(int(layer[i]), 0)
            over = not (left + L <= x0 or left >= x1)
            side.append([(left, z * H), (left + L, z * H), (left + L, (z + 1) * H), (left, (z + 1) * H)])
            scol.append("#e377c2" if over else "#9467bd")
            top = max(top, z + 1)
        # piers: failed robots stacked on the void's floor, the lowest first (struct_layer -1, -2, ..)
        pier = np.flatnonzero(f.mode == Mode.PIER)
        if pier.size and p.void_depth_cm > 0:
            hp = p.void_depth_cm / max(p.pier_robots, 1)
            for i in pier:
                left, lvl = float(f.x[i]) - 0.5 * L, -int(layer[i]) - 1
                b = -p.void_depth_cm + lvl * hp
                side.append([(left, b), (left + L, b), (left + L, b + hp), (left, b + hp)])
                scol.append(COLOURS[Mode.PIER])
        self.side.set_verts(side)
        self.side.set_facecolors(scol)
        self.sv.set_ylim(-3 * L, max(3 * L, (top + 1) * H))
        members = set(inside.tolist()) | set(pier.tolist())
        free = [i for i in range(len(f.x)) if i not in members]
        self.free_dots.set_offsets(np.c_[f.x[free], np.full(len(free), 0.5 * H)] if free else np.empty((0, 2)))
        self.free_dots.set_color([COLOURS[Mode(int(f.mode[i]))] for i in free] if free else [])
        return self.fig

    # -- the video's fast path --------------------------------------------------------------
    # A full ``canvas.draw()`` per frame (~90 ms) spends most of its time on the constrained
    # layout (the extents of every tick label, label, title and the legend) and on drawing the
    # static parts (arena, void, ledges, ticks, labels, legend) again. Here the layout is computed only when one of its inputs
    # changes (the side view's height, the title's size), exactly as ``savefig`` of a fresh
    # figure computes it; the static parts are drawn once per layout and the frame's moving
    # parts (robots, outline, labels, caption, title, side view) are drawn over a copy of them
    # in the order a full draw uses. A frame whose moving parts reach an axes' frame (where
    # the spines, drawn over them in a full draw, would be drawn under them here) is drawn in
    # full. The frame is the one ``fig.savefig(dpi=100)`` writes for the same state.

    def _moving(self) -> list:
        """The artists :meth:`update` changes, in the order a full draw of the figure draws them."""
        dyn = {id(a) for a in (self.robots, self.outline, self.caption, self.title, self.side, self.free_dots,
                               *self.texts)}
        return [a for ax in self.fig.axes for a in sorted(ax.get_children(), key=lambda a: a.get_zorder())
                if id(a) in dyn]

    def _layout_key(self):
        size = self.title.get_window_extent(self.fig.canvas.get_renderer()).size
        return tuple(self.sv.get_ylim()), tuple(float(v) for v in size)

    def _draw_frozen(self) -> None:
        """``canvas.draw()`` with the positions as they are (no layout pass, as ``savefig`` draws)."""
        eng = self.fig.get_layout_engine()
        self.fig.set_layout_engine("none")
        try:
            self.fig.canvas.draw()
        finally:
            self.fig.set_layout_engine(eng)

    def reset_layout(self) -> None:
        """Put the axes back where a fresh figure has them: a constrained-layout pass starts from
        the positions it finds, so without this a reused figure's layout drifts by a pixel or
        two from a fresh one's after its first draw."""
        for a, pos in self._pos0:
            a._set_position(pos, which="both")

    def _relayout(self) -> None:
        """The layout ``savefig`` computes for a fresh figure (one constrained-layout pass from
        the initial positions in a dry-run draw, then a draw with the layout engine off), and
        the static parts drawn once for it."""
        self.reset_layout()
        self.fig.draw_without_rendering()
        moving = self._moving()
        for a in moving:
            a.set_animated(True)
        try:
            self._draw_frozen()
        finally:
            for a in moving:
                a.set_animated(False)
        self._bg = self.fig.canvas.copy_from_bbox(self.fig.bbox)

    def _reaches_frame(self, margin_px: float = 6.0) -> bool:
        """Do the robots, the outline or the side view come within ``margin_px`` of an axes' frame?"""
        for ax, polys, dots in ((self.ax, (self.robots, self.outline), None), (self.sv, (self.side,), self.free_dots)):
            pts = [path.vertices for c in polys for path in c.get_paths()]
            if dots is not None:
                pts.append(np.asarray(dots.get_offsets(), dtype=float).reshape(-1, 2))
            pts = [q for q in pts if len(q)]
            if not pts:
                continue
            xy = ax.transData.transform(np.concatenate(pts))
            b = ax.bbox
            if (xy[:, 0].min() < b.x0 + margin_px or xy[:, 0].max() > b.x1 - margin_px
                    or xy[:, 1].min() < b.y0 + margin_px or xy[:, 1].max() > b.y1 - margin_px):
                return True
        return False

    def frame_rgba(self, f: Frame) -> np.ndarray:
        """The frame of state ``f`` as an ``(H, W, 4)`` uint8 view of the canvas (valid until the
        next call): the pixels ``savefig(dpi=100)`` of a fresh figure gives, drawn fast."""
        self.update(f)
        key = self._layout_key()
        if key != self._key:
            self._relayout()
            self._key = key
        if self._reaches_frame():
            self._draw_frozen()
        else:
            canvas = self.fig.canvas
            canvas.restore_region(self._bg)
            for a in self._moving():
                self.fig.draw_artist(a)
        return np.asarray(self.fig.canvas.buffer_rgba())

    def frame_rgba_full(self, f: Frame) -> np.ndarray:
        """The frame by a full ``canvas.draw()`` with the layout engine, as videos were drawn
        before the fast path (kept for the benchmark; from the second frame on, its layout has
        had one more pass than ``savefig``'s and sits a pixel or two off)."""
        fig = self.update(f)
        fig.canvas.draw()
        return np.asarray(fig.canvas.buffer_rgba())

    def close(self):
        import matplotlib.pyplot as plt

        plt.close(self.fig)


def header_counts(mode: np.ndarray) -> str:
    """Robots per mode, named as in the legend (seed and recruits counted with the structure
    they are part of or joining only by their own names)."""
    parts = [f"{MODE_NAMES[m]} {int((mode == m).sum())}" for m in COLOURS if (mode == m).any()]
    return "   ".join(parts)


def draw(f: Frame, p: Params) -> Renderer:
    """One frame (top view + side-view strip); ``.fig`` is the matplotlib Figure."""
    r = Renderer(p)
    r.update(f)
    return r


def write_video(frames: list, p: Params, path: str | os.PathLike, fps: int = 10, progress=lambda it, total: it,
                fast: bool = True) -> Path:
    """MP4 (imageio-ffmpeg) or GIF (Pillow) of the frames, written atomically. Frames are drawn
    one at a time (:meth:`Renderer.frame_rgba`) and streamed to the encoder: ffmpeg gets each
    RGB frame through its pipe; the GIF writer gets each frame already reduced to its palette
    (Pillow's adaptive median cut, what it would do itself) and a frame delay of
    ``1000 / fps`` milliseconds. ``fast=False`` draws every frame in full (the old path, for
    the benchmark)."""
    path = Path(path)
    ext = path.suffix.lower()
    if ext not in (".mp4", ".gif"):
        raise InputError(f"--video {path}: use a .mp4 or .gif file name")
    try:
        if ext == ".mp4":
            import imageio.v2 as imageio
        from PIL import Image
    except ImportError as exc:  # pragma: no cover - video extra missing
        raise InputError(f"--video needs imageio (pip install 'voidcross[video]'): {exc}") from None
    rend = Renderer(p)
    grab = rend.frame_rgba if fast else rend.frame_rgba_full
    try:
        with atomic_path(path) as tmp:
            if ext == ".mp4":
                with imageio.get_writer(tmp, format="FFMPEG", fps=fps, macro_block_size=1) as w:
                    for f in progress(frames, len(frames)):
                        w.append_data(grab(f)[:, :, :3])
            else:
                pal = (Image.fromarray(grab(f)[:, :, :3]).convert("P", palette=Image.Palette.ADAPTIVE)
                       for f in progress(frames, len(frames)))
                first = next(pal, None)
                if first is not None:
                    # Pillow's GIF writer takes the frame delay in milliseconds
                    first.save(tmp, format="GIF", save_all=True, append_images=pal, duration=1000.0 / fps, loop=0)
    finally:
        rend.close()
    return path


def snapshot_frames(frames: list, count: int) -> list[int]:
    """Indices of the frames worth a snapshot: the first and the last, then the frames of the
    run's events (seed, landing, switches, first release, retreat, target found, dissolved;
    evenly thinned when there are more than ``count``), topped up with evenly spaced frames."""
    n = len(frames)
    if n == 0 or count < 1:
        return []
    ends = sorted({0, n - 1})[:count]
    marks, seen = [], set()
    for i, f in enumerate(frames):
        for e in f.events:
            kind = e[1]
            if CAPTIONS.get(kind, ("", False))[1] and (kind != "release_front" or kind not in seen):
                seen.add(kind)
                marks.append(i)
    marks = [i for i in dict.fromkeys(marks) if i not in ends]
    room = count - len(ends)
    if len(marks) > room:
        marks = [marks[int(k)] for k in np.linspace(0, len(marks) - 1, room).round().astype(int)] if room else []
    idx = set(ends) | set(marks)
    for i in np.linspace(0, n - 1, count).round().astype(int):  # top up, evenly spaced
        if len(idx) >= min(count, n):
            break
        idx.add(int(i))
    return sorted(idx)


def write_snapshots(frames: list, p: Params, directory: str | os.PathLike, count: int = 6,
                    progress=lambda it, total: it) -> list[Path]:
    """PNG snapshots (150 dpi) at the run's events (:func:`snapshot_frames`); file names carry
    the simulated time."""
    d = Path(directory)
    d.mkdir(parents=True, exist_ok=True)
    idx = snapshot_frames(frames, count)
    out = []
    rend = Renderer(p)
    for i in progress(idx, len(idx)):
        f = frames[i]
        fig = rend.update(f)
        rend.reset_layout()  # every snapshot laid out as a fresh figure's
        target = d / f"t{f.t_s:09.2f}s.png"
        write_via(target, lambda tmp, fig=fig: fig.savefig(tmp, format="png", dpi=150))
        out.append(target)
    rend.close()
    return out
