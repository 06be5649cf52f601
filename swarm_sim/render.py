"""Pictures of a run in the style of the thesis's figures: top view (arena, void in black,
target in blue, obstacles in red, robots as squares coloured by state, the structure
highlighted and numbered, a clock) and a side-view strip of the structure over the void.

Frames are recorded during :func:`swarm_sim.runner.simulate` (``Recorder``, every
``every_s`` simulated seconds) and rendered afterwards with matplotlib (Agg), to MP4
through imageio-ffmpeg or to GIF through imageio, or as PNG snapshots.
"""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .errors import InputError
from .params import Params
from .state import Mode, SwarmState, thesis_state

COLOURS = {  # by mode
    Mode.EXPLORE: "#2ca02c",   # -1 initial exploration: green
    Mode.SEED: "#d62728",      # seed: red
    Mode.RECRUIT: "#ff7f0e",   # recruit approaching: orange
    Mode.MEMBER: "#9467bd",    # in the structure: purple
    Mode.TARGET: "#1f77b4",    # -2 target exploration: blue
    Mode.RETREAT: "#8c564b",   # -3 retreat: brown
    Mode.STOPPED: "#7f7f7f",   # stopped: grey
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


@dataclass
class Recorder:
    """Keeps a frame every ``every_s`` simulated seconds (and the last one)."""

    every_s: float = 0.5
    frames: list = field(default_factory=list)
    _next: float = 0.0

    def __call__(self, s: SwarmState) -> None:
        if s.t_s + 1e-9 >= self._next or s.phase >= 4:
            st = s.structure
            self.frames.append(Frame(s.t_s, s.x_cm.copy(), s.y_cm.copy(), s.heading_rad.copy(), s.mode.copy(),
                                     thesis_state(s), st.members if st else (), st.front_s_cm if st else None,
                                     s.seed_robot, st.lines * st.layers if st else 1, st.lines if st else 1))
            self._next = s.t_s + self.every_s


def _robot_polys(f: Frame, p: Params) -> np.ndarray:
    hl, hw = 0.5 * p.robot_length_cm, 0.5 * p.robot_width_cm
    loc = np.array([[hl, hw], [hl, -hw], [-hl, -hw], [-hl, hw]])
    c, s = np.cos(f.h), np.sin(f.h)
    px = f.x[:, None] + c[:, None] * loc[None, :, 0] - s[:, None] * loc[None, :, 1]
    py = f.y[:, None] + s[:, None] * loc[None, :, 0] + c[:, None] * loc[None, :, 1]
    return np.stack([px, py], axis=2)


def draw(f: Frame, p: Params, fig=None):
    """One frame as a matplotlib Figure (top view + side-view strip)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection
    from matplotlib.patches import Circle, Rectangle

    if fig is None:
        fig = plt.figure(figsize=(10, 7.2), dpi=80)
    fig.clf()
    gs = fig.add_gridspec(2, 1, height_ratios=[4, 1])
    ax = fig.add_subplot(gs[0])
    ax.add_patch(Rectangle((0, 0), p.arena_w_cm, p.arena_h_cm, fill=False, lw=1.5, ec="k"))
    ax.add_patch(Rectangle((p.void_x0_cm, 0), p.void_width_cm, p.arena_h_cm, color="k"))
    ax.add_patch(Circle((p.target_x_cm, p.target_y_cm), p.target_radius_cm, color="b"))
    for ox, oy, r in p.obstacles:
        ax.add_patch(Circle((ox, oy), r, color="r"))
    polys = _robot_polys(f, p)
    cols = [COLOURS[Mode(int(m))] for m in f.mode]
    ax.add_collection(PolyCollection(polys, facecolors=cols, edgecolors="k", linewidths=0.4))
    if f.members:
        ids = np.array(f.members)
        ax.add_collection(PolyCollection(polys[ids], facecolors="none", edgecolors="gold", linewidths=1.6))
        if len(ids) <= 40 * f.row_size:
            for m, i in enumerate(ids):
                if (m % f.row_size) < f.lines:  # label the ground layer with the row number
                    ax.text(f.x[i], f.y[i], str(m // f.row_size + 1), ha="center", va="center", fontsize=6,
                            color="w")
    ax.set_xlim(-5, p.arena_w_cm + 5)
    ax.set_ylim(-5, p.arena_h_cm + 5)
    ax.set_aspect("equal")
    ax.set_xlabel("x (cm)")
    ax.set_ylabel("y (cm)")
    counts = {k: int((f.state == v).sum()) for k, v in (("-1", -1), ("-2", -2), ("-3", -3))}
    ax.set_title(f"{p.preset}  N={p.robots}  void={p.void_width} widths  t = {f.t_s:7.2f} s   "
                 f"structure {len(f.members)}  states -1:{counts['-1']} -2:{counts['-2']} -3:{counts['-3']}",
                 fontsize=9)
    handles = [Rectangle((0, 0), 1, 1, color=c) for c in COLOURS.values()]
    ax.legend(handles, ["explore -1", "seed", "recruit", "structure 1..n", "target -2", "retreat -3", "stopped"],
              fontsize=6, loc="upper left", ncol=7, frameon=False, bbox_to_anchor=(0, -0.08))
    # side view: ground, void and the structure's line at the ledge height
    sv = fig.add_subplot(gs[1])
    L = p.robot_length_cm
    H = 0.85 * L
    x0, x1 = p.void_x0_cm, p.void_x1_cm
    sv.add_patch(Rectangle((0, -3 * L), x0, 3 * L, color="#c8b48a"))
    sv.add_patch(Rectangle((x1, -3 * L), p.arena_w_cm - x1, 3 * L, color="#c8b48a"))
    if f.front_s_cm is not None and f.members:
        for m in range(len(f.members)):
            row, q = divmod(m, f.row_size)
            if q % f.lines:
                continue  # side lines hide behind the core line in the side view
            layer = q // f.lines
            left = x0 + f.front_s_cm - (row + 1) * L
            over = not (left + L <= x0 or left >= x1)
            sv.add_patch(Rectangle((left, layer * H), L, H, fc="#9467bd" if not over else "#e377c2",
                                   ec="k", lw=0.5))
    free = [i for i in range(len(f.x)) if i not in set(f.members)]
    if free:
        sv.scatter(f.x[free], np.full(len(free), 0.5 * H), s=4, c=[COLOURS[Mode(int(f.mode[i]))] for i in free])
    sv.set_xlim(-5, p.arena_w_cm + 5)
    sv.set_ylim(-3 * L, max(3 * L, (f.row_size // max(f.lines, 1) + 1) * H))
    sv.set_aspect("equal")
    sv.set_yticks([])
    sv.set_xlabel("side view along the structure (cm)")
    fig.tight_layout()
    return fig


def _atomic_target(path: Path) -> Path:
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=path.suffix, dir=path.parent)
    os.close(fd)
    return Path(tmp)


def write_video(frames: list, p: Params, path: str | os.PathLike, fps: int = 10, progress=lambda it, total: it) -> Path:
    """MP4 (imageio-ffmpeg) or GIF (imageio) of the frames; written atomically."""
    path = Path(path)
    ext = path.suffix.lower()
    if ext not in (".mp4", ".gif"):
        raise InputError(f"--video {path}: use a .mp4 or .gif file name")
    try:
        import imageio.v2 as imageio
    except ImportError as exc:  # pragma: no cover - video extra missing
        raise InputError(f"--video needs imageio (pip install 'voidcross[video]'): {exc}") from None
    import matplotlib.pyplot as plt

    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = _atomic_target(path)
    fig = None
    try:
        kw = {"fps": fps, "macro_block_size": 1} if ext == ".mp4" else {"duration": 1.0 / fps, "loop": 0}
        with imageio.get_writer(tmp, format="FFMPEG" if ext == ".mp4" else "GIF", **kw) as w:
            for f in progress(frames, len(frames)):
                fig = draw(f, p, fig)
                fig.canvas.draw()
                img = np.asarray(fig.canvas.buffer_rgba())[:, :, :3]
                w.append_data(img)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    finally:
        if fig is not None:
            plt.close(fig)
        if tmp.exists():
            tmp.unlink()
    return path


def write_snapshots(frames: list, p: Params, directory: str | os.PathLike, count: int = 6,
                    progress=lambda it, total: it) -> list[Path]:
    """PNG snapshots at ``count`` evenly spaced times (first and last included)."""
    import matplotlib.pyplot as plt

    d = Path(directory)
    d.mkdir(parents=True, exist_ok=True)
    idx = sorted(set(np.linspace(0, len(frames) - 1, min(count, len(frames))).round().astype(int)))
    out = []
    fig = None
    for i in progress(idx, len(idx)):
        f = frames[i]
        fig = draw(f, p, fig)
        target = d / f"t{f.t_s:09.2f}s.png"
        tmp = _atomic_target(target)
        fig.savefig(tmp, format="png")
        os.chmod(tmp, 0o644)
        os.replace(tmp, target)
        out.append(target)
    if fig is not None:
        plt.close(fig)
    return out
