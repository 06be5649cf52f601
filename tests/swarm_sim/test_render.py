"""The video and snapshots of a run (issue 17): frame delays right, named states that agree
with the legend, event captions, snapshots where the run's events are, frames drawn fast and
equal to what the figure saves, progress while rendering."""

from __future__ import annotations

import dataclasses
import io
import time

import numpy as np
import pytest
from PIL import Image

from swarm_sim import render as R
from swarm_sim.runner import resolve_params, simulate
from swarm_sim.state import Mode


@pytest.fixture(scope="module")
def recorded():
    p = resolve_params("case-d", 9, 2, "thesis")
    rec = R.Recorder(every_s=2.0)
    _, res = simulate(p, 3, on_step=rec)
    assert res.success
    return p, rec, res


def test_gif_frames_last_one_over_fps_seconds(recorded, tmp_path):
    p, rec, _ = recorded
    out = R.write_video(rec.frames[:6], p, tmp_path / "run.gif", fps=5)
    with Image.open(out) as im:
        delays = []
        for k in range(im.n_frames):
            im.seek(k)
            delays.append(im.info["duration"])
    assert delays and all(d == pytest.approx(200, abs=10) for d in delays)  # ms


def test_header_counts_the_modes_by_the_legends_names():
    mode = np.array([Mode.STOPPED] * 7 + [Mode.TARGET] * 2, dtype=np.int8)
    text = R.header_counts(mode)
    assert text == "target search (-2) 2   stopped 7"  # a finished run: no "retreat" where none retreated
    assert all(name in R.MODE_NAMES.values() for name in ("stopped", "target search (-2)"))


def test_every_event_the_run_had_is_captioned_on_its_frame(recorded):
    _, rec, _ = recorded
    kinds = {e[1] for f in rec.frames for e in f.events}
    assert {"seed", "far_ledge", "release_front", "target_found"} <= kinds
    seeded = next(f for f in rec.frames if any(e[1] == "seed" for e in f.events))
    assert any("found the edge" in c for c in seeded.captions)
    assert R.caption((1.0, "retreat", 0, {"why": "no-robots"})) == "retreat: no-robots"
    assert R.caption((1.0, "advance", 0, {})) is None


def test_snapshots_are_taken_at_the_events_first_and_last_included(recorded):
    _, rec, _ = recorded
    idx = R.snapshot_frames(rec.frames, 6)
    assert idx[0] == 0 and idx[-1] == len(rec.frames) - 1 and len(idx) == 6
    seed_frame = next(i for i, f in enumerate(rec.frames) if any(e[1] == "seed" for e in f.events))
    land_frame = next(i for i, f in enumerate(rec.frames) if any(e[1] == "far_ledge" for e in f.events))
    assert seed_frame in idx and land_frame in idx
    assert R.snapshot_frames(rec.frames, 2) == [0, len(rec.frames) - 1]
    assert R.snapshot_frames([], 6) == []


def test_a_snapshot_is_150_dpi_with_the_caption_drawn(recorded, tmp_path):
    p, rec, _ = recorded
    files = R.write_snapshots(rec.frames, p, tmp_path, count=3)
    with Image.open(files[0]) as im:
        assert im.size[0] >= 1400  # 10 in at 150 dpi
        assert round(im.info["dpi"][0]) == 150


def _saved(f, p) -> np.ndarray:
    """What ``savefig`` writes for the state ``f`` from a fresh figure (100 dpi, RGBA)."""
    r = R.draw(f, p)
    try:
        buf = io.BytesIO()
        r.fig.savefig(buf, format="png", dpi=100)
    finally:
        r.close()
    with Image.open(buf) as im:
        return np.asarray(im.convert("RGBA"))


def _assert_same_picture(got: np.ndarray, want: np.ndarray, what: str) -> None:
    assert got.shape == want.shape, what
    diff = np.abs(got.astype(np.int16) - want.astype(np.int16)).max(axis=2)
    # Agg draws the same pixels either way; allow a few rounding-level pixels, no shifted layout
    assert diff.max() <= 2 and (diff > 0).mean() < 1e-4, f"{what}: {(diff > 0).sum()} pixels differ by <= {diff.max()}"


