"""The video and snapshots of a run (issue 17): frame delays right, named states that agree
with the legend, event captions, snapshots where the run's events are."""

from __future__ import annotations

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
