"""Exploded views (cubot_cad.outputs.exploded): every part is in the assembly plan, the steps' parts are
moved clear of each other, stacks open in their own order, the callouts carry the step numbers
of docs/assembly.md, and the docs' images and step tables are current."""

from __future__ import annotations

import itertools
import re
import types
from pathlib import Path

import numpy as np
import pytest

from cubot_cad.outputs.exploded import (
    DOC_ROBOTS,
    VIEWS,
    doc_block,
    exploded_items,
    exploded_labels,
    exploded_view,
    plan,
)

DOCS = Path(__file__).resolve().parents[2] / "docs"


def _bbox(shape):
    b = shape.BoundingBox()
    return np.array([b.xmin, b.ymin, b.zmin]), np.array([b.xmax, b.ymax, b.zmax])


@pytest.mark.parametrize("name", DOC_ROBOTS)
def test_every_part_is_in_a_step_and_steps_come_apart(robots, name):
    robot = robots[name]
    items = exploded_items(robot)
    printed = [i for i in items if i.name in {p.part.name for p in robot.placed}]
    assert len(printed) >= len(robot.placed)
    assert sorted(p.part.name for p in robot.placed) == sorted(
        i.name for i in items if i.step.parts is not None and i.step.parts(i.name, i.role))
    # parts of different steps end up clear of each other (their bounding boxes do not overlap)
    boxes = [(i, _bbox(i.shape)) for i in items]
    for (a, (alo, ahi)), (b, (blo, bhi)) in itertools.combinations(boxes, 2):
        if a.step is b.step:
            continue
        assert np.any(np.minimum(ahi, bhi) - np.maximum(alo, blo) <= 0), \
            f"{a.name} (step {a.step.number}) and {b.name} (step {b.step.number}) still overlap"
    # and every part but the body moved
    assert all(np.linalg.norm(i.offset_mm) > 10 for i in items if i.step is not plan(robot)[0])


def test_stacks_open_in_their_order(robots):
    """CuBot's front block at y = -20: plates a, b, c, d keep their order outward along +x, and the
    3 mm pitch between neighbours is spread to (1 + spread) x 3 mm; the pins stay in plate b."""
    items = [i for i in exploded_items(robots["cubot"]) if i.step.number == "5"]
    block = [i for i in items if abs(_bbox(i.shape)[0][1] + _bbox(i.shape)[1][1] + 40) < 20]
    inner = {}
    for i in block:
        m = re.match(r"pinset_([a-e])_", i.name)
        inner.setdefault(m.group(1), []).append(_bbox(i.shape)[0][0])
    a, b, c, d = (min(inner[k]) for k in "abcd")
    assert a < b < c < d
    spread = plan(robots["cubot"])[6].spread
    assert b - a == pytest.approx(3.0 * (1 + spread), abs=0.05)
    assert d - c == pytest.approx(3.0 * (1 + spread), abs=0.05)
    assert min(inner["e"]) == pytest.approx(b, abs=0.05)  # pin heads in plate b's counterbores
    # lifted out of the open top: the whole stack is above the body
    body_top = _bbox(robots["cubot"].body.solid)[1][2]
    assert min(_bbox(i.shape)[0][2] for i in block) > body_top


@pytest.mark.parametrize("name", DOC_ROBOTS)
def test_callouts_are_the_steps(robots, name):
    robot = robots[name]
    items = exploded_items(robot)
    labels = exploded_labels(robot, items, *VIEWS[name])
    texts = [lab.text for lab in labels]
    for st in plan(robot):
        if st.letters:
            assert {f"{st.number.split()[0]}{x}" for x in "abcde"} <= set(texts), st.number
        else:
            assert st.number in texts
    assert len(texts) == len(set(texts))


def test_a_part_no_step_selects_is_an_error(robots):
    cubot = robots["cubot"]
    extra = types.SimpleNamespace(part=types.SimpleNamespace(name="mystery_bracket"), role="structure",
                                  shape=cubot.placed[0].shape)
    fake = types.SimpleNamespace(name="cubot", placed=[*cubot.placed, extra], components=cubot.components)
    with pytest.raises(ValueError, match="mystery_bracket"):
        exploded_items(fake)


def test_exploded_view_png(robots, tmp_path):
    from PIL import Image

    from cubot_cad.robots.base import role_colour

    p = exploded_view(robots["octbot"], tmp_path / "octbot-exploded.png")
    im = np.asarray(Image.open(p).convert("RGB")).astype(int)
    assert im.shape == (1200, 1600, 3)
    # the ring (orange), housing (blue) and fingers (yellow) all show, lit: match by hue direction
    for role in ("ring", "housing", "finger"):
        want = np.asarray(role_colour(role))
        v = im / np.maximum(np.linalg.norm(im, axis=2, keepdims=True), 1)
        cos = v @ (want / np.linalg.norm(want))
        assert int((cos > 0.995).sum()) > 2000, role
    # callout boxes (pale yellow fill, 255, 255, 215) are drawn
    assert int(np.all(im == [255, 255, 215], axis=2).sum()) > 6 * 400


@pytest.mark.parametrize("name", DOC_ROBOTS)
def test_assembly_guide_shows_the_current_plan(robots, name):
    from PIL import Image

    md = (DOCS / "assembly.md").read_text(encoding="utf-8")
    assert doc_block(robots[name]) in md, "stale: run `python -m cubot_cad.outputs.exploded`"
    img = DOCS / "img" / f"{name}-exploded.png"
    assert Image.open(img).size == (1600, 1200)