def test_a_fast_frame_is_the_frame_the_figure_saves(recorded):
    """The video's frames (static parts drawn once, moving parts over them) are the pixels a
    fresh figure's ``savefig`` gives for the same state, also after the side view grows
    (layered members), with a robot at the frame's edge, and with failed robots' rims."""
    p, rec, _ = recorded
    frames = rec.frames
    f = next(f for f in frames if sum(i >= 0 for i in f.members) >= 3)
    stacked = f.layer.copy()
    stacked[[i for i in f.members if i >= 0][:2]] = 3
    x = f.x.copy()
    x[0] = 0.5  # against the arena wall, near the axes' frame
    cases = [("first", frames[0]), ("second", frames[1]), ("assembling", f),
             ("layered", dataclasses.replace(f, layer=stacked)), ("at the edge", dataclasses.replace(f, x=x)),
             ("failed", dataclasses.replace(f, failed=np.arange(len(f.x)) % 3 == 0)),
             ("after the rims", frames[-2]), ("last", frames[-1])]
    rend = R.Renderer(p)
    try:
        for name, fr in cases:
            _assert_same_picture(rend.frame_rgba(fr), _saved(fr, p), name)
    finally:
        rend.close()


def test_mp4_has_one_frame_per_recorded_frame_at_fps(recorded, tmp_path):
    import imageio.v2 as imageio

    p, rec, _ = recorded
    frames = rec.frames[:12]
    out = R.write_video(frames, p, tmp_path / "run.mp4", fps=8)
    reader = imageio.get_reader(out, format="FFMPEG")
    try:
        meta = reader.get_meta_data()
        assert reader.count_frames() == len(frames)
        assert meta["fps"] == pytest.approx(8)
        assert tuple(meta["size"]) == (1000, 760)  # 10 x 7.6 in at 100 dpi
    finally:
        reader.close()


def test_gif_has_every_frame_with_its_delay_and_the_rendered_picture(recorded, tmp_path):
    p, rec, _ = recorded
    frames = rec.frames[:8]
    out = R.write_video(frames, p, tmp_path / "run.gif", fps=10)
    with Image.open(out) as im:
        assert im.n_frames == len(frames)  # the clock changes: no two frames merged
        im.seek(3)
        assert im.info["duration"] == 100  # ms
        got = np.asarray(im.convert("RGB")).astype(np.int16)
    want = _saved(frames[3], p)[:, :, :3].astype(np.int16)
    # the GIF's palette (256 colours) is Pillow's median cut of the frame: nearly every pixel exact
    assert got.shape == want.shape and (np.abs(got - want).max(axis=2) > 8).mean() < 0.01


def test_run_video_reports_progress_and_its_time_off_a_terminal(cli, tmp_path):
    """stderr is not a terminal under pytest: a first line, then (at the end) how long it took."""
    res = cli("sim", "run", "--preset", "case-c", "--robots", "3", "--void-width", "1", "--seed", "2",
              "--limits", "thesis", "--max-time", "20", "--frame-every", "5", "--video", "run.mp4",
              "--out", str(tmp_path))
    assert res.code == 0, res.err
    lines = [ln for ln in res.err.splitlines() if ln.startswith("rendering video")]
    assert lines[0].startswith("rendering video: 5 frames -> "), res.err
    assert " frames in " in lines[-1] and lines[-1].endswith(str(tmp_path / "run.mp4")), res.err


@pytest.mark.bench
@pytest.mark.parametrize("ext", ["mp4", "gif"])
def test_bench_video_fast_path_against_the_full_draw(ext, tmp_path, capsys):
    """``make bench``: the case-D run of the issue (9 robots, 3-wide void, seed 1, a frame every
    0.5 s) rendered by the old path (a full draw with the layout engine per frame) and the
    fast one, in one session; prints the ratio (no timing is asserted)."""
    p = resolve_params("case-d", 9, 3, "derived")
    rec = R.Recorder(every_s=0.5)
    simulate(p, 1, on_step=rec)
    wall = {}
    for fast in (False, True):
        t0 = time.perf_counter()
        R.write_video(rec.frames, p, tmp_path / f"{fast}.{ext}", fast=fast)
        wall[fast] = time.perf_counter() - t0
    with capsys.disabled():
        print(f"\n{ext}: {len(rec.frames)} frames; full draw {wall[False]:.1f} s, fast {wall[True]:.1f} s: "
              f"{wall[False] / wall[True]:.2f}x")
