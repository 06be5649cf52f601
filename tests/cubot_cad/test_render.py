"""Renders: a z-buffered offscreen renderer (VTK), big enough to show the connectors.

What is checked on pixels: the depth order (a box in front occludes one behind whatever order
they are given in: the depth-sorted matplotlib renderer this replaced got that wrong), that a
robot fills a good part of the frame, and that each connector's role colour reaches the image.
"""

from __future__ import annotations

import numpy as np
import pytest

from cubot_cad.outputs.render import (
    DEFAULT_SIZE_PX,
    camera_axes,
    render_image,
    render_robot,
    robot_groups,
)

pytest.importorskip("vtk")

RED, BLUE = (1.0, 0.0, 0.0), (0.0, 0.0, 1.0)


def _boxes():
    from cubot_cad.shapes import box

    # camera on +x (elev 0, azim 0): the red box (x 20..30) is in front of the big blue one (x 0..10)
    front = box(20, 30, -5, 5, -5, 5)
    back = box(0, 10, -20, 20, -20, 20)
    return front, back


def _count(img, rgb, tol=3):
    want = np.round(np.asarray(rgb) * 255)
    return int(np.all(np.abs(img.astype(int) - want) <= tol, axis=2).sum())


@pytest.mark.parametrize("order", ["front first", "back first"])
def test_front_box_occludes_the_one_behind(order):
    front, back = _boxes()
    groups = [([front], RED), ([back], BLUE)]
    if order == "back first":
        groups = groups[::-1]
    img = render_image(groups, elev=0, azim=0, size_px=(400, 300), shading="flat", edges=False)
    h, w, _ = img.shape
    assert (h, w) == (300, 400)
    centre = img[h // 2 - 5:h // 2 + 5, w // 2 - 5:w // 2 + 5].reshape(-1, 3)
    assert np.all(centre == [255, 0, 0]), "the front box must cover the centre"
    # the back box shows round it, and the front one covers about its projected share (10/40)^2
    red, blue = _count(img, RED), _count(img, BLUE)
    assert blue > 5 * red > 0
    assert red / (red + blue) == pytest.approx(100 / 1600, rel=0.15)


def test_seen_from_behind_the_big_box_hides_the_small_one():
    front, back = _boxes()
    img = render_image([([front], RED), ([back], BLUE)], elev=0, azim=180, size_px=(400, 300), shading="flat",
                       edges=False)
    assert _count(img, RED) == 0 and _count(img, BLUE) > 0


def test_lit_render_keeps_the_depth_order_and_antialiases():
    front, back = _boxes()
    img = render_image([([back], BLUE), ([front], RED)], elev=0, azim=0, size_px=(400, 300))
    c = img[150, 200].astype(int)
    assert c[0] > 100 and c[0] > 3 * c[2], f"centre pixel {c} is not the red front box"
    # supersampled: the silhouette has in-between shades, not just box and background colours
    row = img[150].astype(int)
    assert len({tuple(p) for p in row}) > 4


def test_camera_axes_are_orthonormal_and_match_matplotlib():
    eye, right, up = camera_axes(22, -58)
    m = np.array([eye, right, up])
    assert np.allclose(m @ m.T, np.eye(3), atol=1e-12)
    assert eye[0] > 0 and eye[1] < 0 and eye[2] > 0  # front-right, from above
    assert up[2] > 0


def test_robot_fills_the_frame_and_every_connector_colour_shows(robots):
    from cubot_cad.robots.base import role_colour

    cubot = robots["cubot"]
    img = render_image(robot_groups(cubot), shading="flat", edges=False)
    assert img.shape[:2] == (DEFAULT_SIZE_PX[1], DEFAULT_SIZE_PX[0])
    background = np.all(img == 255, axis=2)
    assert 1 - background.mean() > 0.35, "the robot fills too little of the frame"
    # front-right from above: the grooved pins (orange), the right rail (green), the cover, the
    # locking key; the thresholds are a third of what the 1600 x 1200 frame shows (measured)
    for role, at_least in (("pin", 10000), ("rail", 50000), ("cover", 100000), ("locking_key", 1000),
                           ("body", 200000)):
        n = _count(img, role_colour(role))
        assert n >= at_least, f"{role}: only {n} px of its colour"
    # rear-left from below: the twist key, its bearing ring, the caster seats, the latch plates
    under = render_image(robot_groups(cubot), elev=-30, azim=150, shading="flat", edges=False)
    for role, at_least in (("cross_key", 8000), ("key_bearing", 8000), ("caster_seat", 8000), ("latchset", 2500)):
        n = _count(under, role_colour(role))
        assert n >= at_least, f"{role} from below: only {n} px"


def test_render_robot_writes_a_large_png(robots, tmp_path):
    from PIL import Image

    p = render_robot(robots["octbot"], tmp_path / "octbot.png")
    im = np.asarray(Image.open(p).convert("RGB"))
    assert im.shape == (1200, 1600, 3)
    assert (1 - np.all(im >= 250, axis=2).mean()) > 0.2
    assert not list(tmp_path.glob(".*")), "no temporary file left behind"


def test_empty_scene_is_an_error():
    with pytest.raises(ValueError, match="nothing to render"):
        render_image([([np.zeros((0, 3, 3))], RED)], size_px=(100, 80))
